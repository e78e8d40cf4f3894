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
  profile: its two ends are corners), the face of a body :data:`PAD_DEPTH` deep: a point
  farther behind it is behind the fingertip and makes no contact.
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

__all__ = ["PAD_DEPTH", "HandModel", "tip_profile"]

#: how deep a flat fingertip's body reaches behind its pad face [m]
#: (:attr:`planner.sim.planar.outline.Outline.depth`). A corner, an arc or a curve of the
#: object farther behind the pad has come round its end and is behind the fingertip (where
#: the links, which do not collide, are), not in it. Pushed out through the face however
#: deep (until 2026-11-25), such a "penetration" fed the step's gap term: a 2.8 cm 7-gon
#: tumbling in a failed gait (mu 1, seed 687) brought a corner round the left pad's end
#: 25 mm behind its face, and the kinetic energy went from 0.08 to 1.25 J, the object to
#: 235 rad/s, in one step; a round right tip whose centre came behind the left pad read as
#: 50 mm deep and stopped a run on a Lemke ray. A step's own penetrations are its travel
#: (about 2 mm at 1 m/s), and the ball's 3 mm ridge entering a pad's slab from the side is
#: still pushed out through the face. The palm keeps an unbounded depth (a floor).
PAD_DEPTH = 5e-3


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
