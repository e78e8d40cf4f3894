"""Reachable sets of the hand's fingers and the workspace map on a disc object (thesis §2.2.1).

The workspace map tells, for each contact angle on a circular object slice, whether a finger
can touch it there: an inverse-kinematics solution inside the joint limits, with the fingertip
orientation inside the allowed range (round tip: the contact stays within
``max_tip_contact_angle`` of the fingertip axis; flat tip: the pad lies flat on the object), and
no penetration (no link crosses the object, no point goes below the palm plane y = 0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks
from robots.planar_hand import kinematics as kin
from robots.planar_hand.hand import PlanarHand
from robots.planar_hand.params import FINGERS


@dataclass(frozen=True)
class ReachableSet:
    """Samples of one finger's reachable fingertip poses.

    Attributes:
        q: (N, 3) joint angles inside the limits [rad].
        positions: (N, 2) fingertip points [m].
        angles: (N,) fingertip orientations phi [rad].
    """

    q: np.ndarray
    positions: np.ndarray
    angles: np.ndarray


@dataclass(frozen=True)
class WorkspaceMap:
    """Which contact angles on a disc a finger can reach.

    Attributes:
        finger: ``"left"`` or ``"right"``.
        angles: (M,) contact angles on the object, counter-clockwise from +x about its
            centre [rad].
        reachable: (M,) whether the contact can be made.
        q: (M, 3) one solution per reachable angle (the one farthest from the joint limits);
            rows of unreachable angles are NaN (check ``reachable``) [rad].
        contacts: (M, 2) contact points on the object [m].
    """

    finger: str
    angles: np.ndarray
    reachable: np.ndarray
    q: np.ndarray
    contacts: np.ndarray

    @property
    def fraction(self) -> float:
        """Fraction of the sampled contact angles that are reachable [-]."""
        return float(np.mean(self.reachable)) if self.reachable.size else 0.0


def sample_reachable(
    hand: PlanarHand, finger: str, n: int, rng: np.random.Generator
) -> ReachableSet:
    """Sample the reachable set uniformly in joint space.

    Args:
        hand: the hand.
        finger: ``"left"`` or ``"right"``.
        n: number of samples (>= 1).
        rng: the random generator (seeded by the caller).
    """
    checks.choice("finger", finger, FINGERS)
    n = checks.integer("n", n, 1)
    lim = hand.finger_limits(finger)
    q = rng.uniform(lim[:, 0], lim[:, 1], size=(n, 3))
    f = hand.params.finger(finger)
    p, phi = kin.fingertip(np.array(f.base), np.array(f.lengths), q)
    return ReachableSet(q, p, phi)


def _segment_distance(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance from ``points`` (2,) to segments a->b (..., 2) [m]."""
    ab = b - a
    t = np.clip(
        np.sum((points - a) * ab, axis=-1) / np.maximum(np.sum(ab * ab, axis=-1), 1e-300), 0.0, 1.0
    )
    return np.linalg.norm(a + t[..., None] * ab - points, axis=-1)


def collision_free(
    hand: PlanarHand,
    finger: str,
    q: np.ndarray,
    center: np.ndarray,
    radius: float,
    tol: float = 1e-9,
) -> np.ndarray:
    """Whether configurations are free of penetration with the disc and the palm plane.

    Args:
        q: (..., 3) joint angles of ``finger`` [rad].
        center: (2,) disc centre [m]; radius: disc radius [m].

    Returns:
        (...) boolean mask: no link closer than ``radius`` to the disc centre, no joint or
        fingertip point below y = 0, a round tip's disc not below y = 0.
    """
    f = hand.params.finger(finger)
    pts = kin.finger_points(np.array(f.base), np.array(f.lengths), q)  # (..., 4, 2)
    d = _segment_distance(center, pts[..., :-1, :], pts[..., 1:, :])
    ok = np.all(d >= radius - tol, axis=-1)
    ok &= np.all(pts[..., 1:, 1] >= -tol, axis=-1)
    if f.tip == "round":
        ok &= pts[..., 3, 1] >= f.tip_radius - tol
        tip_to_center = np.linalg.norm(pts[..., 3, :] - center, axis=-1)
        ok &= tip_to_center >= radius + f.tip_radius - 1e-6
    return ok


