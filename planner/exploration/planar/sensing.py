"""What the gait's controllers know about the grasp, from sensors only (§2.2.2, Fig. 2.7).

"Contact point sensing ... can be done using intrinsic or extrinsic tactile sensors, or
using assumptions based on fingertip motion history if the local object shape is known."
Here:

* left (flat pad with the 8x8 array): the contact position ``u`` across the pad is the
  pressure centroid of the tactile image (extrinsic sensing); the pad's pose comes from the
  encoders, so the contact point and the object's outward normal there
  (``n = (sin phi, -cos phi)``) are sensed;
* right (round tip, no array): the contact lies on the tip towards the estimated object
  centre (the nominal shape's local radius ``R``);
* object centre: ``c = p_L + R n_L`` while the pad touches; otherwise from the right tip
  and the palm (the object resting on the palm, ``c_y = R``);
* object rotation during rolling (eq. 2.4 integrated): ``theta = Δbeta_L - Δu / R`` with
  ``beta_L = phi_L - pi/2`` the world angle of the pad contact;
* strain gauges give the fingertip forces (applied on the object, WCS).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: tactile force [N] above which the pad is considered in contact
TOUCH_FORCE = 0.02


@dataclass
class GraspEstimate:
    """The sensed grasp at one instant (mutable, updated in place each control step).

    Attributes:
        u: contact position across the left pad [m] (tactile centroid).
        pad_touch: whether the tactile array sees a contact.
        p: (2, 2) contact points of the left and right fingers [m].
        n: (2, 2) outward object normals at them (the fingers push along ``-n``).
        centre: (2,) estimated object centre [m].
        beta: (2,) world polar angles of the contacts about ``centre`` [rad].
        forces: (2, 2) strain-gauge forces on the object [N].
        normal_force: (2,) their components along ``-n`` [N].
        offsets: (4,) contact points in the fingertip frames [m] (for the control step).
        tip_normals: (4,) tip-frame unit normals pointing into the object.
        tips: (2, 2) fingertip points from the encoders (pad centre, tip-disc centre) [m].
    """

    u: float = 0.0
    pad_touch: bool = False
    p: np.ndarray = None  # type: ignore[assignment]
    n: np.ndarray = None  # type: ignore[assignment]
    centre: np.ndarray = None  # type: ignore[assignment]
    beta: np.ndarray = None  # type: ignore[assignment]
    forces: np.ndarray = None  # type: ignore[assignment]
    normal_force: np.ndarray = None  # type: ignore[assignment]
    offsets: np.ndarray = None  # type: ignore[assignment]
    tip_normals: np.ndarray = None  # type: ignore[assignment]
    tips: np.ndarray = None  # type: ignore[assignment]


class GraspSensing:
    """Turns :class:`planner.sim.Observation` readings into a :class:`GraspEstimate`.

    Args:
        hand: the ``robots.planar_hand.PlanarHand`` (flat left pad, round right tip).
        radius: the nominal object radius used by the estimate [m].
        tactile: the ``robots.sensors.TactileArray`` model (for reading images).
    """

    def __init__(self, hand, radius: float, tactile=None) -> None:
        from robots.sensors import TactileArray

        self.hand = hand
        self.radius = float(radius)
        self.r = hand.params.right.tip_radius
        self.array = tactile or TactileArray()
        self._geom = tuple(
            (tuple(float(v) for v in f.base), tuple(float(v) for v in f.lengths))
            for f in (hand.params.left, hand.params.right)
        )
        self.est = GraspEstimate(
            p=np.zeros((2, 2)),
            n=np.zeros((2, 2)),
            centre=np.zeros(2),
            beta=np.zeros(2),
            forces=np.zeros((2, 2)),
            normal_force=np.zeros(2),
            offsets=np.zeros(4),
            tip_normals=np.array([0.0, 1.0, 0.0, 1.0]),
            tips=np.zeros((2, 2)),
        )

    def _tip(self, k: int, q) -> np.ndarray:
        """Fingertip point of finger ``k`` (0 left, 1 right) [m]: the closed-form forward
        kinematics of ``PlanarHand.fingertip_pose`` in Python scalars (5x faster per call;
        equal to it to rounding, tested)."""
        (bx, by), lengths = self._geom[k]
        a, x, y = 0.0, bx, by
        for i in range(3):
            a += float(q[3 * k + i])
            x -= lengths[i] * math.sin(a)
            y += lengths[i] * math.cos(a)
        return np.array((x, y))

    def update(self, obs, source: str = "auto") -> GraspEstimate:
        """Refresh the estimate from one observation (see the module docstring).

        Args:
            obs: the :class:`planner.sim.Observation`.
            source: where the object centre comes from: ``"pad"`` (left pad + nominal
                radius), ``"palm"`` (right tip + palm), ``"auto"`` (pad while it touches).
        """
        e = self.est
        q = obs.q
        if obs.tactile is not None and "left" in obs.tactile:
            reading = self.array.read(obs.tactile["left"])
            e.pad_touch = bool(reading.in_contact and reading.force > TOUCH_FORCE)
            if e.pad_touch:
                e.u = float(reading.centroid[0])
        phiL = float(q[0] + q[1] + q[2])
        cL, sL = math.cos(phiL), math.sin(phiL)
        tipL = self._tip(0, q)
        e.p[0] = tipL + e.u * np.array([cL, sL])
        e.n[0] = (sL, -cL)
        tipR = self._tip(1, q)
        e.tips[0], e.tips[1] = tipL, tipR
        R, r = self.radius, self.r
        if source == "pad" or (source == "auto" and e.pad_touch):
            e.centre[:] = e.p[0] - R * e.n[0]
        else:  # resting on the palm, touching the right tip
            dy = R - tipR[1]
            dx = math.sqrt(max((R + r) ** 2 - dy * dy, 0.0))
            e.centre[:] = (tipR[0] - dx, R)
        d = e.centre - tipR
        d /= max(float(np.hypot(d[0], d[1])), 1e-12)
        e.p[1] = tipR + r * d
        e.n[1] = -d
        for k in range(2):
            v = e.p[k] - e.centre
            e.beta[k] = math.atan2(v[1], v[0])
        e.forces[:] = obs.tip_forces
        e.normal_force[:] = -np.sum(e.forces * e.n, axis=1)
        phiR = float(q[3] + q[4] + q[5])
        cR, sR = math.cos(phiR), math.sin(phiR)
        dt = (cR * d[0] + sR * d[1], -sR * d[0] + cR * d[1])  # d in the right tip frame
        e.offsets[:] = (e.u, 0.0, r * dt[0], r * dt[1])
        e.tip_normals[:] = (0.0, 1.0, dt[0], dt[1])
        return e


def round_contact_arclength(beta: float, phi: float, tip_radius: float) -> float:
    """Contact location on the round right tip as an arclength from its apex [m]
    (:func:`planner.control.rolling_pd.contact_arclength` for the contact at world polar
    angle ``beta`` of the object and tip orientation ``phi``)."""
    alpha = (beta + math.pi) - phi  # tip-frame angle of the contact direction
    a = math.atan2(math.sin(alpha), math.cos(alpha))
    return tip_radius * (a - 0.5 * math.pi)


__all__ = ["GraspEstimate", "GraspSensing", "TOUCH_FORCE", "round_contact_arclength"]
