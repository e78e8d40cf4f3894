"""Exact contact geometry of catalogue profiles in their body frame (planar world).

An :class:`Outline` compiles a :class:`planner.geometry.profiles.Profile` into the features
the contact search needs, all in the body frame:

* **lines** ``(a, b)`` with their outward normal (left normal of travel);
* **arcs** (centre, radius, start angle, sweep); clockwise arcs are convex (material inside);
* **parametric** pieces (ellipses, Gaussian bumps, splines) with a sample table used only to
  start the root finders;
* **corners**: sharp convex joints (turn < 0), smooth joints of a line with a curved piece
  (a flat face tilted past its fillet touches there first) and the ends of open profiles.

Queries are exact: the closest point on a line or an arc is closed form; on a parametric
piece it is the root of ``g(u) = (c(u) - p) . c'(u)`` found by safeguarded Newton
(bisection fallback on a bracket around the nearest table sample) to machine precision; the
extremal point of a parametric piece along a direction solves ``c'(u) . n = 0`` the same way.
No curved outline is ever replaced by a polygon.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from planner.geometry.primitives import Arc, Line, Parametric
from planner.geometry.profiles import Profile

__all__ = ["Outline", "closest_point", "compile_outline"]

TWO_PI = 2.0 * math.pi
TABLE = 257  # samples per parametric piece used to seed the Newton iterations


@dataclass(frozen=True)
class ParamPiece:
    """A parametric piece with its seed table (body frame)."""

    piece: Parametric
    u: np.ndarray  # (TABLE,) parameters
    pts: np.ndarray  # (TABLE, 2) points [m]
    direction: float  # sign(u1 - u0): travel direction
    periodic: bool  # the piece closes on itself (an ellipse)

    def point(self, u: float) -> tuple[float, float]:
        p = self.piece.f(np.array([u]))[0]
        return float(p[0]), float(p[1])

    def derivs(self, u: float):
        uu = np.array([u])
        p = self.piece.f(uu)[0]
        d1 = self.piece.df(uu)[0]
        d2 = self.piece.ddf(uu)[0]
        return p, d1, d2

    def normal(self, d1: np.ndarray) -> tuple[float, float]:
        tx, ty = self.direction * d1[0], self.direction * d1[1]
        s = math.hypot(tx, ty)
        return -ty / s, tx / s

    def bracket(self, i: int) -> tuple[float, float]:
        lo = self.u[max(i - 1, 0)]
        hi = self.u[min(i + 1, len(self.u) - 1)]
        if self.periodic and (i == 0 or i == len(self.u) - 1):
            step = self.u[1] - self.u[0]
            lo, hi = self.u[i] - step, self.u[i] + step
        return (min(lo, hi), max(lo, hi))


@dataclass(frozen=True)
class Outline:
    """A profile compiled for contact queries (body frame).

    Attributes:
        lines: (nl, 6) rows ``ax, ay, bx, by, nx, ny`` [m], outward unit normal.
        arcs: (na, 6) rows ``cx, cy, r, phi0, sweep, convex`` [m, rad, flag].
        params: parametric pieces.
        corners: (nc, 2) sharp convex corners and open-profile ends [m].
        closed: whether the outline bounds a region.
        bound: radius of a circle about the body origin containing the outline [m].
        ends: an open outline's two end points ((x0, y0), (x1, y1)) [m]; () when closed.
        depth: how deep an open outline's body reaches behind its face [m]: a corner, an
            arc or a parametric piece whose gap to it is below ``-depth`` is beyond the body
            (through its back) and makes no contact. ``inf`` (the default, and always for a
            closed outline): a half-plane behind the face (a floor, the palm).
    """

    lines: np.ndarray
    arcs: np.ndarray
    params: tuple[ParamPiece, ...]
    corners: np.ndarray
    closed: bool
    bound: float
    profile: Profile
    line_list: tuple = ()
    arc_list: tuple = ()
    corner_list: tuple = ()
    ends: tuple = ()
    depth: float = math.inf


def compile_outline(profile: Profile, depth: float = math.inf) -> Outline:
    """Compile ``profile`` (in its own frame) for the contact queries; ``depth`` [m] > 0:
    how deep an open outline's body reaches behind its face (:class:`Outline`; a closed
    outline's is its interior)."""
    if not isinstance(profile, Profile):
        raise InvalidParameter(
            f"profile: expected a planner.geometry Profile, got {checks.shown(profile)}"
        )
    depth = checks.positive("depth", depth, "m", allow_inf=True)
    if profile.closed and depth != math.inf:
        raise InvalidParameter("depth: a closed outline's body is its interior (leave inf)")
    lines, arcs, params, corners = [], [], [], []
    for piece in profile.pieces:
        if isinstance(piece, Line):
            (ax, ay), (bx, by) = piece.p0, piece.p1
            L = math.hypot(bx - ax, by - ay)
            if L <= 0:
                continue
            lines.append((ax, ay, bx, by, -(by - ay) / L, (bx - ax) / L))
        elif isinstance(piece, Arc):
            arcs.append(
                (*piece.center, piece.radius, piece.phi0, piece.sweep, float(piece.sweep < 0))
            )
        elif isinstance(piece, Parametric):
            u = np.linspace(piece.u0, piece.u1, TABLE)
            pts = piece.f(u)
            periodic = bool(np.allclose(pts[0], pts[-1], atol=1e-12))
            params.append(ParamPiece(piece, u, pts, float(np.sign(piece.u1 - piece.u0)), periodic))
        else:  # pragma: no cover - Profile only holds these three
            raise InvalidParameter(f"unsupported piece {type(piece).__name__}")
    n = len(profile.pieces)
    turns = profile.joint_turns
    for i in range(n - 1 + int(profile.closed)):
        here, nxt = profile.pieces[i], profile.pieces[(i + 1) % n]
        smooth_to_line = turns[i] == 0 and (isinstance(here, Line) or isinstance(nxt, Line))
        if turns[i] < 0 or smooth_to_line:
            P, _, _ = here.evaluate(np.array([here.length]))
            corners.append(P[0])
    if not profile.closed:
        P0, _, _ = profile.pieces[0].evaluate(np.array([0.0]))
        P1, _, _ = profile.pieces[-1].evaluate(np.array([profile.pieces[-1].length]))
        corners += [P0[0], P1[0]]
    smp = profile.sample(profile.length / 2000.0).points
    L = np.array(lines, float).reshape(-1, 6)
    A = np.array(arcs, float).reshape(-1, 6)
    C = np.array(corners, float).reshape(-1, 2)
    return Outline(
        L,
        A,
        tuple(params),
        C,
        bool(profile.closed),
        float(np.max(np.hypot(smp[:, 0], smp[:, 1]))) * (1 + 1e-9) + 1e-12,
        profile,
        tuple(tuple(map(float, r)) for r in L),
        tuple(tuple(map(float, r)) for r in A),
        tuple(tuple(map(float, r)) for r in C),
        () if profile.closed else tuple(tuple(map(float, r)) for r in C[-2:]),
        float(depth),
    )


