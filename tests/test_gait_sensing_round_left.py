"""The gait's sensing with a round left tip (sensing._round_left): no tactile array, so the
left contact lies on its tip towards the estimated centre, like the right one's; the centre
comes from both tips (tangent circle), or from one tip and the palm. Checked against the
exact grasp of a circle placed by the start-grasp search."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from planner.exploration.planar.heuristics import start_grasp_candidates
from planner.exploration.planar.sensing import GraspSensing, round_contact_arclength

R, RL = 0.05, 0.025


@pytest.fixture(scope="module")
def hand():
    from robots.planar_hand import PlanarHand, gait_hand_params

    return PlanarHand(gait_hand_params(left_tip_radius=RL))


def _obs(q, press=(1.0, 1.0), centre=(0.0, R), hand=None):
    """Encoders ``q`` and strain gauges pressing each tip towards ``centre`` [N]."""
    forces = np.zeros((2, 2))
    for k, side in enumerate(("left", "right")):
        d = np.asarray(centre) - hand.fingertip_pose(q, side).position
        forces[k] = press[k] * d / np.linalg.norm(d)
    return SimpleNamespace(q=np.asarray(q, float), tip_forces=forces, tactile=None)


@pytest.mark.parametrize("index", [0, 7, 31])
@pytest.mark.parametrize("source", ["auto", "pad", "palm"])
def test_a_circle_on_the_palm_is_sensed_exactly(hand, index, source):
    c = np.array([0.0, R])
    bl, br, q, _ = start_grasp_candidates(hand, c, R, 0.8)[index]
    est = GraspSensing(hand, R).update(_obs(q, hand=hand), source)
    np.testing.assert_allclose(est.centre, c, atol=1e-9)
    np.testing.assert_allclose(est.beta, (bl, math.remainder(br, 2 * math.pi)), atol=1e-9)
    for k, b in enumerate((bl, br)):
        n = np.array([math.cos(b), math.sin(b)])
        np.testing.assert_allclose(est.p[k], c + R * n, atol=1e-9)
        np.testing.assert_allclose(est.n[k], n, atol=1e-9)
    assert est.u == pytest.approx(round_contact_arclength(bl, q[:3].sum(), RL), abs=1e-12)
    assert est.pad_touch
    np.testing.assert_allclose(est.normal_force, 1.0, atol=1e-9)


def test_both_tips_find_a_lifted_circle_the_palm_does_not(hand):
    """Lifted 5 mm off the palm: the tangent circle of both tips is exact, the palm's is
    5 mm low; a left tip that stops pressing hands the centre to the right tip and palm."""
    c = np.array([0.0, R])
    _, _, q, _ = start_grasp_candidates(hand, c, R, 0.8)[0]
    lifted = c + (0.0, 0.005)
    q_up = _lift(hand, q, lifted)
    est = GraspSensing(hand, R).update(_obs(q_up, hand=hand, centre=lifted), "auto")
    np.testing.assert_allclose(est.centre, lifted, atol=1e-9)
    palm = GraspSensing(hand, R).update(_obs(q_up, hand=hand, centre=lifted), "palm").centre
    assert palm[1] == pytest.approx(R) and np.linalg.norm(palm - lifted) > 0.004
    loose = GraspSensing(hand, R)
    est = loose.update(_obs(q_up, press=(0.0, 1.0), hand=hand, centre=lifted), "auto")
    assert not est.pad_touch and est.centre[1] == pytest.approx(R)


def _lift(hand, q, centre):
    """Joints putting both tips on the circle of radius R about ``centre`` at the contact
    angles of ``q``'s grasp of the circle on the palm (IK of each tip centre)."""
    from planner.exploration.planar.heuristics import best_margin_ik

    out = []
    c0 = np.array([0.0, R])
    for side in ("left", "right"):
        t = hand.fingertip_pose(q, side)
        qk = best_margin_ik(hand, side, t.position + (np.asarray(centre) - c0),
                            around=t.angle, spread=0.05)  # fmt: skip
        assert qk is not None
        out.append(qk)
    return np.r_[out[0], out[1]]


def test_round_radius_is_the_round_tips_and_zero_for_the_pad(hand):
    from robots.planar_hand import PlanarHand

    assert hand.params.left.round_radius == RL
    assert PlanarHand().params.left.round_radius == 0.0  # the flat pad
    assert PlanarHand().params.right.round_radius == PlanarHand().params.right.tip_radius
