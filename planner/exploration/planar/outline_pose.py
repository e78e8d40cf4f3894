"""Pose of the planner's known outline from what the hand senses (§2.2.3, §2.3.1).

The thesis plans each phase "using a current estimate of the object curvature and surface
orientation", and its §2.3.1 simulation "modeled the grasp kinematics" of the square it
rotated. The executor's per-step estimate (:mod:`.sensing`) is a circle: on a sharp square it
is 7-35 mm off. This module poses the nominal outline (a polygon in the object frame) by a
small least-squares fit of its pose ``(x, y, theta)`` [m, m, rad] to the sensed constraints:

* the flat left pad (encoders: a point ``t_L`` of its surface and its angle ``phi_L``) is a
  supporting line of the object: ``h(n_L) = n_L . t_L`` with ``n_L = (sin phi, -cos phi)``
  the object's outward normal there and ``h`` the posed outline's support function;
* the tactile centroid ``u`` is the middle of the support set's part on the pad (a corner:
  the corner itself; a face: the overlap of the face with the pad), weighted
  :data:`U_WEIGHT`;
* the round right tip (centre ``T`` from the encoders, radius ``r``) touches the outline:
  ``dist(T, outline) = r``;
* the palm: the object rests on ``y = 0``: ``min y = 0``;
* a prior on the rotation (the rolling-integrated estimate), weighted: with the pad flat on
  a face the face's distance is all the pad gives, and the rotation is then fixed by the
  tip and the palm only up to the outline's symmetry.

Each constraint is one residual [m] (the rotation prior is scaled to metres by its weight),
so three sensed constraints determine the pose of a generic grasp exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.exploration.planar.outline_pose_kernel import BESIDE_TIE
from planner.grasp.workspace import rotation

#: points of the outline within this of the support value lie on the pad [m] (the tactile
#: array sees a face as flat when its ends are this close to the pad)
FLAT_TOL = 3e-4
#: weight of the tactile-centroid residual [-]: the centroid is a pressure average (a corner
#: pressed into the rubber beside a face read 7.9 mm where the corner was); at full weight
#: one fit in two on the 11 cm square was rejected or 7-17 mm / 14-17 deg off, at 0.3 all
#: were within 1.3 mm / 1.4 deg of the simulator's truth (seed 0, first 4 s)
U_WEIGHT = 0.3


@dataclass(frozen=True)
class Outline:
    """A closed polygonal outline in the object frame.

    Attributes:
        points: (M, 2) vertices [m], in order (either orientation), not repeated at the end.
    """

    points: np.ndarray

    def __post_init__(self) -> None:
        pts = checks.points("points", self.points, dims=(2,), min_count=3)
        object.__setattr__(self, "points", np.ascontiguousarray(pts, dtype=float))

    @classmethod
    def from_profile(cls, profile, spacing: float = 1e-3) -> Outline:
        """The outline of a closed ``planner.geometry.profiles.Profile`` sampled every
        ``spacing`` [m] (piece ends kept, so a polygon's corners are exact)."""
        pts = np.asarray(profile.sample(spacing).points, dtype=float)
        keep = np.r_[True, np.linalg.norm(np.diff(pts, axis=0), axis=1) > 1e-9]
        pts = pts[keep]
        if np.linalg.norm(pts[-1] - pts[0]) < 1e-9:
            pts = pts[:-1]
        return cls(pts)

    def centroid(self) -> np.ndarray:
        """(2,) the area centroid of the polygon [m] (not the vertices' mean: a sampled
        outline's vertices are not evenly spread)."""
        P, Q = self.points, np.roll(self.points, -1, axis=0)
        cross = P[:, 0] * Q[:, 1] - Q[:, 0] * P[:, 1]
        return ((P + Q) * cross[:, None]).sum(axis=0) / (3.0 * cross.sum())

    def simplified(self, tol: float = 1e-9) -> Outline:
        """The same polygon without its collinear vertices (those within ``tol`` [m] of the
        line through their neighbours): a sharp square sampled every millimetre keeps its
        4 corners, so the global pose search (:func:`fit_pose_global`) evaluates the same
        residuals about 60 times faster."""
        P = self.points
        keep = np.ones(len(P), bool)
        for i in range(len(P)):
            a, b = P[i - 1], P[(i + 1) % len(P)]
            ab = b - a
            n = float(np.hypot(*ab))
            d = abs(ab[0] * (P[i, 1] - a[1]) - ab[1] * (P[i, 0] - a[0])) / max(n, 1e-300)
            keep[i] = d > tol
        if keep.sum() < 3:
            return self
        return Outline(P[keep])

    def roundness(self) -> float:
        """``(max - min) / mean`` of the vertices' distances from the centroid [-] (0 for
        a circle)."""
        d = np.linalg.norm(self.points - self.points.mean(axis=0), axis=1)
        return float((d.max() - d.min()) / d.mean())

    def posed(self, pose) -> np.ndarray:
        """(M, 2) world vertices [m] at ``pose = (x, y, theta)``."""
        x, y, a = (float(v) for v in pose)
        c, s = math.cos(a), math.sin(a)
        P = self.points
        return np.column_stack([x + c * P[:, 0] - s * P[:, 1], y + s * P[:, 0] + c * P[:, 1]])

    def hull(self, count: int) -> np.ndarray:
        """At most ``count`` points of the outline's convex hull (object frame) [m]: the
        hull's vertices, thinned evenly when there are more (for the NLP's palm clearance)."""
        from scipy.spatial import ConvexHull

        h = self.points[ConvexHull(self.points).vertices]
        if len(h) <= count:
            return h
        return h[np.linspace(0, len(h), count, endpoint=False).astype(int)]


def clip_halfplane(P: np.ndarray, a, b: float) -> np.ndarray:
    """The part ``a . x <= b`` of the closed polygon ``P`` (M, 2) (Sutherland-Hodgman
    against one line; convex input gives convex output; may be empty)."""
    Q = np.roll(P, -1, axis=0)
    sp, sq = P @ a - b, Q @ a - b
    inside = sp <= 0.0
    cross = (sp <= 0.0) != (sq <= 0.0)
    w = sp / np.where(cross, sp - sq, 1.0)
    X = P + w[:, None] * (Q - P)
    cand = np.stack([P, X], axis=1)  # (M, 2, 2): the vertex, then the crossing after it
    keep = np.stack([inside, cross], axis=1)
    return cand[keep]


def pad_window(W: np.ndarray, point, tdir, half_width: float) -> np.ndarray:
    """The part of the polygon ``W`` within the pad's strip: ``|t . (x - point)| <= w``."""
    p = np.asarray(point, float)
    Wc = clip_halfplane(W, tdir, float(tdir @ p) + half_width)
    if len(Wc) == 0:
        return Wc
    return clip_halfplane(Wc, -tdir, -float(tdir @ p) + half_width)


def nearest_on_polygon(W: np.ndarray, point) -> tuple[np.ndarray, float]:
    """The point of the closed polygon ``W`` (M, 2) nearest to ``point`` and its distance
    [m] (exact, over the M segments)."""
    p = np.asarray(point, float)
    A, B = W, np.roll(W, -1, axis=0)
    AB = B - A
    t = np.clip(np.einsum("ij,ij->i", p - A, AB) / np.maximum(np.einsum("ij,ij->i", AB, AB),
                                                               1e-300), 0.0, 1.0)  # fmt: skip
    Q = A + t[:, None] * AB
    d = np.hypot(Q[:, 0] - p[0], Q[:, 1] - p[1])
    k = int(np.argmin(d))
    return Q[k], float(d[k])


@dataclass(frozen=True)
class Readings:
    """The sensed constraints of one instant (None/NaN: not sensed).

    Attributes:
        pad_point: (2,) a point of the left pad's surface (its centre) [m] or None.
        pad_angle: the pad's orientation ``phi_L`` [rad] (direction ``(cos, sin)``).
        pad_u: tactile centroid along the pad from ``pad_point`` [m] (NaN: not used).
        pad_half_width: half-width of the pad [m]: the pad touches the outline within it
            (a corner beyond its edge touches the pad's edge).
        pad_u_max: largest tactile centroid [m] (the outermost taxel centre: a contact at the
            pad's edge reads this).
        tip_centre: (2,) centre of the round right tip [m] or None; tip_radius [m].
        palm: the object rests on the palm (``min y = 0``).
    """

    pad_point: np.ndarray | None = None
    pad_angle: float = 0.0
    pad_u: float = float("nan")
    pad_half_width: float = 0.01
    pad_u_max: float = 0.01
    tip_centre: np.ndarray | None = None
    tip_radius: float = 0.0
    palm: bool = True


def residuals(outline: Outline, pose, rd: Readings, theta_prior=None, theta_weight=0.0):
    """The constraint residuals [m] of ``pose`` (module docstring), in the order pad line,
    pad centroid, tip, palm, rotation prior (the unsensed ones left out); compiled
    (:mod:`.outline_pose_kernel`), equal to :func:`residuals_reference` to rounding."""
    return _Residuals(outline, rd, theta_prior, theta_weight)(pose)


class _Residuals:
    """``pose -> residuals`` of one outline and reading (the reading packed once; the
    function a least-squares fit calls)."""

    def __init__(self, outline: Outline, rd: Readings, theta_prior, theta_weight) -> None:
        from planner.exploration.planar import outline_pose_kernel as K

        self._kernel, self._jacobian = K.residuals, K.jacobian
        self._P = outline.points
        self._rd = K.pack(rd, theta_prior, theta_weight, FLAT_TOL, U_WEIGHT)
        self._out = np.empty(5)
        self._J = np.empty((5, 3))

    def __call__(self, pose) -> np.ndarray:
        x, y, a = (float(v) for v in pose)
        k = self._kernel(self._P, x, y, a, self._rd, self._out)
        return self._out[:k].copy()

    def jacobian(self, pose) -> np.ndarray:
        """(k, 3) scipy's 3-point difference Jacobian of :meth:`__call__` at ``pose``
        (:func:`.outline_pose_kernel.jacobian`)."""
        k = self._jacobian(self._P, np.asarray(pose, float), self._rd, self._J)
        return self._J[:k].copy()


def residuals_reference(outline: Outline, pose, rd: Readings, theta_prior=None,
                        theta_weight=0.0):  # fmt: skip
    """:func:`residuals` in numpy (the reference its compiled kernel is tested against)."""
    W = outline.posed(pose)
    out = []
    if rd.pad_point is not None:
        c, s = math.cos(rd.pad_angle), math.sin(rd.pad_angle)
        n, tdir = np.array([s, -c]), np.array([c, s])
        Wp = pad_window(W, rd.pad_point, tdir, rd.pad_half_width)
        if len(Wp) == 0:  # the outline is beside the pad: its nearest corner to the strip
            d = np.abs((W - rd.pad_point) @ tdir)
            tied = W[d <= d.min() + BESIDE_TIE]  # of tied corners the highest
            Wp = tied[[int(np.argmax(tied @ n))]]
        h = Wp @ n
        hmax = float(h.max())
        out.append(hmax - float(n @ rd.pad_point))
        if math.isfinite(rd.pad_u):
            along = (Wp[h >= hmax - FLAT_TOL] - rd.pad_point) @ tdir
            mid = float(np.clip(0.5 * (along.min() + along.max()), -rd.pad_u_max, rd.pad_u_max))
            out.append(U_WEIGHT * (mid - rd.pad_u))
    if rd.tip_centre is not None:
        _, d = nearest_on_polygon(W, rd.tip_centre)
        out.append(d - rd.tip_radius)
    if rd.palm:
        out.append(float(W[:, 1].min()))
    if theta_prior is not None and theta_weight > 0:
        out.append(theta_weight * (float(pose[2]) - float(theta_prior)))
    return np.asarray(out, dtype=float)


@dataclass(frozen=True)
class PoseFit:
    """Result of :func:`fit_pose`: ``pose`` (3,) [m, m, rad], the residuals' norm [m] and
    whether the solver converged."""

    pose: np.ndarray
    cost: float
    success: bool


def fit_pose(
    outline: Outline,
    readings: Readings,
    guess,
    theta_prior: float | None = None,
    theta_weight: float = 0.0,
    max_step: float = 0.05,
) -> PoseFit:
    """The pose of ``outline`` best fitting ``readings`` (least squares, started at
    ``guess`` = (x, y, theta) [m, m, rad]; ``theta_weight`` [m/rad] scales the rotation
    prior; a pose farther than ``max_step`` [m, rad] from the guess is not a success)."""
    from scipy.optimize import least_squares

    g = checks.vector("guess", guess, 3)
    f = _Residuals(outline, readings, theta_prior, theta_weight)
    if len(f(g)) == 0:
        return PoseFit(g.copy(), 0.0, True)
    # central differences: the forward ones stalled 2e-7 rad short of an exact pose (and
    # so did bounds), the 3-point Jacobian converges to rounding in 5-6 evaluations (it is
    # scipy's "3-point" one, computed in one compiled call)
    sol = least_squares(f, g, method="trf", jac=f.jacobian,
                        x_scale=np.array([0.01, 0.01, 0.2]), xtol=1e-15, ftol=1e-15,
                        gtol=1e-15, max_nfev=200)  # fmt: skip
    x = np.asarray(sol.x, float)
    cost = float(np.linalg.norm(f(x)))
    near = bool(np.all(np.abs(x - g) <= max_step + 1e-12))
    return PoseFit(x, cost, bool(sol.status > 0) and near)


#: rotation step of the global search's starts [rad]
GLOBAL_STEP = math.radians(10.0)
#: fits whose sensed cost is within this of the best one are ties, broken by the rotation
#: prior modulo the outline's symmetry [m]
TIE_COST = 5e-4


def symmetry_order(outline: Outline, tol: float = 1e-4, max_order: int = 12) -> int:
    """The largest ``n <= max_order`` such that turning ``outline`` by ``2 pi / n`` about
    its area centroid maps it onto itself within ``tol`` [m] (1: no rotational symmetry;
    4 for a square, n for a regular n-gon)."""
    P = outline.points
    c = outline.centroid()
    for n in range(max_order, 1, -1):
        Q = c + (P - c) @ rotation(2 * math.pi / n).T
        if max(distances_to_polygon(P, Q)) <= tol:
            return n
    return 1


def distances_to_polygon(W: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(N,) distance [m] of each of ``points`` (N, 2) from the closed polygon ``W``."""
    return np.array([nearest_on_polygon(W, p)[1] for p in points])


def symmetric_pose(outline: Outline, pose, turns: int, order: int) -> np.ndarray:
    """The pose (3,) [m, m, rad] at which ``outline`` (of symmetry ``order``) covers the
    same world polygon as at ``pose``, its rotation ``turns * 2 pi / order`` larger: with
    ``c`` the centroid, ``X' = X + R(theta) c - R(theta + alpha) c``."""
    x, y, th = (float(v) for v in pose)
    a = 2 * math.pi * turns / order
    c = outline.centroid()
    X = np.array([x, y]) + rotation(th) @ c - rotation(th + a) @ c
    return np.array([X[0], X[1], th + a])


def start_position(outline: Outline, theta: float, rd: Readings, guess) -> np.ndarray:
    """A start pose at rotation ``theta`` [rad] for :func:`fit_pose`: the height that puts
    the outline on the palm (``min y = 0``, when ``rd.palm``) and the abscissa that puts
    its support on the pad's line (when the pad touches and its normal is not vertical);
    the ``guess`` (2,) [m] where a reading is missing."""
    P = outline.points @ rotation(theta).T
    x, y = float(guess[0]), float(guess[1])
    if rd.palm:
        y = -float(P[:, 1].min())
    if rd.pad_point is not None:
        n = np.array([math.sin(rd.pad_angle), -math.cos(rd.pad_angle)])
        if abs(n[0]) > 0.3:
            x = (float(n @ rd.pad_point) - float((P @ n).max()) - n[1] * y) / n[0]
    return np.array([x, y, theta])


def fit_pose_global(
    outline: Outline, readings: Readings, guess, theta_prior: float, order: int | None = None
) -> PoseFit:
    """The pose of ``outline`` best fitting ``readings`` from starts every
    :data:`GLOBAL_STEP` over one period of its symmetry (``order``, default
    :func:`symmetry_order`), each placed on the palm and the pad's line
    (:func:`start_position`), without a rotation prior: a rolling-integrated rotation was
    30 deg off after a square tipped over its corner, and its prior then held the fit 7-30
    mm off. The best sensed cost wins; fits within :data:`TIE_COST` of it are ties, broken
    by the rotation nearest ``theta_prior`` [rad] modulo the symmetry. The pose returned is
    the symmetric one nearest the prior (the same world polygon)."""
    g = checks.vector("guess", guess, 3)
    n = symmetry_order(outline) if order is None else int(order)
    outline = outline.simplified()
    period = 2 * math.pi / n
    starts = theta_prior + np.arange(-0.5 * period, 0.5 * period, GLOBAL_STEP)
    fits = []
    for th in starts:
        s = start_position(outline, float(th), readings, g[:2])
        f = fit_pose(outline, readings, s, max_step=math.inf)
        if f.success:
            fits.append(f)
    if not fits:
        return PoseFit(g.copy(), math.inf, False)
    best = min(f.cost for f in fits)

    def off(f):
        return abs(math.remainder(float(f.pose[2]) - theta_prior, period))

    pick = min((f for f in fits if f.cost <= best + TIE_COST), key=off)
    turns = round((theta_prior - float(pick.pose[2])) / period)
    return PoseFit(symmetric_pose(outline, pick.pose, turns, n), pick.cost, True)


def contacts(outline: Outline, pose, rd: Readings) -> dict:
    """The contacts of the posed outline [m]: ``pad`` (the support set's middle on the pad),
    ``tip`` (nearest point to the tip centre) with its outward normal ``tip_normal``, and
    ``palm`` (the middle of the lowest points)."""
    W = outline.posed(pose)
    out = {}
    if rd.pad_point is not None:
        c, s = math.cos(rd.pad_angle), math.sin(rd.pad_angle)
        n = np.array([s, -c])
        Wp = pad_window(W, rd.pad_point, np.array([c, s]), rd.pad_half_width)
        Wp = Wp if len(Wp) else W
        h = Wp @ n
        sup = Wp[h >= h.max() - FLAT_TOL]
        out["pad"] = 0.5 * (sup.min(axis=0) + sup.max(axis=0))
    if rd.tip_centre is not None:
        q, d = nearest_on_polygon(W, rd.tip_centre)
        out["tip"] = q
        out["tip_normal"] = (np.asarray(rd.tip_centre) - q) / max(d, 1e-12)
    low = W[W[:, 1] <= W[:, 1].min() + FLAT_TOL]
    out["palm"] = low.mean(axis=0)
    return out


__all__ = [
    "FLAT_TOL",
    "GLOBAL_STEP",
    "TIE_COST",
    "Outline",
    "PoseFit",
    "Readings",
    "contacts",
    "fit_pose",
    "fit_pose_global",
    "clip_halfplane",
    "nearest_on_polygon",
    "pad_window",
    "residuals",
    "residuals_reference",
    "start_position",
    "symmetric_pose",
    "symmetry_order",
]
