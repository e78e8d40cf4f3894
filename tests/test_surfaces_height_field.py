"""Tests of height-field surfaces and their traced/estimated surfaces (§3.2.1)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.geometry import surfaces as S

X = np.linspace(-1, 1, 81)
GX, GY = np.meshgrid(X, X, indexing="ij")


def sphere_cap(r):
    return np.sqrt(r**2 - GX**2 - GY**2)


@settings(max_examples=10, deadline=None)
@given(r=st.floats(2.0, 20.0))
def test_height_field_of_sphere_cap_matches_sphere(r):
    hf = S.HeightField(X, X, sphere_cap(r))
    u, v = np.array([0.1, -0.4, 0.5]), np.array([0.3, 0.2, -0.6])
    k1, k2 = hf.principal_curvatures(u, v)
    np.testing.assert_allclose(k1, 1 / r, rtol=1e-4)
    np.testing.assert_allclose(k2, 1 / r, rtol=1e-4)
    np.testing.assert_allclose(
        hf.curvature_matrix(u, v), np.broadcast_to(np.eye(2) / r, (3, 2, 2)), atol=1e-4 / r
    )
    n = hf.normal(u, v)
    p = hf.point(u, v)
    np.testing.assert_allclose(n, p / r, atol=1e-6)  # normal of a sphere = radial


def test_grid_curvatures_and_monge_forms_agree_with_parametric_forms():
    # a ridge as a height field vs. the swept parametric ridge
    z = 0.3 * np.exp(-(GX**2) / (2 * 0.25**2))
    k1, k2 = S.grid_principal_curvatures(X, X, z)
    ridge = S.ridge(0.3, 0.25)
    k1p, k2p = ridge.principal_curvatures(X[10:-10], 0.0)
    np.testing.assert_allclose(k1[10:-10, 40], k1p, atol=2e-2 * np.abs(k1p).max())
    np.testing.assert_allclose(k2[10:-10, 40], 0.0, atol=1e-9)
    hf = S.HeightField(X, X, z)
    g = hf.evaluate(X[10:-10], 0.2)
    # cubic-spline second derivatives are accurate to about (h / w)^2 = 1 %
    np.testing.assert_allclose(
        g.curvature_matrix, ridge.curvature_matrix(X[10:-10], 0.2), atol=1e-2 * np.abs(k1p).max()
    )
    np.testing.assert_allclose(g.torsion, 0.0, atol=1e-6)


def test_non_orthogonal_height_field_forms_are_consistent():
    hf = S.HeightField(X, X, 0.4 * GX * GY + 0.2 * GX**2)
    g = hf.evaluate(0.3, 0.4)
    frame = g.gauss_frame
    np.testing.assert_allclose(frame.T @ frame, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(g.curvature_matrix, g.curvature_matrix.T, atol=1e-9)
    k1, k2 = hf.principal_curvatures(0.3, 0.4)
    ev = np.linalg.eigvalsh(g.curvature_matrix)
    np.testing.assert_allclose(sorted([k1, k2]), ev, rtol=1e-8)


def test_traced_surface_of_a_sphere_is_the_parallel_sphere():
    r, rf = 3.0, 0.2
    off = S.offset_surfaces(X, X, sphere_cap(r), rf)
    inside = GX**2 + GY**2 < 0.5
    # a ball sampled on the grid misses the true maximum by about (1/rf + 1/r) h^2 / 4,
    # more on slopes (the cap's curvature in the offset plane grows): allow a factor 2
    tol = (1 / rf + 1 / r) * (X[1] - X[0]) ** 2 / 2
    np.testing.assert_allclose(
        off.traced[inside], np.sqrt((r + rf) ** 2 - GX**2 - GY**2)[inside], atol=tol
    )
    np.testing.assert_allclose(off.estimated[inside], sphere_cap(r)[inside], atol=tol)
    assert not off.unobservable.any() and not off.interference.any()


def test_narrow_groove_is_unobservable_with_an_interference_curve():
    x = np.linspace(-1, 1, 201)
    gx, _ = np.meshgrid(x, x, indexing="ij")
    z = -0.3 * np.exp(-(gx**2) / (2 * 0.05**2))
    off = S.offset_surfaces(x, x, z, 0.2)
    rows = np.unique(np.nonzero(off.unobservable)[0])
    assert x[rows].min() < -0.05 and x[rows].max() > 0.05  # the groove's bottom is hidden
    assert np.all(np.abs(x[np.nonzero(off.interference)[0]]) < 0.02)  # crease above centre
    assert np.all(off.estimated >= z - 1e-12)  # closing is extensive


@pytest.mark.parametrize(
    ("args", "match"),
    [
        ((X, X, np.zeros((81, 80))), "shape"),
        ((X[::-1], X, np.zeros((81, 81))), "increasing"),
        ((X, X, np.full((81, 81), np.nan)), "finite"),
        ((X[:3], X[:3], np.zeros((3, 3))), "at least"),
    ],
)
def test_bad_grids(args, match):
    with pytest.raises(InvalidParameter, match=match):
        S.HeightField(*args)


def test_offsets_reject_a_tip_smaller_than_the_grid():
    with pytest.raises(InvalidParameter, match="grid step"):
        S.offset_surfaces(X, X, np.zeros((81, 81)), 0.001)
