"""Workspace maps: which contact angles each finger of the planar hand can reach (§2.2.1).

The object lies in the hand plane resting on the palm (the segment ``y = 0``,
``|x| <= palm_half_width``, surface facing +y): for an object rotation φ its origin is placed
at ``(x0, h(φ))`` with ``h`` such that the lowest point touches the palm. A finger reaches the
contact angle θ when an inverse-kinematics solution inside the joint limits puts its
fingertip on the contact with an admissible orientation (round tip: the contact within
``max_tip_contact_angle`` of the fingertip axis; flat tip: the pad flat on the object, the
contact anywhere on the pad) and no link penetrates the object or goes below the palm.

Anything with the :class:`ReachabilityModel` interface can stand in for the hand (e.g. a
simpler model in tests); :class:`HandReachability` wraps ``robots.planar_hand.PlanarHand``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from planner.grasp.maps import contact_angles, profile_contacts

PAIRS = (("left", "right"), ("left", "palm"), ("right", "palm"))


@runtime_checkable
class ReachabilityModel(Protocol):
    """What the workspace maps and the gait search need from a hand.

    Attributes:
        fingers: names of the active fingers, e.g. ``("left", "right")``.
        palm_half_width: the palm is the segment ``y = 0, |x| <= palm_half_width`` [m].
    """

    fingers: tuple[str, ...]
    palm_half_width: float

    def reachable(
        self,
        finger: str,
        contacts: np.ndarray,
        normals: np.ndarray,
        inside: Callable[[np.ndarray], np.ndarray],
    ) -> np.ndarray:
        """Whether ``finger`` can touch each contact.

        Args:
            finger: one of :attr:`fingers`.
            contacts: (M, 2) contact points in the hand frame [m].
            normals: (M, 2) outward unit object normals there.
            inside: ``inside(points, rows)`` maps (L, P, 2) hand-frame points and (L,) contact
                indices to (L, P) bool "inside the object" (row l is tested against the
                object pose of contact ``rows[l]``).

        Returns:
            (M,) bool.
        """
        ...


class RadialFunction:
    """Radius of a star-shaped closed profile as a function of the polar angle (table)."""

    def __init__(self, profile, samples: int = 2048):
        self.alpha = contact_angles(samples)
        pts, _ = profile_contacts(profile, self.alpha)
        self.radius = np.hypot(pts[:, 0], pts[:, 1])
        self._a = np.concatenate([self.alpha, [2 * np.pi]])
        self._r = np.concatenate([self.radius, self.radius[:1]])

    def __call__(self, alpha) -> np.ndarray:
        """Radius at polar angles ``alpha`` (any shape) [m]."""
        return np.interp(np.mod(alpha, 2 * np.pi), self._a, self._r)

    def inside(self, points_obj: np.ndarray, tol: float = 1e-6) -> np.ndarray:
        """Whether object-frame points (..., 2) lie strictly inside (by more than ``tol`` [m])."""
        r = np.hypot(points_obj[..., 0], points_obj[..., 1])
        return r < self(np.arctan2(points_obj[..., 1], points_obj[..., 0])) - tol


def rotation(phi) -> np.ndarray:
    """Rotation matrices (..., 2, 2) of angles ``phi`` [rad] (object frame -> hand frame)."""
    c, s = np.cos(phi), np.sin(phi)
    return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)


@dataclass(frozen=True)
class Placement:
    """Object poses resting on the palm.

    Attributes:
        angles: (K,) object rotations φ (counter-clockwise) [rad].
        offsets: (K, 2) positions of the object origin in the hand frame [m].
        palm_theta: (K,) contact angle of the palm contact in the object frame [rad]
            (NaN when the lowest point is off the palm segment).
    """

    angles: np.ndarray
    offsets: np.ndarray
    palm_theta: np.ndarray


def rest_on_palm(
    profile, angles, x0: float = 0.0, palm_half_width: float = np.inf, samples: int = 2048
) -> Placement:
    """Place the object on the palm for each rotation (lowest point at ``y = 0``).

    A flat face lying on the palm touches it along a segment; its middle is taken as the
    palm contact point.
    """
    angles = np.atleast_1d(np.asarray(angles, dtype=float))
    alpha = contact_angles(samples)
    pts, _ = profile_contacts(profile, alpha)
    R = rotation(angles)  # (K, 2, 2)
    y = np.einsum("kj,nj->kn", R[:, 1, :], pts)  # (K, N) heights of every point
    ymin = y.min(axis=1)
    scale = float(np.max(np.hypot(pts[:, 0], pts[:, 1])))
    tied = y <= ymin[:, None] + 1e-7 * scale
    # circular mean of the tied polar angles
    z = np.where(tied, np.exp(1j * alpha)[None, :], 0).sum(axis=1)
    theta_p = np.mod(np.angle(z), 2 * np.pi)
    offsets = np.stack([np.full(angles.shape, float(x0)), -ymin], axis=1)
    p_palm, _ = profile_contacts(profile, theta_p)
    x_world = np.einsum("kj,kj->k", R[:, 0, :], p_palm) + offsets[:, 0]
    theta_p = np.where(np.abs(x_world) <= palm_half_width, theta_p, np.nan)
    return Placement(angles, offsets, theta_p)


class HandReachability:
    """:class:`ReachabilityModel` of ``robots.planar_hand.PlanarHand`` for any star-shaped object.

    Args:
        hand: the planar hand (default ``PlanarHand()``).
        max_tip_contact_angle: round tips: largest angle between the fingertip axis and the
            direction to the contact [rad] (default 60°).
        n_orientations: round tips: orientation samples over that range (>= 1).
        n_pad_offsets: flat tips: contact positions sampled across the pad (>= 1).
        link_samples: points tested for penetration along each link (>= 2).
    """

    fingers = ("left", "right")

    def __init__(
        self,
        hand=None,
        *,
        max_tip_contact_angle: float = np.deg2rad(60.0),
        n_orientations: int = 13,
        n_pad_offsets: int = 5,
        link_samples: int = 4,
    ):
        if hand is None:
            from robots.planar_hand import PlanarHand

            hand = PlanarHand()
        self.hand = hand
        self.palm_half_width = float(hand.params.palm_half_width)
        self.max_tip_contact_angle = checks.in_range(
            "max_tip_contact_angle", max_tip_contact_angle, 0.0, np.pi / 2, "rad"
        )
        self.n_orientations = checks.integer("n_orientations", n_orientations, 1)
        self.n_pad_offsets = checks.integer("n_pad_offsets", n_pad_offsets, 1)
        self.link_samples = checks.integer("link_samples", link_samples, 2)

    def tip_radius(self, finger: str) -> float:
        """Fingertip radius of a round tip (0 for a flat pad) [m]."""
        return self.hand.params.finger(finger).round_radius

    def roll_length(self, finger: str) -> float:
        """Longest rolling travel of a contact over the fingertip in one phase [m]: the arc
        ``2 r_f max_tip_contact_angle`` of a round tip, the width of a flat pad."""
        f = self.hand.params.finger(finger)
        if f.tip == "round":
            return 2.0 * f.tip_radius * self.max_tip_contact_angle
        return 2.0 * f.pad_half_width

    def reachable(self, finger: str, contacts, normals, inside) -> np.ndarray:
        """See :meth:`ReachabilityModel.reachable`."""
        from robots.planar_hand.kinematics import finger_points

        checks.choice("finger", finger, self.fingers)
        f = self.hand.params.finger(finger)
        c_all = np.asarray(contacts, dtype=float)
        u_all = np.asarray(normals, dtype=float)
        # contacts whose fingertip point is beyond the finger's reach cannot be touched
        pad = f.tip_radius if f.tip == "round" else f.pad_half_width
        near = np.linalg.norm(c_all - np.asarray(f.base), axis=1) <= sum(f.lengths) + pad
        sel = np.nonzero(near)[0]
        out = np.zeros(c_all.shape[0], dtype=bool)
        if sel.size == 0:
            return out
        c, u = c_all[sel], u_all[sel]
        m = c.shape[0]
        phi0 = np.arctan2(u[:, 1], u[:, 0]) + np.pi / 2  # fingertip axis along -u
        if f.tip == "round":
            k = self.n_orientations
            a = self.max_tip_contact_angle
            dphi = np.linspace(-a, a, k) if k > 1 else np.zeros(1)
            phi = phi0[:, None] + dphi[None, :]
            targets = np.broadcast_to((c + f.tip_radius * u)[:, None, :], (m, k, 2))
        else:
            k = self.n_pad_offsets
            w = f.pad_half_width
            s = np.linspace(-w, w, k) if k > 1 else np.zeros(1)
            t = np.stack([-u[:, 1], u[:, 0]], axis=-1)
            targets = c[:, None, :] - s[None, :, None] * t[:, None, :]
            phi = np.broadcast_to(phi0[:, None], (m, k))
        # wrist (joint 3) must lie in the annulus reachable by links 1-2: cheap prefilter
        tg, ph = targets.reshape(-1, 2), phi.reshape(-1)
        l1, l2, l3 = (float(v) for v in f.lengths)
        wx = tg[:, 0] + l3 * np.sin(ph) - f.base[0]
        wy = tg[:, 1] - l3 * np.cos(ph) - f.base[1]
        r2 = wx * wx + wy * wy
        cand = np.nonzero((r2 <= (l1 + l2) ** 2 + 1e-12) & (r2 >= (l1 - l2) ** 2 - 1e-12))[0]
        q = np.zeros((tg.shape[0], 2, 3))
        ok = np.zeros((tg.shape[0], 2), dtype=bool)
        if cand.size:
            q[cand], ok[cand] = self.hand.ik_candidates(finger, tg[cand], ph[cand])
        q = q.reshape(m, k * 2, 3)
        ok = ok.reshape(m, k * 2)
        rows, cols = np.nonzero(ok)  # check collisions only where IK succeeded
        if rows.size == 0:  # nothing reachable (e.g. an object larger than the workspace)
            return out
        pts = finger_points(np.array(f.base), np.array(f.lengths), q[rows, cols])  # (L, 4, 2)
        good = np.all(pts[:, 1:, 1] >= -1e-9, axis=-1)
        if f.tip == "round":
            good &= pts[:, 3, 1] >= f.tip_radius - 1e-9
        # points along the links (tip point excluded: it touches the object by design)
        lam = np.linspace(0.0, 1.0, self.link_samples, endpoint=False)
        seg = pts[:, :-1, None, :] + lam[:, None] * (pts[:, 1:, None, :] - pts[:, :-1, None, :])
        good &= ~inside(seg.reshape(len(rows), -1, 2), sel[rows]).any(axis=-1)
        out[sel[rows[good]]] = True
        return out


@dataclass(frozen=True)
class WorkspaceTables:
    """Reachability of every contact angle for every object rotation on the palm.

    Attributes:
        theta: (n,) contact angles in the object frame [rad].
        placement: the K object poses (rotations ``placement.angles``).
        reachable: finger -> (K, n) bool, ``[k, i]``: the finger reaches ``theta[i]`` when
            the object has rotation ``placement.angles[k]``.
        palm_index: (K,) index in ``theta`` of the palm contact (-1 when off the palm).
    """

    theta: np.ndarray
    placement: Placement
    reachable: dict[str, np.ndarray]
    palm_index: np.ndarray


def workspace_tables(
    profile, reach: ReachabilityModel, theta, angles, x0: float = 0.0
) -> WorkspaceTables:
    """Reachability of the contact angles ``theta`` (n,) for the object rotations ``angles`` (K,).

    Args:
        profile: closed star-shaped profile (object frame) [m].
        reach: the hand's :class:`ReachabilityModel`.
        theta: (n,) contact angles [rad] (a uniform grid ``2π i / n``).
        angles: (K,) object rotations φ [rad] (counter-clockwise).
        x0: x position of the object origin in the hand frame [m].
    """
    if not isinstance(reach, ReachabilityModel):
        raise InvalidParameter(
            "hand: expected a robots.planar_hand.PlanarHand or a "
            f"planner.grasp.workspace.ReachabilityModel, got {type(reach).__name__}"
        )
    theta = np.asarray(theta, dtype=float)
    place = rest_on_palm(profile, angles, x0, reach.palm_half_width)
    radial = RadialFunction(profile)
    pts, nin = profile_contacts(profile, theta)
    R = rotation(place.angles)  # (K, 2, 2)
    cw = np.einsum("kab,nb->kna", R, pts) + place.offsets[:, None, :]  # (K, n, 2)
    uw = -np.einsum("kab,nb->kna", R, nin)
    K, n = cw.shape[:2]
    k_of_row = np.repeat(np.arange(K), n)
    cos_k, sin_k = np.cos(place.angles), np.sin(place.angles)

    def inside(points: np.ndarray, rows: np.ndarray) -> np.ndarray:
        # points (L, P, 2) in the hand frame -> object frame of each row's pose
        kk = k_of_row[rows]
        rx = points[..., 0] - place.offsets[kk, 0][:, None]
        ry = points[..., 1] - place.offsets[kk, 1][:, None]
        c, s = cos_k[kk][:, None], sin_k[kk][:, None]
        obj = np.stack([c * rx + s * ry, c * ry - s * rx], axis=-1)  # R^T (x - t)
        return radial.inside(obj)

    table = {
        f: reach.reachable(f, cw.reshape(-1, 2), uw.reshape(-1, 2), inside).reshape(K, n)
        for f in reach.fingers
    }
    step = 2 * np.pi / n
    idx = np.where(
        np.isfinite(place.palm_theta),
        np.mod(np.rint(np.nan_to_num(place.palm_theta) / step), n),
        -1,
    ).astype(int)
    return WorkspaceTables(theta, place, table, idx)


def as_reachability(hand) -> ReachabilityModel:
    """A :class:`ReachabilityModel` from a ``PlanarHand`` (wrapped) or a model (as is)."""
    if isinstance(hand, ReachabilityModel):
        return hand
    if hand is None or hasattr(hand, "ik_candidates"):
        return HandReachability(hand)
    raise InvalidParameter(
        f"hand: expected a PlanarHand or a ReachabilityModel, got {type(hand).__name__}"
    )


def workspace_map(
    profile, hand=None, resolution: int = 360, *, angle: float = 0.0, x0: float = 0.0
) -> WorkspaceTables:
    """The workspace map of Fig. 2.4 for one object pose (rotation ``angle`` on the palm).

    Args:
        profile: closed star-shaped profile [m].
        hand: ``PlanarHand`` or :class:`ReachabilityModel` (default ``PlanarHand()``).
        resolution: contact angles ``2π i / resolution``.
        angle: object rotation φ [rad]; x0: object origin x [m].

    Returns:
        :class:`WorkspaceTables` with K = 1 (``reachable[f][0]`` is the finger's map).
    """
    return workspace_tables(
        profile, as_reachability(hand), contact_angles(resolution), [float(angle)], x0
    )


__all__ = [
    "PAIRS",
    "HandReachability",
    "Placement",
    "RadialFunction",
    "ReachabilityModel",
    "WorkspaceTables",
    "as_reachability",
    "rest_on_palm",
    "rotation",
    "workspace_map",
    "workspace_tables",
]
