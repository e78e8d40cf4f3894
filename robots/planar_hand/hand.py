"""The planar two-finger hand with a passive palm: kinematics, Jacobians and IK (thesis §2.2)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from robots.errors import UnreachableTarget
from robots.planar_hand import kinematics as kin
from robots.planar_hand.params import FINGERS, HandParams, default_finger


@dataclass(frozen=True)
class FingertipPose:
    """Pose of a fingertip in the hand plane.

    Attributes:
        position: (2,) fingertip point (round: disc centre; flat: pad centre) [m].
        angle: orientation phi = q1 + q2 + q3, measured counter-clockwise from +y [rad].
        axis: (2,) unit direction of the distal link, (-sin phi, cos phi); for a flat tip the
            pad's outward normal [-].
    """

    position: np.ndarray
    angle: float
    axis: np.ndarray


class PlanarHand:
    """Two planar 3-DOF fingers ("left", "right") and a fixed passive palm.

    ``q`` is always the full (6,) configuration ``(left_j1..3, right_j1..3)`` [rad] unless a
    method says it takes one finger's (3,) angles. Kinematics are closed form (numpy) and agree
    with the Pinocchio model :attr:`model` to machine precision (tested).

    Args:
        params: all hand parameters; the keyword arguments below override parts of the
            defaults when ``params`` is not given.
        left_tip: ``"flat"`` (default, 8x8 tactile array) or ``"round"``.
        right_tip: ``"round"`` (default) or ``"flat"``.
        tip_radius: radius of round fingertips [m] (default 0.025, thesis §2.3.2).
        friction: default contact friction coefficient [-] (default 1.0, Fig. 2.4).
    """

    def __init__(
        self,
        params: HandParams | None = None,
        *,
        left_tip: str | None = None,
        right_tip: str | None = None,
        tip_radius: float = 0.025,
        friction: float = 1.0,
    ) -> None:
        if params is None:
            for name, v in (("left_tip", left_tip), ("right_tip", right_tip)):
                if v is not None:
                    checks.choice(name, v, ("round", "flat"))
            friction = checks.nonnegative("friction", friction)
            params = HandParams(
                left=default_finger("left", left_tip, tip_radius),
                right=default_finger("right", right_tip, tip_radius),
                friction=float(friction),
            )
        self.params: HandParams = params
        self._base = {s: np.array(params.finger(s).base, dtype=float) for s in FINGERS}
        self._len = {s: np.array(params.finger(s).lengths, dtype=float) for s in FINGERS}
        self._basel = {s: tuple(float(v) for v in params.finger(s).base) for s in FINGERS}
        self._lenl = {s: tuple(float(v) for v in params.finger(s).lengths) for s in FINGERS}
        self._model = None

    # ------------------------------------------------------------------ model and limits
    @property
    def model(self):
        """The Pinocchio model (``pin.Model``, nq == 6), built on first use."""
        if self._model is None:
            from robots.planar_hand.model import build_model

            self._model = build_model(self.params)
        return self._model

    @property
    def nq(self) -> int:
        """Number of joints (6)."""
        return 6

    @property
    def joint_limits(self) -> np.ndarray:
        """(6, 2) lower/upper joint limits [rad] in the order of ``q``."""
        return np.vstack([self.finger_limits(s) for s in FINGERS])

    def finger_limits(self, finger: str) -> np.ndarray:
        """(3, 2) joint limits of one finger [rad]."""
        f = self.params.finger(finger)
        return np.column_stack([f.lower, f.upper]).astype(float)

    @staticmethod
    def finger_slice(finger: str) -> slice:
        """The slice of ``q`` holding ``finger``'s joints."""
        checks.choice("finger", finger, FINGERS)
        return slice(0, 3) if finger == "left" else slice(3, 6)

    def neutral(self) -> np.ndarray:
        """(6,) mid-range configuration [rad]."""
        return self.joint_limits.mean(axis=1)

    # ------------------------------------------------------------------ forward kinematics
    def fingertip_positions(self, q) -> dict[str, np.ndarray]:
        """Fingertip points of both fingers.

        Args:
            q: (6,) joint angles [rad].

        Returns:
            ``{"left": (2,), "right": (2,)}`` fingertip points in the hand plane [m].
        """
        ql = checks.vector("q", q, 6, "rad").tolist()
        out = {}
        for s, k in (("left", 0), ("right", 3)):
            x, y, _, _ = kin.tip_and_jacobian(self._basel[s], self._lenl[s], ql[k : k + 3])
            out[s] = np.array([x, y])
        return out

    def fingertip_pose(self, q, finger: str) -> FingertipPose:
        """Position and orientation of one fingertip for the full (6,) configuration ``q``."""
        checks.choice("finger", finger, FINGERS)
        q = checks.vector("q", q, 6, "rad")
        sl = self.finger_slice(finger)
        x, y, phi, _ = kin.tip_and_jacobian(self._basel[finger], self._lenl[finger], q[sl].tolist())
        return FingertipPose(np.array([x, y]), phi, np.array([-math.sin(phi), math.cos(phi)]))

    def finger_points(self, q, finger: str) -> np.ndarray:
        """(4, 2) joint 1, joint 2, joint 3 and fingertip points of ``finger`` [m]."""
        checks.choice("finger", finger, FINGERS)
        q = checks.vector("q", q, 6, "rad")
        return kin.finger_points(
            self._base[finger], self._len[finger], q[self.finger_slice(finger)]
        )

    # ------------------------------------------------------------------ Jacobians
    def jacobian(self, q, finger: str, point=None) -> np.ndarray:
        """Fingertip Jacobian of one finger: d p / d q_finger.

        Args:
            q: (6,) joint angles [rad].
            finger: ``"left"`` or ``"right"``.
            point: optional (2,) point fixed on the distal link, in the fingertip frame
                (x across the link, y along it, origin at the fingertip point) [m] — e.g. the
                contact point on the fingertip. Default: the fingertip point.

        Returns:
            (2, 3) Jacobian [m/rad] with respect to that finger's three joints.
        """
        checks.choice("finger", finger, FINGERS)
        q = checks.vector("q", q, 6, "rad")
        if point is None:
            sl = self.finger_slice(finger)
            return kin.tip_and_jacobian(self._basel[finger], self._lenl[finger], q[sl].tolist())[3]
        off = checks.vector("point", point, 2, "m")
        return kin.fingertip_jacobian(self._len[finger], q[self.finger_slice(finger)], off)

    def hand_jacobian(self, q, contacts: dict[str, np.ndarray] | None = None) -> np.ndarray:
        """Hand Jacobian J_h of thesis eq. 2.5, ``xdot_c = J_h qdot``.

        Args:
            q: (6,) joint angles [rad].
            contacts: optional ``{finger: (2,) contact point in that fingertip's frame [m]}``;
                a finger not given uses its fingertip point.

        Returns:
            (4, 6) block-diagonal Jacobian; rows (left x, left y, right x, right y) [m/rad].
        """
        contacts = contacts or {}
        unknown = set(contacts) - set(FINGERS)
        if unknown:
            raise InvalidParameter(
                f"contacts: expected keys in {list(FINGERS)}, got {sorted(unknown)}"
            )
        out = np.zeros((4, 6))
        for i, s in enumerate(FINGERS):
            out[2 * i : 2 * i + 2, self.finger_slice(s)] = self.jacobian(q, s, contacts.get(s))
        return out

    def tip_frame_point(self, q, finger: str, point) -> np.ndarray:
        """(2,) hand-plane position of a point given in the fingertip frame [m]."""
        pose = self.fingertip_pose(q, finger)
        c, s = np.cos(pose.angle), np.sin(pose.angle)
        p = checks.vector("point", point, 2, "m")
        return pose.position + np.array([c * p[0] - s * p[1], s * p[0] + c * p[1]])

    # ------------------------------------------------------------------ inverse kinematics
    def inverse_kinematics(
        self, finger: str, position, angle: float | None = None, q0=None, n_angles: int = 721
    ) -> np.ndarray:
        """Joint angles of one finger that put its fingertip at ``position``.

        With ``angle`` the fingertip orientation is imposed too (closed form, both elbow
        branches tried). Without it the redundant orientation is searched on a grid of
        ``n_angles`` values over the reachable range and the solution closest to ``q0``
        (default: the middle of the joint ranges) is returned; position is exact either way.

        Args:
            finger: ``"left"`` or ``"right"``.
            position: (2,) fingertip point target [m].
            angle: fingertip orientation phi [rad] or None.
            q0: (3,) reference angles of that finger [rad] for choosing among solutions.
            n_angles: orientation grid size when ``angle`` is None.

        Returns:
            (3,) joint angles within the joint limits [rad].

        Raises:
            UnreachableTarget: no solution inside the joint limits.
        """
        checks.choice("finger", finger, FINGERS)
        p = checks.vector("position", position, 2, "m")
        lim = self.finger_limits(finger)
        ref = lim.mean(axis=1) if q0 is None else checks.vector("q0", q0, 3, "rad")
        if angle is None:
            n_angles = checks.integer("n_angles", n_angles, 2)
            phis = np.linspace(lim[:, 0].sum(), lim[:, 1].sum(), n_angles)
        else:
            phis = checks.vector("angle", [angle], 1, "rad")
        sols, ok = self.ik_candidates(finger, np.broadcast_to(p, phis.shape + (2,)), phis)
        if not ok.any():
            what = f"position {p.tolist()} m" + ("" if angle is None else f", angle {angle} rad")
            raise UnreachableTarget(
                f"{finger} finger cannot reach {what} within its joint "
                f"limits {np.rad2deg(lim).round(1).tolist()} deg"
            )
        cand = sols[ok]
        best = np.argmin(np.sum((cand - ref) ** 2, axis=1))
        return cand[best].copy()

    def ik_candidates(
        self, finger: str, positions: np.ndarray, angles: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """All closed-form IK solutions (vectorized, no validation; for hot loops).

        Args:
            finger: ``"left"`` or ``"right"``.
            positions: (M, 2) fingertip targets [m].
            angles: (M,) fingertip orientations [rad].

        Returns:
            q: (M, 2, 3) solutions wrapped into the joint limits where possible [rad],
            ok: (M, 2) reachable and inside the limits.
        """
        lim = self.finger_limits(finger)
        q, ok = kin.ik_branches(self._base[finger], self._len[finger], positions, angles)
        q, inside = kin.wrap_into(q, lim[:, 0], lim[:, 1])
        return q, ok & inside.all(axis=-1)

    def within_limits(self, q, tol: float = 1e-9) -> bool:
        """Whether the (6,) configuration ``q`` respects every joint limit."""
        q = checks.vector("q", q, 6, "rad")
        lim = self.joint_limits
        return bool(np.all(q >= lim[:, 0] - tol) and np.all(q <= lim[:, 1] + tol))
