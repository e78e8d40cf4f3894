"""How far the hand can pivot a polygonal object about its palm corner (§2.3.1, Fig. 2.12).

A sharp-cornered object turned clockwise on the palm does not roll: it pivots about the
rightmost of its lowest corners (the palm contact), so every point of it moves on a circle
about that corner:

.. math:: p(\\theta) = k + R(\\theta)\\,(p_0 - k)

(``k`` the corner, ``theta`` <= 0 the object's rotation, clockwise). The fingers follow:

* the flat left pad sticks to its face (a flat pad on a flat face cannot roll, sliding needs
  the friction overcome): its centre moves on the circle above and its orientation turns
  with the object, ``phi_L = phi_L0 + theta``;
* the round right tip rolls on its face: with ``d`` the contact's distance along the face
  (tangent ``e = R(+90 deg) m``, ``m`` the outward normal) and ``psi = phi_R - theta`` the
  tip's orientation relative to the face, pure rolling is ``d = d_0 + r (psi - psi_0)``
  (the disc's contact point is at rest: ``d' e - r psi' (z x m) = 0``, ``z x m = e``); its
  centre is ``T = A(theta) + d e(theta) + r m(theta)``.

The right tip's relative orientation ``psi`` is free (the hand's third degree of freedom):
:func:`tip_rolling_path` finds, by dynamic programming over a grid of ``(theta, psi)``, the
path that turns the object furthest while every configuration keeps its joints a margin
inside their limits, the tip disc above the palm and the finger's links clear of the object
(the simulator does not collide links, a real hand does). :func:`pad_reach` does the same
for the sticking pad. These are the kinematic bounds of one phase 1; the executor uses them
(:mod:`.pivot_planning`), :mod:`.pivot_grasps` asks which stable grasps remain along a pivot.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.grasp.workspace import rotation  # (2, 2) of an angle [rad], exported

#: a joint must stay this far inside its limits along a pivot [rad] (the executor's
#: workspace event fires at ``joint_margin`` = 0.03 rad; the phase-1 NLP keeps 0.05)
JOINT_MARGIN = 0.05
#: the finger's links keep this far outside the object [m]
LINK_CLEARANCE = 0.004
#: the round contact keeps this far from a face's ends [m]
FACE_END = 0.003
#: the palm corner is the lowest vertex with the object tipped clockwise by atan of this
#: [-] (5 deg: more than a posed face's tilt error, 1.4 deg)
PIVOT_SLOPE = math.tan(math.radians(5.0))


def palm_corner(W) -> np.ndarray:
    """(2,) the corner a clockwise turn pivots about: the vertex of the world polygon ``W``
    (M, 2) [m] lowest after the object is tipped clockwise by ``atan(PIVOT_SLOPE)``
    (minimum of ``y - PIVOT_SLOPE x``): of a face resting on the palm its right end, even
    when the posed face is tilted a little or sampled every millimetre; of an object
    standing on a corner that corner."""
    W = checks.points("W", W, dims=(2,), min_count=3)
    return W[int(np.argmin(W[:, 1] - PIVOT_SLOPE * W[:, 0]))].copy()


#: a palm corner whose outline turns by more than this over :data:`SHARP_SPAN` is sharp [rad]
SHARP_TURN = math.radians(45.0)
#: arclength on each side of the corner over which its turn is measured [m]
SHARP_SPAN = 2e-3


def is_sharp(W, corner) -> bool:
    """Whether the polygon ``W`` (M, 2) [m] turns by more than :data:`SHARP_TURN` within
    :data:`SHARP_SPAN` of its vertex ``corner`` (2,): a pivot there, not a rolling corner
    (a rounded corner of radius rho turns by ``2 SHARP_SPAN / rho`` there)."""
    W = np.asarray(W, float)
    i = int(np.argmin(np.linalg.norm(W - np.asarray(corner, float), axis=1)))
    P = W[i]
    d = np.linalg.norm(W - P, axis=1)
    n = len(W)
    j, k = (i - 1) % n, (i + 1) % n
    while d[j] < SHARP_SPAN and j != i:
        j = (j - 1) % n
    while d[k] < SHARP_SPAN and k != i:
        k = (k + 1) % n
    a, b = P - W[j], W[k] - P
    cos = float(a @ b) / max(float(np.linalg.norm(a) * np.linalg.norm(b)), 1e-15)
    return math.acos(max(-1.0, min(1.0, cos))) > SHARP_TURN


def pivoted(points, corner, theta: float) -> np.ndarray:
    """``points`` (..., 2) [m] after the object turned by ``theta`` [rad] about ``corner``
    (2,) [m]: ``k + R(theta) (p - k)``."""
    k = np.asarray(corner, float)
    return k + (np.asarray(points, float) - k) @ rotation(theta).T


@dataclass(frozen=True)
class Face:
    """A straight face of the object at the phase start (world frame).

    Attributes:
        start: (2,) the face end ``d = 0`` is measured from [m].
        normal: (2,) unit outward normal ``m``; the tangent is ``e = R(+90 deg) m``.
        length: the face's length along ``e`` [m] (it runs from ``d = 0`` to ``length``).
    """

    start: np.ndarray
    normal: np.ndarray
    length: float

    @classmethod
    def between(cls, a, b, inside) -> Face:
        """The face from ``a`` to ``b`` (2,) [m], its normal pointing away from ``inside``
        (2,), ``start`` the end from which ``e`` runs along the face."""
        a, b = np.asarray(a, float), np.asarray(b, float)
        t = (b - a) / np.linalg.norm(b - a)
        m = np.array([t[1], -t[0]])
        if m @ (a - np.asarray(inside, float)) < 0:
            m = -m
        e = np.array([-m[1], m[0]])
        start = a if e @ (b - a) > 0 else b
        return cls(start, m, float(np.linalg.norm(b - a)))

    @property
    def tangent(self) -> np.ndarray:
        """(2,) unit tangent ``e = R(+90 deg) m``."""
        return np.array([-self.normal[1], self.normal[0]])

    @property
    def end(self) -> np.ndarray:
        """(2,) the face's far end ``start + length e`` [m]."""
        return self.start + self.length * self.tangent

    def tip_centre(self, corner, theta, d, r: float) -> np.ndarray:
        """(..., 2) centre [m] of a round tip of radius ``r`` touching the face at distance
        ``d`` [m] after the object turned by ``theta`` [rad] about ``corner``
        (broadcast over ``theta`` and ``d``)."""
        th = np.asarray(theta, float)[..., None]
        c, s = np.cos(th), np.sin(th)
        m, e = self.normal, self.tangent
        mt = np.concatenate([c * m[0] - s * m[1], s * m[0] + c * m[1]], axis=-1)
        et = np.concatenate([c * e[0] - s * e[1], s * e[0] + c * e[1]], axis=-1)
        a0 = self.start - np.asarray(corner, float)
        at = np.asarray(corner, float) + np.concatenate(
            [c * a0[0] - s * a0[1], s * a0[0] + c * a0[1]], axis=-1
        )
        return at + np.asarray(d, float)[..., None] * et + r * mt