def ball_workspace(
    hand: PlanarHand,
    finger: str,
    center,
    radius: float,
    angles,
    max_tip_contact_angle: float = np.deg2rad(60.0),
    n_orientations: int = 61,
    n_pad_offsets: int = 9,
) -> WorkspaceMap:
    """Workspace map of one finger on a disc (the ball's slice in the hand plane).

    Round tip: for contact angle a the fingertip centre is ``c + (R + r) u(a)``; the fingertip
    orientation phi ranges over ``n_orientations`` values such that the contact lies within
    ``max_tip_contact_angle`` of the fingertip axis. Flat tip: the pad's outward normal is
    ``-u(a)`` (phi fixed) and the contact may lie anywhere on the pad (``n_pad_offsets``
    offsets across +-pad_half_width).

    Args:
        hand: the hand.
        finger: ``"left"`` or ``"right"``.
        center: (2,) disc centre [m].
        radius: disc radius [m] (a 10 cm ball: 0.05).
        angles: (M,) contact angles, counter-clockwise from +x [rad].
        max_tip_contact_angle: round tips only, in [0, pi/2] [rad].
        n_orientations: orientation samples (round tip), >= 1.
        n_pad_offsets: pad offset samples (flat tip), >= 1.

    Returns:
        The :class:`WorkspaceMap`.
    """
    checks.choice("finger", finger, FINGERS)
    c = checks.vector("center", center, 2, "m")
    radius = checks.positive("radius", radius, "m")
    a = checks.series("angles", np.atleast_1d(np.asarray(angles, dtype=float)), unit="rad")
    checks.in_range("max_tip_contact_angle", max_tip_contact_angle, 0.0, np.pi / 2, "rad")
    checks.integer("n_orientations", n_orientations, 1)
    checks.integer("n_pad_offsets", n_pad_offsets, 1)
    f = hand.params.finger(finger)
    u = np.stack([np.cos(a), np.sin(a)], axis=-1)  # (M, 2) outward object normal
    contacts = c + radius * u
    # fingertip axis pointing at the object: d(phi) = -u(a)  <=>  phi = a + pi/2
    phi0 = a + np.pi / 2
    if f.tip == "round":
        dphi = np.linspace(-max_tip_contact_angle, max_tip_contact_angle, int(n_orientations))
        phi = phi0[:, None] + dphi[None, :]
        targets = np.broadcast_to((c + (radius + f.tip_radius) * u)[:, None, :], phi.shape + (2,))
    else:
        w = f.pad_half_width
        s = np.linspace(-w, w, int(n_pad_offsets)) if n_pad_offsets > 1 else np.zeros(1)
        t = np.stack([-u[:, 1], u[:, 0]], axis=-1)  # tangent
        targets = contacts[:, None, :] - s[None, :, None] * t[:, None, :]
        phi = np.broadcast_to(phi0[:, None], targets.shape[:-1])
    q, ok = hand.ik_candidates(finger, targets, phi)  # (M, K, 2, 3), (M, K, 2)
    ok &= collision_free(hand, finger, q, c, radius)
    lim = hand.finger_limits(finger)
    margin = np.min(np.minimum(q - lim[:, 0], lim[:, 1] - q), axis=-1)
    margin = np.where(ok, margin, -np.inf).reshape(len(a), -1)
    best = np.argmax(margin, axis=1)
    reachable = np.isfinite(margin[np.arange(len(a)), best])
    qsel = q.reshape(len(a), -1, 3)[np.arange(len(a)), best]
    qsel[~reachable] = np.nan
    return WorkspaceMap(finger, a, reachable, qsel, contacts)
