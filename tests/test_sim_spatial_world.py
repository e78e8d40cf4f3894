"""The spatial world with free balls: closed forms of rolling, sliding, bouncing, momentum."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.sim.spatial import Plane, Plate, PlateFeature, SpatialWorld

G = 9.81


def _ball_on_incline(alpha, mu, radius=0.01, mass=0.1, duration=0.5):
    w = SpatialWorld(dt=1e-3)
    w.add_surface(Plane.tilted(alpha), friction=mu, name="incline")
    n = np.array([math.sin(alpha), 0.0, math.cos(alpha)])
    ball = w.add_sphere(radius, mass, n * radius)
    log = w.run(duration)
    down = np.array([math.cos(alpha), 0.0, -math.sin(alpha)])
    s = log.poses[ball][:, :3] @ down
    v = log.velocities[ball][:, :3] @ down
    return w, log, ball, s, v


def _discrete_acceleration(v, dt=1e-3):
    return float(np.mean(np.diff(v[1:]) / dt))


def test_ball_rolls_with_five_sevenths_g_sin_alpha():
    alpha = math.radians(25.0)
    w, log, ball, s, v = _ball_on_incline(alpha, mu=0.5)
    assert _discrete_acceleration(v) == pytest.approx(5 / 7 * G * math.sin(alpha), rel=1e-9)
    # rolling without slipping: the contact point does not slip, s = r * (rotation angle)
    slip = np.linalg.norm(log.slip_velocity[1:, 0], axis=1)
    assert slip.max() <= 1e-12
    omega = log.velocities[ball][:, 4]  # about +y for a ball rolling down +x
    angle = np.concatenate([[0.0], np.cumsum(omega[1:]) * 1e-3])
    np.testing.assert_allclose(s - s[0], 0.01 * angle, rtol=1e-9, atol=1e-15)
    assert np.nanmax(np.abs(log.gap[1:, 0])) <= 1e-12  # no penetration, no hovering
    assert log.status == "ok"


def test_ball_slides_when_friction_is_small():
    alpha, mu = math.radians(30.0), 0.1  # rolling needs mu >= 2/7 tan(alpha) = 0.165
    w, log, ball, s, v = _ball_on_incline(alpha, mu)
    a = _discrete_acceleration(v)
    assert a == pytest.approx(G * (math.sin(alpha) - mu * math.cos(alpha)), rel=1e-9)
    fn = log.normal_force[1:, 0]
    ft = np.linalg.norm(log.tangential_force[1:, 0], axis=1)
    np.testing.assert_allclose(ft, mu * fn, rtol=1e-12)
    assert np.all(np.linalg.norm(log.slip_velocity[2:, 0], axis=1) > 0)


@settings(max_examples=25, deadline=None)
@given(
    alpha=st.floats(math.radians(2), math.radians(60)),
    mu=st.floats(0.0, 1.5),
    radius=st.floats(0.002, 0.1),
    mass=st.floats(0.01, 10.0),
)
def test_incline_acceleration_is_the_closed_form(alpha, mu, radius, mass):
    _, log, _, _, v = _ball_on_incline(alpha, mu, radius, mass, duration=0.05)
    rolling = mu >= 2 / 7 * math.tan(alpha)
    expected = (
        5 / 7 * G * math.sin(alpha) if rolling else G * (math.sin(alpha) - mu * math.cos(alpha))
    )
    assert _discrete_acceleration(v) == pytest.approx(expected, rel=1e-8, abs=1e-10)
    assert np.nanmax(np.abs(log.gap[1:, 0])) <= 1e-6 * radius  # penetration <= 1 um


def test_resting_ball_does_not_creep():
    w = SpatialWorld()
    w.add_surface(Plane(), friction=0.8)
    b = w.add_sphere(0.02, 0.3, (0.1, -0.2, 0.02))
    log = w.run(2.0)
    drift = np.linalg.norm(log.poses[b][:, :3] - [0.1, -0.2, 0.02], axis=1)
    assert drift.max() <= 1e-12
    assert np.linalg.norm(log.slip_velocity[1:, 0], axis=1).max() == 0.0
    assert log.normal_force[1:, 0] == pytest.approx(0.3 * G, rel=1e-12)


@settings(max_examples=20, deadline=None)
@given(
    v=st.lists(st.floats(-2, 2), min_size=3, max_size=3),
    w=st.lists(st.floats(-20, 20), min_size=3, max_size=3),
    mass=st.floats(0.01, 5.0),
)
def test_free_ball_conserves_momentum(v, w, mass):
    world = SpatialWorld(gravity=(0.0, 0.0, 0.0))
    b = world.add_sphere(0.05, mass, (0, 0, 0), velocity=v, angular_velocity=w)
    log = world.run(0.2)
    np.testing.assert_allclose(log.velocities[b], np.tile(np.r_[v, w], (len(log.t), 1)), atol=1e-14)
    x = log.poses[b][:, :3]
    np.testing.assert_allclose(x[-1], 0.2 * np.asarray(v), atol=1e-12)
    q = log.poses[b][:, 3:]
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-14)


@settings(max_examples=20, deadline=None)
@given(
    height=st.floats(0.001, 0.2),
    vx=st.floats(-1.0, 1.0),
    alpha=st.floats(0.0, 0.6),
)
def test_frictionless_bounce_never_gains_energy(height, vx, alpha):
    w = SpatialWorld()
    w.add_surface(Plane.tilted(alpha), friction=0.0)
    n = np.array([math.sin(alpha), 0.0, math.cos(alpha)])
    r, m = 0.01, 0.2
    b = w.add_sphere(r, m, n * (r + height), velocity=(vx, 0.3, 0.0))
    log = w.run(0.4)
    x, v = log.poses[b][:, :3], log.velocities[b][:, :3]
    energy = 0.5 * m * np.sum(v**2, axis=1) + m * G * x[:, 2]
    assert np.all(np.diff(energy) <= 1e-12 * energy.max() + 1e-15)
    assert np.nanmin(log.gap) >= -1e-12


def test_ball_over_a_ridge_plate_stays_on_the_offset_surface():
    plate = Plate((PlateFeature("ridge", 2e-3, 4e-3, position=(0.02, 0.0)),))
    w = SpatialWorld()
    w.add_surface(plate, friction=1.0, name="plate")
    b = w.add_sphere(0.01, 0.1, (-0.01, 0.0, 0.01), velocity=(0.5, 0.0, 0.0))
    log = w.run(0.15)
    on = log.normal_force[:, 0] > 0
    assert on.sum() > 50
    assert np.nanmax(np.abs(log.gap[on, 0])) <= 1e-12
    assert log.poses[b][-1, 0] > 0.04  # it crossed the ridge


def test_bad_input_is_rejected():
    w = SpatialWorld()
    w.add_surface(Plane(), name="floor")
    with pytest.raises(InvalidParameter, match="mass"):
        w.add_sphere(0.01, -1.0, (0, 0, 0.1))
    with pytest.raises(InvalidParameter, match="penetration"):
        w.add_sphere(0.01, 1.0, (0, 0, 0.005))
    with pytest.raises(InvalidParameter, match="friction"):
        w.add_surface(Plane(), friction=-0.1)
    with pytest.raises(InvalidParameter, match="already used"):
        w.add_surface(Plane(), name="floor")
    with pytest.raises(InvalidParameter, match="dt"):
        SpatialWorld(dt=0.0)


def test_frictionless_ball_leaves_a_dome_at_the_closed_form_angle():
    """A particle sliding from rest at θ0 off a sphere leaves it at cos θ = (2/3) cos θ0; a
    frictionless ball does not spin, so its centre does the same on the offset sphere
    (parametric catalogue surface: the CasADi Newton foot point)."""
    from planner.geometry.surfaces import sphere

    R, r, th0 = 0.1, 0.01, 0.1
    w = SpatialWorld(dt=1e-3)
    w.add_surface(sphere(R), friction=0.0, name="dome")
    b = w.add_sphere(r, 0.1, (R + r) * np.array([math.sin(th0), 0.0, math.cos(th0)]))
    log = w.run(0.55)
    on = log.normal_force[:, 0] > 0
    k = np.flatnonzero(on)[-1]
    assert on[1 : k + 1].all()  # in contact from the first step until it leaves
    p = log.poses[b][k, :3]
    leave = math.degrees(math.acos(p[2] / np.linalg.norm(p)))
    assert leave == pytest.approx(math.degrees(math.acos(2 / 3 * math.cos(th0))), abs=0.5)
    assert np.nanmax(np.abs(log.gap[on, 0])) <= 1e-12


def test_a_runaway_ball_is_named_with_its_velocity_component():
    """The runaway guard names the coordinate that ran away: spheres' 6 components first
    (linear, then angular), the finger's motor rates after them."""
    w = SpatialWorld(gravity=(0.0, 0.0, 0.0))
    ball = w.add_sphere(0.01, 0.1, (0.0, 0.0, 0.5), angular_velocity=(0.0, 2e3, 0.0))
    log = w.run(0.01)
    assert log.status == "failed"
    assert log.reason.startswith("runaway velocity 2e+03 > 1000")
    assert log.reason.endswith(f"({ball}, component 4)")