@dataclass(frozen=True)
class RollingPath:
    """The right tip's path along a pivot (knots ``k = 0 .. K``).

    Attributes:
        theta: (K+1,) object rotation [rad] (0, then decreasing: clockwise).
        d: (K+1,) contact distance along the face [m].
        phi: (K+1,) tip orientation ``q1 + q2 + q3`` [rad].
        q: (K+1, 3) the finger's joint angles [rad].
        margin: (K+1,) smallest joint-limit margin [rad].
    """

    theta: np.ndarray
    d: np.ndarray
    phi: np.ndarray
    q: np.ndarray
    margin: np.ndarray

    @property
    def reach(self) -> float:
        """How far the object turns along the path [rad] (>= 0)."""
        return float(-self.theta[-1]) + 0.0  # never -0.0


class HullClearance:
    """Signed distance [m] of points from the object's convex hull (> 0 outside: the
    largest of the hull's half-plane distances, exact inside and a lower bound outside)."""

    def __init__(self, W: np.ndarray) -> None:
        from scipy.spatial import ConvexHull

        eq = ConvexHull(W).equations  # rows (nx, ny, c): n . x + c <= 0 inside
        self.n, self.c = np.ascontiguousarray(eq[:, :2]), np.ascontiguousarray(eq[:, 2])

    def of(self, P: np.ndarray, corner, theta: float) -> np.ndarray:
        """Distances of ``P`` (..., 2) from the hull turned by ``theta`` about ``corner``."""
        back = pivoted(P, corner, -theta)
        return (back @ self.n.T + self.c).max(axis=-1)