def _arc_contains(phi0: float, sweep: float, phi: float) -> bool:
    if abs(sweep) >= TWO_PI - 1e-15:
        return True
    d = (phi - phi0) % TWO_PI if sweep > 0 else (phi0 - phi) % TWO_PI
    return d <= abs(sweep) + 1e-12


def _newton(fun, u: float, lo: float, hi: float) -> float:
    """Root of ``fun(u) -> (g, dg)`` in [lo, hi]: Newton, bisection when it leaves the bracket."""
    glo, _ = fun(lo)
    for _ in range(60):
        g, dg = fun(u)
        if g == 0.0:
            return u
        if (g < 0) == (glo < 0):
            lo, glo = u, g
        else:
            hi = u
        step = g / dg if dg != 0.0 else 0.0
        un = u - step
        if dg != 0.0 and abs(step) <= 1e-15 * max(1.0, abs(u)):
            return un  # converged: the Newton step is below the resolution of u
        if not (lo < un < hi) or dg == 0.0:
            un = 0.5 * (lo + hi)
        if abs(un - u) <= 1e-15 * max(1.0, abs(u)):
            return un
        u = un
    return u


def _param_closest(pp: ParamPiece, px: float, py: float):
    """Closest point of a parametric piece to (px, py): (d2, qx, qy, nx, ny, interior)."""
    d2s = (pp.pts[:, 0] - px) ** 2 + (pp.pts[:, 1] - py) ** 2
    i = int(np.argmin(d2s))

    def g(u):
        p, d1, d2 = pp.derivs(u)
        rx, ry = p[0] - px, p[1] - py
        return rx * d1[0] + ry * d1[1], d1[0] ** 2 + d1[1] ** 2 + rx * d2[0] + ry * d2[1]

    lo, hi = pp.bracket(i)
    glo, ghi = g(lo)[0], g(hi)[0]
    if glo < 0 < ghi:
        u = _newton(g, float(pp.u[i]), lo, hi)
        interior = True
    else:  # the minimum is at a piece end (an open end or a joint)
        u = float(pp.u[i])
        interior = False
    p, d1, _ = pp.derivs(u)
    nx, ny = pp.normal(d1)
    return (p[0] - px) ** 2 + (p[1] - py) ** 2, float(p[0]), float(p[1]), nx, ny, interior


