"""CasADi kinematics (walked from the pin.Model, and the 3GM closed form) vs Pinocchio/numpy."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from planner.errors import InvalidParameter
from robots import casadi_kinematics as ck
from robots.planar_hand import PlanarHand
from robots.three_gm import ThreeGM
from robots.three_gm.casadi_fk import casadi_kinematics
from robots.three_gm.model import configuration


def test_walked_hand_kinematics_match_pinocchio():
    hand = PlanarHand()
    m = hand.model
    d = m.createData()
    f = ck.frame_kinematics(m, ["left_tip", "right_tip"])
    rng = np.random.default_rng(0)
    lim = hand.joint_limits
    for q in rng.uniform(lim[:, 0], lim[:, 1], size=(10, 6)):
        out = [np.array(o) for o in f(q)]
        pin.computeJointJacobians(m, d, q)
        pin.updateFramePlacements(m, d)
        for k, name in enumerate(["left_tip", "right_tip"]):
            fid = m.getFrameId(name)
            np.testing.assert_allclose(out[2 * k].ravel(), d.oMf[fid].translation, atol=1e-14)
            J = pin.getFrameJacobian(m, d, fid, pin.LOCAL_WORLD_ALIGNED)[:3]
            np.testing.assert_allclose(out[2 * k + 1], J, atol=1e-14)


def test_walked_3gm_tree_matches_pinocchio():
    """The walker handles the 3GM's rotated joint placements too (3-D tree)."""
    gm = ThreeGM()
    m = gm.model
    d = m.createData()
    f = ck.frame_kinematics(m, ["endpoint"])
    th = gm.center_theta
    q = configuration(th, *gm.passive_angles(th)) + 0.1
    pin.framesForwardKinematics(m, d, q)
    np.testing.assert_allclose(
        np.array(f(q)[0]).ravel(), d.oMf[m.getFrameId("endpoint")].translation, atol=1e-14
    )


def test_3gm_casadi_closed_form_and_compiled():
    gm = ThreeGM()
    f = casadi_kinematics(gm.params)
    fc = ck.compile(f)
    for th in [gm.center_theta, gm.center_theta + np.array([0.1, -0.2, 0.3])]:
        for fun in (f, fc):
            x, J = (np.array(o) for o in fun(th))
            np.testing.assert_allclose(x.ravel(), gm.forward_kinematics(th), atol=1e-14)
            np.testing.assert_allclose(J, gm.jacobian(th), atol=1e-12)


def test_unknown_frame_is_rejected():
    with pytest.raises(InvalidParameter, match="not in the model"):
        ck.frame_kinematics(PlanarHand().model, ["thumb_tip"])