def finger_configurations(
    hand, finger: str, T, phi, clear: HullClearance, corner, theta, margin, clr
):
    """The configurations of ``finger`` with its fingertip point at ``T`` (M, 2) [m] and
    orientation ``phi`` (M,) [rad], the object turned by ``theta`` [rad] about ``corner``
    (2,) [m]: joint angles (M, 3) [rad] of the elbow branch with the largest margin, that
    smallest joint-limit margin (M,) [rad], and whether it is feasible (M,): inside the
    limits by ``margin`` [rad], joints and link midpoints ``clr`` [m] outside the object
    (``clear``). Compiled (:mod:`.pivot_reach_kernel`); equal to
    :func:`finger_configurations_reference` to rounding."""
    from planner.exploration.planar.pivot_reach_kernel import configurations

    f = hand.params.finger(finger)
    T = np.ascontiguousarray(T, dtype=float).reshape(-1, 2)
    phi = np.ascontiguousarray(np.broadcast_to(np.asarray(phi, float), (len(T),)))
    M = len(T)
    q, m, ok = np.empty((M, 3)), np.empty(M), np.empty(M, dtype=np.bool_)
    configurations(np.asarray(f.base, float), np.asarray(f.lengths, float),
                   np.ascontiguousarray(hand.finger_limits(finger), dtype=float), T, phi,
                   clear.n, clear.c, np.asarray(corner, float), float(theta), float(margin),
                   float(clr), q, m, ok)  # fmt: skip
    return q, m, ok


def finger_configurations_reference(
    hand, finger: str, T, phi, clear: HullClearance, corner, theta, margin, clr
):
    """:func:`finger_configurations` in numpy (the reference its kernel is tested
    against)."""
    from robots.planar_hand import kinematics as kin

    lim = hand.finger_limits(finger)
    f = hand.params.finger(finger)
    sols, ok = hand.ik_candidates(finger, T, phi)
    m = np.minimum(sols - lim[:, 0], lim[:, 1] - sols).min(axis=-1)
    ok = ok & (m >= margin)
    for b in range(sols.shape[1]):
        pts = kin.finger_points(np.array(f.base), np.array(f.lengths), sols[:, b])
        # joints 1-3 and the link midpoints (the fingertip itself touches the object)
        probe = np.concatenate([pts[:, :3], 0.5 * (pts[:, :-1] + pts[:, 1:])], axis=1)
        ok[:, b] &= clear.of(probe, corner, theta).min(axis=1) >= clr
    best = np.argmax(np.where(ok, m, -np.inf), axis=1)
    idx = np.arange(len(T))
    return sols[idx, best], m[idx, best], ok[idx, best]