def closest_point(ol: Outline, px: float, py: float):
    """Signed distance from (px, py) to the outline, body frame.

    Returns:
        ``(d, qx, qy, nx, ny)``: signed distance [m] (< 0 inside the material), the closest
        point q and the unit normal n (outward; at a corner the direction q -> p) with
        ``p = q + d n``. An open outline (a pad, the palm) is a one-sided face: a point is
        behind it only within the slab of its pieces; when the closest point is one of its
        two ends the distance is unsigned (d >= 0, n from q to p) - signing it by the face
        normal would put every point of the half-plane behind the face "inside" (a phantom
        penetration of the pad's corner 9 cm behind the palm ended a gait run). A point more
        than ``ol.depth`` behind an open outline's face is beyond its body: ``d`` is ``inf``
        (no contact; see :data:`planner.sim.planar.hand.PAD_DEPTH`).

    At a corner (the closest point is where two pieces meet) the sign is that of
    ``(p - q) . (n_1 + n_2)``, the sum of the normals of every piece that ends there (the
    2-D angle-weighted pseudonormal, Baerentzen & Aanaes 2005): p is outside exactly when
    it is in front of the bisector. One piece's normal is not enough: a point in the normal
    cone of a corner sharper than 90 deg can be behind one of its two faces while outside
    (until 2026-11-25 the piece that won the distance tie by round-off signed it, so 1 in
    8 such points of a triangle came out 2 d deep: a "50 mm penetration" of a round
    fingertip touching a triangle's corner ended a gait as a simulator fault).
    """
    best = (math.inf, 0.0, 0.0, 0.0, 0.0, True, -math.inf, 0.0, 0.0)  # d2 q n inner sig nsum
    for ax, ay, bx, by, nx, ny in ol.line_list:
        ex, ey = bx - ax, by - ay
        t = ((px - ax) * ex + (py - ay) * ey) / (ex * ex + ey * ey)
        inner = 0.0 < t < 1.0
        t = min(max(t, 0.0), 1.0)
        qx, qy = ax + t * ex, ay + t * ey
        d2 = (px - qx) ** 2 + (py - qy) ** 2
        best = _keep(best, d2, qx, qy, nx, ny, inner, px, py)
    for cx, cy, r, phi0, sweep, convex in ol.arc_list:
        phi = math.atan2(py - cy, px - cx)
        if _arc_contains(phi0, sweep, phi):
            ux, uy = math.cos(phi), math.sin(phi)
            sgn = 1.0 if convex else -1.0
            qx, qy = cx + r * ux, cy + r * uy
            d2 = (px - qx) ** 2 + (py - qy) ** 2
            best = _keep(best, d2, qx, qy, sgn * ux, sgn * uy, True, px, py)
        else:
            sgn = 1.0 if convex else -1.0
            for ang in (phi0, phi0 + sweep):
                ux, uy = math.cos(ang), math.sin(ang)
                qx, qy = cx + r * ux, cy + r * uy
                d2 = (px - qx) ** 2 + (py - qy) ** 2
                best = _keep(best, d2, qx, qy, sgn * ux, sgn * uy, False, px, py)
    for pp in ol.params:
        d2, qx, qy, nx, ny, inner = _param_closest(pp, px, py)
        best = _keep(best, d2, qx, qy, nx, ny, inner, px, py)
    d2, qx, qy, nx, ny, inner, _, sx, sy = best
    d = math.sqrt(d2)
    if not inner and d > 1e-13:
        outside = (px - qx) * sx + (py - qy) * sy >= 0.0
        s = 1.0 if outside or is_end(ol.ends, qx, qy) else -1.0
        if s * d < -ol.depth:  # beyond an open outline's body: no contact
            return math.inf, qx, qy, s * (px - qx) / d, s * (py - qy) / d
        return s * d, qx, qy, s * (px - qx) / d, s * (py - qy) / d
    sd = (px - qx) * nx + (py - qy) * ny
    if sd < -ol.depth:  # beyond an open outline's body: no contact
        return math.inf, qx, qy, nx, ny
    return sd, qx, qy, nx, ny


