"""A sphere wider than a groove touches both rims: the simulator's second contact point.

Closed forms for a Gaussian ravine ``Z(s) = -h exp(-s²/2w²)`` across ``x``: a sphere of
radius ``r`` centred over the ravine rests on the two rims at ``±s`` where the normal at the
foot passes through the centre, ``s = (c_z - Z(s)) Z'(s)``, and ``s² + (c_z - Z(s))² = r²``;
a frictionless ball of mass ``m`` resting there carries ``N = m g / (2 cos α)`` on each rim,
``cos α = (c_z - Z(s)) / r``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from planner.errors import InvalidParameter
from planner.sim.spatial import Plate, PlateFeature, SpatialWorld
from planner.sim.spatial.closest import PlacedSurface
from planner.sim.spatial.kernel import pack_plate, plate_foot, plate_other_feet
from planner.sim.spatial.scenes import centre_path_error, ridge_slide_scene

H, W, R = 2e-3, 2e-3, 8e-3  # feature_plate's ravine, the 3GM's tip


def _Z(s):
    return -H * math.exp(-s * s / (2 * W * W))


def _dZ(s):
    return H * s / (W * W) * math.exp(-s * s / (2 * W * W))


def _bridge() -> tuple[float, float]:
    """``(s, c_z)`` of the sphere resting on both rims (the closed form above)."""

    def cz(s):  # the centre height whose foot normal at s passes through x = 0
        return _Z(s) + s / _dZ(s)

    s = brentq(lambda s: s * s + (cz(s) - _Z(s)) ** 2 - R * R, 0.5 * W, 4 * W, xtol=1e-15)
    return s, cz(s)


def _ravine_plate() -> Plate:
    return Plate((PlateFeature("ravine", H, W, position=(0.0, 0.0), across=0.0),))


def test_the_other_rim_is_found_exactly_where_the_sphere_bridges():
    s, cz = _bridge()
    F, P = pack_plate(_ravine_plate())
    out = np.empty((3, 7))
    x, y, *_ = plate_foot(F, P, 0.0, 0.0, 0.0, cz, -s - 1e-4, 0.0)  # the left rim's foot
    assert x == pytest.approx(-s, abs=1e-12)
    n = plate_other_feet(F, P, 0.0, 0.0, 0.0, cz, R, 1e-5, x, y, out)
    assert n == 1
    assert out[0, 0] == pytest.approx(s, abs=1e-12) and abs(out[0, 1]) < 1e-12
    assert out[0, 2] == pytest.approx(_Z(s), abs=1e-15)
    assert out[0, 6] == pytest.approx(R, abs=1e-12)  # its distance: touching
    nz = 1.0 / math.hypot(1.0, _dZ(s))
    np.testing.assert_allclose(out[0, 3:6], [-_dZ(s) * nz, 0.0, nz], atol=1e-12)


def test_a_sphere_resting_on_one_rim_has_no_other_foot():
    """Off the centre line the sphere rests on the near rim alone (the dilation's maximum is
    attained once): the far rim's local foot is farther than the reach."""
    plate = _ravine_plate()
    F, P = pack_plate(plate)
    x0 = 1e-3
    s = np.linspace(x0 - R, x0 + R, 400001)
    cz = float(np.max(plate.height(s, 0.0) + np.sqrt(np.maximum(R * R - (s - x0) ** 2, 0))))
    d = np.hypot(s - x0, plate.height(s, 0.0) - cz)
    left = s < 0
    assert d[left].min() - R > 1e-4  # brute force: the far rim stays clear by 0.1 mm
    k = int(np.argmin(d))
    x, y, *_ = plate_foot(F, P, 0.0, x0, 0.0, cz, s[k], 0.0)
    assert plate_other_feet(F, P, 0.0, x0, 0.0, cz, R, 1e-5, x, y, np.empty((3, 7))) == 0


