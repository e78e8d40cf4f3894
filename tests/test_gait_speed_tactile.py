"""The compiled tactile image equals the NumPy reference (:meth:`TactileArray.sphere_images`).

:func:`robots.sensors.tactile_kernel.sphere_image_add` repeats the reference's operations in
its order (NumPy's pairwise sum, BLAS ``dgemm`` through ``np.dot``), so on this machine the
images are equal to the bit; the assertion allows 1e-12 relative to the peak (another BLAS
could round the blur differently).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from robots.sensors import TactileArray
from robots.sensors.tactile_kernel import pairwise_sum, sphere_image_add


def _compiled(arr: TactileArray, centre, radius: float, force: float) -> np.ndarray:
    img = np.zeros((arr.rows, arr.cols))
    sphere_image_add(img, centre[0], centre[1], radius, force, *arr.kernel_args)
    return img


def _assert_same(got: np.ndarray, ref: np.ndarray) -> None:
    scale = max(float(np.abs(ref).max()), 1.0)
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12 * scale)


ARRAYS = [TactileArray(), TactileArray(rows=5, cols=7, oversample=4, spread=0.0, threshold=0.0)]


@pytest.mark.parametrize("arr", ARRAYS, ids=["default", "5x7-os4-no-spread"])
@given(
    u=st.floats(-0.015, 0.015),
    v=st.floats(-0.015, 0.015),
    radius=st.sampled_from([1e-3, 2e-3, 0.01, 0.05, 1.0]) | st.floats(1e-4, 2.0),
    force=st.just(0.0) | st.floats(1e-9, 5.0),
)
def test_sphere_image_equals_the_reference(arr, u, v, radius, force):
    ref = arr.sphere_images(np.array([u, v]), radius, force)
    _assert_same(_compiled(arr, (u, v), radius, force), ref)


@pytest.mark.parametrize(
    "u, v, radius, force",
    [
        (0.0, 0.0, 0.05, 0.0),  # no contact: zero image
        (0.0, 0.0, 1e-3, 1e-12),  # contact smaller than a sub-cell: F in the nearest one
        (3e-4, -2e-4, 1e-4, 1e-9),  # the same off-centre
        (0.05, 0.0, 0.05, 0.3),  # centre off the pad: a clipped blob or nothing
        (0.0101, 0.0, 0.05, 0.3),  # at the pad's edge
        (0.0, 0.0, 1.0, 2.0),  # flat piece: wide contact
    ],
)
def test_sphere_image_edge_cases(u, v, radius, force):
    arr = TactileArray()
    ref = arr.sphere_images(np.array([u, v]), radius, force)
    got = _compiled(arr, (u, v), radius, force)
    _assert_same(got, ref)
    if force == 0.0:
        assert not got.any()


def test_the_kernel_adds_to_the_image():
    """Two touches: the sum of the two thresholded images (as the simulator's pad)."""
    arr = TactileArray()
    img = _compiled(arr, (0.002, 0.0), 0.05, 0.3)
    sphere_image_add(img, -0.004, 0.0, 1e-3, 0.1, *arr.kernel_args)
    ref = arr.sphere_images(np.array([0.002, 0.0]), 0.05, 0.3)
    ref += arr.sphere_images(np.array([-0.004, 0.0]), 1e-3, 0.1)
    _assert_same(img, ref)


@given(n=st.integers(0, 3000), seed=st.integers(0, 2**31 - 1))
def test_pairwise_sum_is_numpys(n, seed):
    a = np.random.default_rng(seed).standard_normal(n) * 1e3
    assert pairwise_sum(a, 0, n) + 0.0 == np.add.reduce(a) + 0.0
