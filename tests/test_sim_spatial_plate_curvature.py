"""PlateFeature.concave_radius / Plate.concave_radius: the widest sphere the one-foot contact
model holds exactly (closed forms of the catalogue's profiles, and the simulator itself)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.sim.spatial.plate import Plate, PlateFeature


@pytest.mark.parametrize(
    ("feature", "expected"),
    [
        (PlateFeature("ravine", 1e-3, 3e-3), 9e-3),  # Z''(0) = h / w^2, flat there
        (PlateFeature("pit", 1e-3, 3e-3), 4.5e-3),  # Z''(0) = 2 h / w^2
        (PlateFeature("wire", 2e-3, rounding=3e-3), 3e-3),  # its fillets' radius
        (PlateFeature("cusp", 1e-3, 3e-3), math.inf),  # convex everywhere
        (PlateFeature("ridge", 1e-9, 3e-3), 9e-6 * math.exp(1.5) / 2e-9),  # (u-1)e^(-u/2), u=3
        (PlateFeature("pit", 1e-3, 3e-3, path=((0.0, 0.0),)), 4.5e-3),  # a one-point path
    ],
    ids=["ravine", "pit", "wire", "cusp", "shallow-ridge", "pit-path"],
)
def test_closed_forms(feature, expected):
    assert feature.concave_radius() == pytest.approx(expected, rel=1e-9)


def _principal_max(plate: Plate, x: float, y: float) -> float:
    """The larger principal curvature of the graph z = h(x, y) at (x, y) [1/m]: eigenvalues
    of I^-1 II with the first and second fundamental forms from central differences."""
    e = 1e-6

    def h(u, v):
        return float(plate.height(np.array([u]), np.array([v]))[0])

    hx = (h(x + e, y) - h(x - e, y)) / (2 * e)
    hy = (h(x, y + e) - h(x, y - e)) / (2 * e)
    hxx = (h(x + e, y) - 2 * h(x, y) + h(x - e, y)) / e**2
    hyy = (h(x, y + e) - 2 * h(x, y) + h(x, y - e)) / e**2
    hxy = (h(x + e, y + e) - h(x + e, y - e) - h(x - e, y + e) + h(x - e, y - e)) / (4 * e**2)
    first = np.array([[1 + hx * hx, hx * hy], [hx * hy, 1 + hy * hy]])
    second = np.array([[hxx, hxy], [hxy, hyy]]) / math.sqrt(1 + hx * hx + hy * hy)
    return float(max(np.linalg.eigvals(np.linalg.solve(first, second)).real))


@settings(max_examples=12, deadline=None)
@given(
    kind=st.sampled_from(["ridge", "ravine", "step", "bump", "pit"]),
    height=st.floats(2e-4, 3e-3),
    width=st.floats(1e-3, 6e-3),
    across=st.floats(-3.0, 3.0),
)
def test_no_point_of_a_feature_curves_more_than_its_radius_allows(kind, height, width, across):
    """The finite-difference principal curvatures over a grid across the feature never exceed
    1 / concave_radius, and the grid's largest comes within 2 % of it."""
    f = PlateFeature(kind, height, width, position=(1e-3, -2e-3), across=across)
    plate = Plate((f,))
    k_max = 1.0 / f.concave_radius()
    c, s = math.cos(across), math.sin(across)
    seen = []
    for t in np.linspace(-5 * width, 5 * width, 401):  # a line across it through its centre
        x, y = 1e-3 + t * c, -2e-3 + t * s
        seen.append(_principal_max(plate, x, y))
    seen = np.array(seen)
    assert seen.max() <= k_max * (1 + 1e-3) + 1e-3
    assert seen.max() >= 0.98 * k_max


def test_the_plate_takes_its_tightest_feature():
    plate = Plate((PlateFeature("ravine", 1e-3, 3e-3), PlateFeature("pit", 1e-3, 3e-3, (0.05, 0))))
    assert plate.concave_radius() == pytest.approx(4.5e-3, rel=1e-9)
    assert Plate(()).concave_radius() == math.inf


@pytest.mark.parametrize(("factor", "exact"), [(0.97, True), (1.07, False)])
def test_the_simulator_holds_spheres_below_it_exactly_and_not_above(factor, exact):
    """The 3GM ridge slide (1 x 3 mm Gaussian ridge, concave radius 20.7 mm): a tip 3 % below
    rides the exact offset surface (1e-12 m), one 7 % above sinks into a flank that its one
    contact point does not see (micrometres)."""
    from planner.sim.spatial.scenes import centre_path_error, ridge_slide_scene

    radius = PlateFeature("ridge", 1e-3, 3e-3).concave_radius() * factor
    scene = ridge_slide_scene(tip_radius=radius, travel=0.02)
    log = scene.world.run(scene.duration, scene.controller)
    deepest = -float(np.min(centre_path_error(scene, log).errors))
    if exact:
        assert deepest < 1e-12
    else:
        assert deepest > 1e-7