def test_other_feet_are_placed_in_the_world_frame():
    """PlacedSurface.other_feet maps the plate-frame search through the plate's pose."""
    s, cz = _bridge()
    c, sn = math.cos(0.7), math.sin(0.7)
    T = np.eye(4)
    T[:3, :3] = [[c, -sn, 0.0], [sn, c, 0.0], [0.0, 0.0, 1.0]]
    T[:3, 3] = [0.1, -0.2, 0.05]
    placed = PlacedSurface(_ravine_plate(), T)
    centre = T[:3, :3] @ np.array([0.0, 0.0, cz]) + T[:3, 3]
    primary = placed.foot(centre, (-s - 1e-4, 0.0))
    (other,) = placed.other_feet(centre, R, 1e-5, primary)
    want = T[:3, :3] @ np.array([s, 0.0, _Z(s)]) + T[:3, 3]
    np.testing.assert_allclose(other.point, want, atol=1e-12)
    assert other.distance == pytest.approx(R, abs=1e-12)
    local = placed.local_foot(centre, other.hint)
    np.testing.assert_allclose(local.point, want, atol=1e-12)


def test_a_frictionless_ball_rests_on_both_rims_with_the_closed_form_forces():
    s, cz = _bridge()
    m, g = 0.05, 9.81
    world = SpatialWorld(dt=1e-3, all_contacts=True)
    world.add_surface(_ravine_plate(), friction=0.0, name="plate")
    ball = world.add_sphere(R, m, (0.0, 0.0, cz + 1e-9))
    for _ in range(200):
        world.step()
    assert world.pose(ball)[2] == pytest.approx(cz, abs=1e-12)
    assert abs(world.pose(ball)[0]) < 1e-12
    forces = sorted((c.point[0], c.normal_force) for c in world.contacts())
    assert len(forces) == 2
    cos_a = (cz - _Z(s)) / R
    for (x, f), side in zip(forces, (-1.0, 1.0), strict=True):
        assert x == pytest.approx(side * s, abs=1e-12)
        assert f == pytest.approx(m * g / (2.0 * cos_a), rel=1e-9)


@pytest.mark.parametrize(("height", "width"), [(2e-3, 2e-3), (3e-3, 1e-3)])
def test_the_3gm_crosses_a_ravine_narrower_than_its_tip_on_the_exact_offset(height, width):
    """The 8 mm tip slides across a ravine it cannot enter: its centre rides the grey dilation
    of the profile (both rims touched at the bottom). With one contact per sphere it sank
    0.87 / 0.92 mm into the far rim here (2026-11-25)."""
    scene = ridge_slide_scene(
        kind="ravine", ridge_height=height, ridge_width=width, all_contacts=True
    )
    log = scene.world.run(scene.duration, scene.controller)
    assert log.status == "ok", log.reason
    err = centre_path_error(scene, log)
    assert err.lost_steps == 0
    assert err.max < 1e-9
    assert (log.contact_count > 1).any()  # the bridge is two contacts


def test_with_one_contact_per_sphere_the_tip_sinks_into_the_far_rim():
    """all_contacts=False (the default, faster): the documented limit, measured."""
    scene = ridge_slide_scene(kind="ravine", ridge_height=H, ridge_width=W)
    log = scene.world.run(scene.duration, scene.controller)
    deepest = -float(np.min(centre_path_error(scene, log).errors))
    assert 1e-4 < deepest < 2e-3
    assert not (log.contact_count > 1).any()


def test_all_contacts_must_be_a_boolean():
    with pytest.raises(InvalidParameter, match="all_contacts: expected true or false"):
        SpatialWorld(all_contacts="false")


@pytest.mark.parametrize("factor", [1.07, 1.2])
def test_a_tip_wider_than_a_ridge_flank_allows_rides_it_exactly_with_all_contacts(factor):
    """The 3GM ridge slide with a tip beyond the ridge's concave radius: one contact sinks
    into the flank's foot (micrometres, test_sim_spatial_plate_curvature.py); with every
    contact it touches the flank and the plate at once and rides the exact offset."""
    radius = PlateFeature("ridge", 1e-3, 3e-3).concave_radius() * factor
    scene = ridge_slide_scene(tip_radius=radius, travel=0.02, all_contacts=True)
    log = scene.world.run(scene.duration, scene.controller)
    assert -float(np.min(centre_path_error(scene, log).errors)) < 1e-12
