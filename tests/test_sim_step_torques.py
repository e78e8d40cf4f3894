"""Both worlds' ``step`` refuse torques that are not one finite number per joint.

Found by a blind acceptance pass: the planar compiled step accepted 5 or 7 torques (the
kernel read past the array or dropped the last one) and a NaN torque became the state; the
spatial step reported a NaN torque as a singular 3GM."""

from __future__ import annotations

import numpy as np
import pytest

from planner.errors import InvalidParameter
from planner.sim.planar.world import PlanarWorld
from planner.sim.spatial import SpatialWorld
from planner.sim.world import joint_torques
from robots.planar_hand import PlanarHand
from robots.three_gm import ThreeGM

BAD = [
    (np.full(5, 0.1), r"expected 6 joint torques of the hand \[N m\], got shape \(5,\)"),
    (np.full(7, 0.1), r"got shape \(7,\)"),
    (np.full((1, 6), 0.1), r"got shape \(1, 6\)"),
    ([0.0, 0.0, np.nan, 0.0, 0.0, 0.0], r"must be finite, got nan at index 2"),
    ([0.0, 0.0, 0.0, 0.0, 0.0, -np.inf], r"must be finite, got -inf at index 5"),
    ("torques", r"got str"),
]


@pytest.fixture(params=[True, False], ids=["compiled", "reference"])
def hand_world(request):
    w = PlanarWorld(compiled=request.param)
    h = PlanarHand()
    w.add_hand(h, h.neutral())
    return w


@pytest.mark.parametrize(("tau", "msg"), BAD)
def test_planar_step_refuses_bad_torques_and_keeps_its_state(hand_world, tau, msg):
    q0, t0 = hand_world.q.copy(), hand_world.time
    with pytest.raises(InvalidParameter, match=msg):
        hand_world.step(tau)
    assert hand_world.time == t0
    np.testing.assert_array_equal(hand_world.q, q0)


def test_planar_step_takes_a_list_and_huge_finite_torques_pass_the_check():
    t = joint_torques([1e308] * 6, 6, "joint torques")  # the sum overflows, no value is inf
    assert t.shape == (6,) and np.isfinite(t).all()
    w = PlanarWorld()
    h = PlanarHand()
    w.add_hand(h, h.neutral())
    w.step([0.0] * 6)
    assert w.time == pytest.approx(w.dt)


def test_planar_world_without_a_hand_refuses_torques_but_takes_none():
    w = PlanarWorld()
    with pytest.raises(InvalidParameter, match="tau: this world has no hand"):
        w.step([0.1] * 6)
    w.step()
    w.step(np.zeros(0))  # what the run loop passes to a world without joints
    assert w.time == pytest.approx(2 * w.dt)


@pytest.mark.parametrize(
    ("tau", "msg"),
    [
        (np.full(3, np.nan), r"tau: joint torques must be finite, got nan at index 0"),
        (np.full(2, 0.1), r"tau: expected 3 motor torques \[N m\], got shape \(2,\)"),
    ],
)
def test_spatial_step_names_bad_torques(tau, msg):
    w = SpatialWorld()
    gm = ThreeGM()
    w.add_finger(gm, gm.center_theta)
    with pytest.raises(InvalidParameter, match=msg):
        w.step(tau)


def test_spatial_world_without_a_finger_refuses_torques():
    with pytest.raises(InvalidParameter, match="tau: this world has no finger"):
        SpatialWorld().step([0.1, 0.0, 0.0])
