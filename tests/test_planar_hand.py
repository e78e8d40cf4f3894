"""Tests of robots.planar_hand: closed form vs Pinocchio, Jacobians, IK, URDF, workspace."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from robots.errors import UnreachableTarget
from robots.planar_hand import FINGERS, PlanarHand, ball_workspace, sample_reachable
from robots.planar_hand.model import URDF_PATH, build_model, hand_urdf, load_urdf_model

HAND = PlanarHand()


def _random_q(rng, n):
    lim = HAND.joint_limits
    return rng.uniform(lim[:, 0], lim[:, 1], size=(n, 6))


def test_model_shape_and_frames():
    m = HAND.model
    assert m.nq == 6 and m.nv == 6
    for name in ("palm", "left_tip", "right_tip"):
        assert m.existFrame(name)
    np.testing.assert_allclose(
        np.column_stack([m.lowerPositionLimit, m.upperPositionLimit]), HAND.joint_limits
    )
    np.testing.assert_allclose(np.diff(HAND.joint_limits, axis=1), np.deg2rad(110.0))


def test_closed_form_matches_pinocchio():
    rng = np.random.default_rng(0)
    m = HAND.model
    d = m.createData()
    for q in _random_q(rng, 20):
        pin.framesForwardKinematics(m, d, q)
        pos = HAND.fingertip_positions(q)
        pin.computeJointJacobians(m, d, q)
        for f in FINGERS:
            fid = m.getFrameId(f"{f}_tip")
            np.testing.assert_allclose(pos[f], d.oMf[fid].translation[:2], atol=1e-14)
            J = pin.getFrameJacobian(m, d, fid, pin.LOCAL_WORLD_ALIGNED)
            np.testing.assert_allclose(HAND.jacobian(q, f), J[:2, HAND.finger_slice(f)], atol=1e-14)
            R = d.oMf[fid].rotation
            phi = HAND.fingertip_pose(q, f).angle
            assert np.isclose(np.arctan2(R[1, 0], R[0, 0]), np.angle(np.exp(1j * phi)))


@pytest.mark.parametrize("finger", FINGERS)
def test_jacobian_finite_differences(finger):
    rng = np.random.default_rng(1)
    point = np.array([0.004, -0.01])
    for q in _random_q(rng, 5):
        J = HAND.jacobian(q, finger, point)
        Jfd = np.zeros((2, 3))
        sl = HAND.finger_slice(finger)
        for k in range(3):
            dq = np.zeros(6)
            dq[sl.start + k] = 1e-6
            Jfd[:, k] = (
                HAND.tip_frame_point(q + dq, finger, point)
                - HAND.tip_frame_point(q - dq, finger, point)
            ) / 2e-6
        np.testing.assert_allclose(J, Jfd, atol=1e-8)


def test_hand_jacobian_is_block_diagonal():
    q = HAND.neutral()
    Jh = HAND.hand_jacobian(q)
    assert Jh.shape == (4, 6)
    np.testing.assert_array_equal(Jh[:2, 3:], 0.0)
    np.testing.assert_array_equal(Jh[2:, :3], 0.0)
    np.testing.assert_allclose(Jh[2:, 3:], HAND.jacobian(q, "right"))


@settings(max_examples=40, deadline=None)
@given(
    st.sampled_from(FINGERS), st.lists(st.floats(0.02, 0.98), min_size=3, max_size=3), st.booleans()
)
def test_ik_round_trip(finger, frac, with_angle):
    lim = HAND.finger_limits(finger)
    qf = lim[:, 0] + np.array(frac) * (lim[:, 1] - lim[:, 0])
    q = HAND.neutral()
    q[HAND.finger_slice(finger)] = qf
    pose = HAND.fingertip_pose(q, finger)
    sol = HAND.inverse_kinematics(finger, pose.position, pose.angle if with_angle else None)
    assert np.all(sol >= lim[:, 0] - 1e-9) and np.all(sol <= lim[:, 1] + 1e-9)
    q2 = q.copy()
    q2[HAND.finger_slice(finger)] = sol
    back = HAND.fingertip_pose(q2, finger)
    np.testing.assert_allclose(back.position, pose.position, atol=1e-10)
    if with_angle:
        assert np.isclose(np.cos(back.angle - pose.angle), 1.0)


def test_ik_unreachable_and_bad_input():
    with pytest.raises(UnreachableTarget, match="cannot reach"):
        HAND.inverse_kinematics("right", [1.0, 1.0])
    with pytest.raises(InvalidParameter, match=r"finger: expected one of \['left', 'right'\]"):
        HAND.inverse_kinematics("middle", [0.0, 0.1])
    with pytest.raises(
        InvalidParameter, match=r"q: expected shape \(6,\) \[rad\], got shape \(5,\)"
    ):
        HAND.fingertip_positions(np.zeros(5))
    with pytest.raises(InvalidParameter, match=r"position: expected finite values"):
        HAND.inverse_kinematics("left", [np.nan, 0.1])
    with pytest.raises(InvalidParameter, match=r"n_angles: expected an integer >= 2, got 1"):
        HAND.inverse_kinematics("left", [0.0, 0.1], n_angles=1)
    with pytest.raises(InvalidParameter, match=r"friction: expected a finite number >= 0"):
        PlanarHand(friction=-0.5)
    for call in (
        lambda: HAND.jacobian(HAND.neutral(), "thumb", [0.0, 0.0]),
        lambda: HAND.fingertip_pose(HAND.neutral(), "thumb"),
        lambda: HAND.finger_points(HAND.neutral(), "thumb"),
    ):
        with pytest.raises(InvalidParameter, match="finger: expected one of"):
            call()
    with pytest.raises(
        InvalidParameter, match=r"left_tip: expected one of \['round', 'flat'\], got 'pointy'"
    ):
        PlanarHand(left_tip="pointy")


def test_urdf_file_equals_programmatic_model():
    assert URDF_PATH.read_text() == hand_urdf()
    m, u = build_model(), load_urdf_model()
    assert m.nq == u.nq
    assert list(m.names) == list(u.names)
    for a, b in zip(m.jointPlacements, u.jointPlacements, strict=True):
        assert a.isApprox(b, 1e-14)
    for a, b in zip(m.inertias, u.inertias, strict=True):
        assert a.isApprox(b, 1e-12)
    np.testing.assert_allclose(m.lowerPositionLimit, u.lowerPositionLimit)
    np.testing.assert_allclose(m.upperPositionLimit, u.upperPositionLimit)
    dm, du = m.createData(), u.createData()
    for q in _random_q(np.random.default_rng(2), 5):
        pin.framesForwardKinematics(m, dm, q)
        pin.framesForwardKinematics(u, du, q)
        for f in ("left_tip", "right_tip"):
            assert dm.oMf[m.getFrameId(f)].isApprox(du.oMf[u.getFrameId(f)], 1e-14)


def test_sample_reachable_inside_limits():
    rs = sample_reachable(HAND, "left", 200, np.random.default_rng(3))
    lim = HAND.finger_limits("left")
    assert rs.q.shape == (200, 3) and rs.positions.shape == (200, 2)
    assert np.all((rs.q >= lim[:, 0]) & (rs.q <= lim[:, 1]))
    q = HAND.neutral()
    q[:3] = rs.q[7]
    np.testing.assert_allclose(HAND.fingertip_positions(q)["left"], rs.positions[7])


def test_ten_cm_ball_graspable_against_palm():
    """The documented design goal: both fingers reach a 10 cm ball resting on the palm."""
    angles = np.deg2rad(np.arange(0.0, 360.0, 5.0))
    center = np.array([0.0, 0.05])
    for finger, side in (("right", 1.0), ("left", -1.0)):
        w = ball_workspace(HAND, finger, center, 0.05, angles)
        assert w.reachable.sum() >= 8
        # reachable contacts are on the finger's own side of the ball, above the palm
        assert np.all(side * np.cos(w.angles[w.reachable]) > -0.2)
        for a, qf in zip(w.angles[w.reachable], w.q[w.reachable], strict=True):
            q = HAND.neutral()
            q[HAND.finger_slice(finger)] = qf
            pose = HAND.fingertip_pose(q, finger)
            u = np.array([np.cos(a), np.sin(a)])
            tip = HAND.params.finger(finger)
            if tip.tip == "round":
                np.testing.assert_allclose(
                    pose.position, center + (0.05 + tip.tip_radius) * u, atol=1e-10
                )
            else:  # pad flat on the ball: its normal opposes the object normal
                np.testing.assert_allclose(pose.axis, -u, atol=1e-10)
        assert np.all(np.isnan(w.q[~w.reachable]))