def is_end(ends, qx: float, qy: float) -> bool:
    """Whether (qx, qy) is one of an open outline's ``ends`` (to round-off)."""
    return any(abs(qx - ex) + abs(qy - ey) <= 1e-12 * (1.0 + abs(ex) + abs(ey)) for ex, ey in ends)


def _same_point(ax: float, ay: float, bx: float, by: float) -> bool:
    """Whether two closest points are the same corner (to round-off, body frame [m])."""
    return abs(ax - bx) + abs(ay - by) <= 1e-12 * (1.0 + abs(ax) + abs(ay))


def _keep(best, d2, qx, qy, nx, ny, inner, px, py):
    """The nearer of ``best`` and a piece's closest point; the normals of pieces meeting
    at the same closest point are summed (``best[7:9]``, the corner's sign, see
    :func:`closest_point`)."""
    signed = (px - qx) * nx + (py - qy) * ny
    same = _same_point(qx, qy, best[1], best[2])
    sx, sy = (best[7] + nx, best[8] + ny) if same else (nx, ny)
    if d2 < best[0] - 1e-24 or (abs(d2 - best[0]) <= 1e-24 and signed > best[6]):
        return (d2, qx, qy, nx, ny, inner, signed, sx, sy)
    return (*best[:7], sx, sy) if same else best


def param_extreme(pp: ParamPiece, nx: float, ny: float):
    """The point of a parametric piece farthest along ``-n`` (its support point).

    Returns ``(h, px, py, interior)`` with ``h = min_u c(u) . n``; interior is False when the
    minimum sits at a piece end (then corners/neighbours own the contact).
    """
    h = pp.pts[:, 0] * nx + pp.pts[:, 1] * ny
    i = int(np.argmin(h))

    def g(u):
        _, d1, d2 = pp.derivs(u)
        return d1[0] * nx + d1[1] * ny, d2[0] * nx + d2[1] * ny

    lo, hi = pp.bracket(i)
    glo, ghi = g(lo)[0], g(hi)[0]
    if not (glo < 0 < ghi):
        return math.inf, 0.0, 0.0, False
    u = _newton(g, float(pp.u[i]), lo, hi)
    x, y = pp.point(u)
    return x * nx + y * ny, x, y, True


def param_pair(pa: ParamPiece, pb: ParamPiece, Rab: np.ndarray, dab: np.ndarray):
    """Closest points of two parametric pieces: a in frame A, b mapped into A by (Rab, dab).

    Two-variable Newton on the stationarity conditions of |c_a(u) - c_b(w)|^2, seeded by the
    closest pair of table samples. Returns ``(u, w, converged)``.
    """
    A = pa.pts
    B = pb.pts @ Rab.T + dab
    D = ((A[:, None, :] - B[None, :, :]) ** 2).sum(-1)
    i, j = np.unravel_index(int(np.argmin(D)), D.shape)
    u, w = float(pa.u[i]), float(pb.u[j])
    for _ in range(50):
        p, a1, a2 = pa.derivs(u)
        qb, b1, b2 = pb.derivs(w)
        q = Rab @ qb + dab
        b1, b2 = Rab @ b1, Rab @ b2
        r = p - q
        F = np.array([r @ a1, -(r @ b1)])
        J = np.array([[a1 @ a1 + r @ a2, -(a1 @ b1)], [-(a1 @ b1), b1 @ b1 - r @ b2]])
        try:
            du, dw = np.linalg.solve(J, -F)
        except np.linalg.LinAlgError:
            return u, w, False
        u, w = u + du, w + dw
        if abs(du) + abs(dw) < 1e-15 * (1 + abs(u) + abs(w)):
            return u, w, True
    return u, w, bool(abs(du) + abs(dw) < 1e-10)
