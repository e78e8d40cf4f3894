"""The planar hand inside the planar world: fingertip outlines, kinematics, dynamics.

The hand's rigid-body dynamics come from its Pinocchio model
(:func:`robots.planar_hand.model.build_model`, link masses and inertias documented there):
``M(q)`` by the composite-rigid-body algorithm and the bias ``h(q, qd) = C(q, qd) qd + g(q)``
by RNEA with the world's in-plane gravity ``(g_x, g_y, 0)``. Positions of the joints and of
the fingertip frames are closed form (``robots.planar_hand.kinematics``; equal to Pinocchio's
to machine precision, tested in ``tests/test_planar_hand.py``).

Only the fingertips collide (the links are assumed to stay clear of objects - a documented
limit of the planar world). A fingertip is a body of the world whose outline, in the
fingertip frame (origin at the fingertip point, y along the distal link), is

* round: the circle of radius ``tip_radius`` about the origin;
* flat: the pad segment ``y = 0, |x| <= pad_half_width`` with outward normal +y (an open
  profile: its two ends are corners).
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from planner.geometry import shapes
from planner.geometry.primitives import Line
from planner.geometry.profiles import Profile
from planner.sim.planar.step_kernel import hand_parameters
from robots.planar_hand import PlanarHand
from robots.planar_hand.model import EFFORT_LIMIT

__all__ = ["HandModel", "tip_profile"]


def tip_profile(hand: PlanarHand, finger: str) -> Profile:
    """The fingertip outline of ``finger`` in its fingertip frame."""
    f = hand.params.finger(finger)
    if f.tip == "round":
        return shapes.circle(f.tip_radius)
    w = f.pad_half_width
    return Profile((Line((-w, 0.0), (w, 0.0)),), name="pad")


class HandModel:
    """Kinematics and dynamics of the two fingers (6 joints: left_j1..3, right_j1..3)."""

    def __init__(self, hand: PlanarHand, gravity: tuple[float, float]) -> None:
        self.hand = hand
        self.model = hand.model.copy()
        self.model.gravity.linear = np.array([gravity[0], gravity[1], 0.0])
        self.data = self.model.createData()
        self.base = [tuple(hand.params.finger(s).base) for s in ("left", "right")]
        self.lengths = [tuple(hand.params.finger(s).lengths) for s in ("left", "right")]
        self.limits = hand.joint_limits.copy()
        self.torque_limits = np.full(6, float(EFFORT_LIMIT))
        self._zeros = np.zeros(6)
        self.packed = hand_parameters(self.model, [ln[2] for ln in self.lengths])
        """(2, 4, 6) chain parameters of the compiled kernels (:func:`hand_parameters`)."""

    def mass_bias(self, q: np.ndarray, qd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Joint-space inertia (6, 6) [kg m^2] and bias ``C qd + g`` (6,) [N m]."""
        M = pin.crba(self.model, self.data, q)
        M = np.triu(M) + np.triu(M, 1).T
        h = pin.rnea(self.model, self.data, q, qd, self._zeros)
        return M, np.array(h)

    def gravity(self, q: np.ndarray) -> np.ndarray:
        """Gravity torques g(q) (6,) [N m] (what a gravity-compensating controller adds)."""
        return np.array(pin.computeGeneralizedGravity(self.model, self.data, q))

    def frames(self, q: np.ndarray):
        """Joint points and fingertip frames of both fingers.

        Returns:
            ``(joints, tips)``: joints[f] = ((x1, y1), (x2, y2), (x3, y3)) [m];
            tips[f] = (x, y, phi) fingertip point [m] and orientation [rad].
        """
        joints, tips = [], []
        for f in range(2):
            bx, by = self.base[f]
            l1, l2, l3 = self.lengths[f]
            s1 = q[3 * f]
            s2 = s1 + q[3 * f + 1]
            s3 = s2 + q[3 * f + 2]
            x2, y2 = bx - l1 * math.sin(s1), by + l1 * math.cos(s1)
            x3, y3 = x2 - l2 * math.sin(s2), y2 + l2 * math.cos(s2)
            joints.append(((bx, by), (x2, y2), (x3, y3)))
            tips.append((x3 - l3 * math.sin(s3), y3 + l3 * math.cos(s3), s3))
        return joints, tips