def tip_rolling_path(
    hand,
    W,
    face: Face,
    d0: float,
    phi0: float,
    *,
    max_turn: float = math.radians(60.0),
    step: float = math.radians(1.0),
    psi_span: float = math.radians(90.0),
    psi_step: float = math.radians(2.0),
    max_rate: float = 3.0,
    margin: float = JOINT_MARGIN,
    clearance: float = LINK_CLEARANCE,
    start_margin: float | None = None,
) -> RollingPath:
    """The right tip's rolling path that pivots the object (world polygon ``W`` (M, 2) [m]
    at the phase start) furthest about its palm corner (module docstring).

    Args:
        face: the face the tip rolls on; d0: the contact's start distance along it [m];
            phi0: the tip's start orientation [rad].
        max_turn: largest rotation searched [rad]; step: rotation per knot [rad].
        psi_span, psi_step: grid of the relative orientation ``psi`` about its start [rad].
        max_rate: largest change of ``psi`` per unit of rotation [-] (rolling speed).
        margin: joint-limit margin [rad]; clearance: link clearance [m].
        start_margin: the start's joint-limit margin [rad] (default ``margin``; the
            executor passes 0: the start is where the finger is, the path must only not
            go nearer to a limit than ``margin``) - its link clearance is then not
            checked either.

    Returns:
        the :class:`RollingPath` (just the start when even it is infeasible: reach 0).
    """
    W = checks.points("W", W, dims=(2,), min_count=3)
    checks.positive("step", step, "rad")
    r = float(hand.params.right.tip_radius)
    k = palm_corner(W)
    clear = HullClearance(W)
    n = int(round(psi_span / psi_step))
    dpsi = np.arange(-n, n + 1) * psi_step  # psi - psi0
    jump = max(1, int(math.floor(max_rate * step / psi_step)))
    d = d0 + r * dpsi
    on_face = (d >= FACE_END) & (d <= face.length - FACE_END)
    thetas = -np.arange(0.0, max_turn + 1e-12, step)
    value = np.full(dpsi.size, -np.inf)
    rows, back = [], []
    first = (margin, clearance) if start_margin is None else (start_margin, -math.inf)
    for i, th in enumerate(thetas):
        T = face.tip_centre(k, th, d, r)
        mg, cl = first if i == 0 else (margin, clearance)
        q, m, ok = finger_configurations(hand, "right", T, phi0 + dpsi + th, clear, k, th, mg, cl)
        ok &= on_face & (T[:, 1] >= r)
        m = np.where(ok, m, -np.inf)
        if i == 0:
            new = np.where(dpsi == 0.0, m, -np.inf)
            arg = np.arange(dpsi.size)
        else:
            # best predecessor within ``jump`` cells (max-min of the margins)
            shifted = np.stack([np.roll(value, s) for s in range(-jump, jump + 1)])
            for s in range(-jump, jump + 1):  # no wrap-around
                if s > 0:
                    shifted[s + jump, :s] = -np.inf
                elif s < 0:
                    shifted[s + jump, s:] = -np.inf
            j = np.argmax(shifted, axis=0)
            arg = np.arange(dpsi.size) - (j - jump)
            new = np.minimum(shifted[j, np.arange(dpsi.size)], m)
        if not np.isfinite(new).any():
            break
        value = new
        rows.append((q, m))
        back.append(arg)
    if not rows:
        return RollingPath(np.zeros(1), np.array([d0]), np.array([phi0]),
                           np.full((1, 3), np.nan), np.array([-np.inf]))  # fmt: skip
    j = int(np.argmax(value))
    path = []
    for i in range(len(rows) - 1, -1, -1):
        path.append(j)
        j = int(back[i][j])
    path.reverse()
    idx = np.array(path)
    K = len(rows)
    return RollingPath(
        theta=thetas[:K].copy(),
        d=d[idx],
        phi=phi0 + dpsi[idx] + thetas[:K],
        q=np.array([rows[i][0][idx[i]] for i in range(K)]),
        margin=np.array([rows[i][1][idx[i]] for i in range(K)]),
    )


def pad_reach(
    hand,
    W,
    pad_centre,
    pad_phi: float,
    *,
    max_turn: float = math.radians(60.0),
    step: float = math.radians(1.0),
    margin: float = JOINT_MARGIN,
    clearance: float = LINK_CLEARANCE,
    start_margin: float | None = None,
) -> tuple[float, np.ndarray]:
    """How far [rad] the left pad, stuck to its face at ``pad_centre`` (2,) [m] with the
    orientation ``pad_phi`` [rad], follows a pivot of the object (world polygon ``W``)
    about its palm corner within its joint limits (``margin``; ``start_margin`` at the
    start, as in :func:`tip_rolling_path`) and with its links clear; and its joint angles
    (K+1, 3) [rad] at the knots ``0, -step, ...``."""
    W = checks.points("W", W, dims=(2,), min_count=3)
    k = palm_corner(W)
    clear = HullClearance(W)
    thetas = -np.arange(0.0, max_turn + 1e-12, step)
    P = pivoted(np.asarray(pad_centre, float)[None], k, 0.0)
    qs = []
    first = (margin, clearance) if start_margin is None else (start_margin, -math.inf)
    for i, th in enumerate(thetas):
        T = pivoted(P, k, th)
        mg, cl = first if i == 0 else (margin, clearance)
        q, _, ok = finger_configurations(
            hand, "left", T, np.array([pad_phi + th]), clear, k, th, mg, cl
        )
        if not ok[0]:
            break
        qs.append(q[0])
    if not qs:
        return 0.0, np.zeros((0, 3))
    return float(-thetas[len(qs) - 1]), np.array(qs)


__all__ = [
    "FACE_END",
    "JOINT_MARGIN",
    "LINK_CLEARANCE",
    "Face",
    "HullClearance",
    "RollingPath",
    "finger_configurations",
    "finger_configurations_reference",
    "is_sharp",
    "pad_reach",
    "palm_corner",
    "pivoted",
    "rotation",
    "tip_rolling_path",
]
