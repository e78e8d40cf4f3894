"""Contact candidates between two outlines placed in the world (exact geometry).

For bodies A and B at poses ``(R_A, d_A)``, ``(R_B, d_B)`` the candidates are the local
closest-point pairs of their outlines closer than ``margin``:

1. every corner of A against B's outline (closest point, exact), and B's corners against A;
2. every convex arc of A: its centre against B's outline, gap = distance - radius, kept when
   the touching point lies on the arc (arc-line, arc-arc, arc-corner, arc-ellipse exactly);
   and B's convex arcs against A;
3. every parametric piece of A against B's lines: the support point along -n, gap =
   ``min_u c(u).n - a.n``, kept when its foot lies inside the segment; and vice versa;
4. parametric against parametric: two-variable Newton on the closest-point conditions.

Line-line contacts need no rule of their own: a flat face meets another through its end
corners (two candidates for a box on a plane, the classical contact manifold). The normal
points from B toward A; the gap is ``(p_A - p_B) . n``. Duplicates (a corner found from
both sides, an arc pair found from both centres) are merged. Limits: a concave piece of A
touches B only through B's convex features; a parametric piece against a concave arc is not
searched (no catalogue shape needs it). An open outline (a pad, the palm) is one-sided:
beyond its ends the distance to it is unsigned (see
:func:`~planner.sim.planar.outline.closest_point`). The compiled twin of this module, used
by the stepper, is :mod:`planner.sim.planar.geometry_kernel` (same candidates to round-off).
"""

from __future__ import annotations

import math

import numpy as np

from planner.sim.planar.outline import (
    Outline,
    _arc_contains,
    closest_point,
    param_extreme,
    param_pair,
)

__all__ = ["Pose", "candidates"]


class Pose:
    """A rigid placement ``p_world = R p_body + d`` (planar)."""

    __slots__ = ("c", "s", "x", "y")

    def __init__(self, x: float, y: float, angle: float) -> None:
        self.c, self.s, self.x, self.y = math.cos(angle), math.sin(angle), x, y

    def to_world(self, px: float, py: float) -> tuple[float, float]:
        return self.x + self.c * px - self.s * py, self.y + self.s * px + self.c * py

    def rotate(self, vx: float, vy: float) -> tuple[float, float]:
        return self.c * vx - self.s * vy, self.s * vx + self.c * vy

    def to_body(self, px: float, py: float) -> tuple[float, float]:
        dx, dy = px - self.x, py - self.y
        return self.c * dx + self.s * dy, -self.s * dx + self.c * dy

    def unrotate(self, vx: float, vy: float) -> tuple[float, float]:
        return self.c * vx + self.s * vy, -self.s * vx + self.c * vy


def _point_vs(ol: Outline, pose: Pose, px: float, py: float):
    """Closest point of the placed outline to the world point: (d, q world, n world)."""
    bx, by = pose.to_body(px, py)
    d, qx, qy, nx, ny = closest_point(ol, bx, by)
    return (d, *pose.to_world(qx, qy), *pose.rotate(nx, ny))


def _arcs_vs(oa: Outline, pa: Pose, ob: Outline, pb: Pose, margin: float, flip: bool, out: list):
    for cx, cy, r, phi0, sweep, convex in oa.arc_list:
        if not convex:
            continue
        wx, wy = pa.to_world(cx, cy)
        d, qx, qy, nx, ny = _point_vs(ob, pb, wx, wy)
        gap = d - r
        if gap >= margin or gap < -ob.depth:  # (beyond an open outline's body)
            continue
        lx, ly = pa.unrotate(-nx, -ny)
        if not _arc_contains(phi0, sweep, math.atan2(ly, lx)):
            continue
        sx, sy = wx - r * nx, wy - r * ny
        if flip:
            out.append((gap, qx, qy, sx, sy, -nx, -ny, 1.0 / r))
        else:
            out.append((gap, sx, sy, qx, qy, nx, ny, 1.0 / r))


def _corners_vs(oa: Outline, pa: Pose, ob: Outline, pb: Pose, margin: float, flip: bool, out):
    for cx, cy in oa.corner_list:
        wx, wy = pa.to_world(cx, cy)
        d, qx, qy, nx, ny = _point_vs(ob, pb, wx, wy)
        if d >= margin:
            continue
        if flip:
            out.append((d, qx, qy, wx, wy, -nx, -ny, math.inf))
        else:
            out.append((d, wx, wy, qx, qy, nx, ny, math.inf))


def _params_vs_lines(oa: Outline, pa: Pose, ob: Outline, pb: Pose, margin, flip, out):
    for pp in oa.params:
        for ax, ay, bx, by, nx, ny in ob.line_list:
            # the line of B in A's frame
            wax, way = pb.to_world(ax, ay)
            wbx, wby = pb.to_world(bx, by)
            wnx, wny = pb.rotate(nx, ny)
            lax, lay = pa.to_body(wax, way)
            lbx, lby = pa.to_body(wbx, wby)
            lnx, lny = pa.unrotate(wnx, wny)
            h, x, y, inner = param_extreme(pp, lnx, lny)
            if not inner:
                continue
            gap = h - (lax * lnx + lay * lny)
            if gap >= margin or gap < -ob.depth:  # (beyond an open outline's body)
                continue
            fx, fy = x - gap * lnx, y - gap * lny
            ex, ey = lbx - lax, lby - lay
            t = ((fx - lax) * ex + (fy - lay) * ey) / (ex * ex + ey * ey)
            if not 0.0 <= t <= 1.0:
                continue
            sx, sy = pa.to_world(x, y)
            qx, qy = pa.to_world(fx, fy)
            if flip:
                out.append((gap, qx, qy, sx, sy, -wnx, -wny, 0.0))
            else:
                out.append((gap, sx, sy, qx, qy, wnx, wny, 0.0))


def _params_vs_params(oa: Outline, pa: Pose, ob: Outline, pb: Pose, margin: float, out: list):
    if not oa.params or not ob.params:
        return
    # B's frame expressed in A's frame
    c = pa.c * pb.c + pa.s * pb.s
    s = pa.c * pb.s - pa.s * pb.c
    Rab = np.array([[c, -s], [s, c]])
    dab = np.array(pa.to_body(pb.x, pb.y))
    for ka in oa.params:
        for kb in ob.params:
            u, w, ok = param_pair(ka, kb, Rab, dab)
            if not ok:
                continue
            p = np.array(ka.point(u))
            _, b1, _ = kb.derivs(w)
            q = Rab @ np.array(kb.point(w)) + dab
            nbx, nby = kb.normal(b1)
            n = Rab @ np.array([nbx, nby])
            gap = float((p - q) @ n)
            if gap >= margin:
                continue
            sx, sy = pa.to_world(*p)
            qx, qy = pa.to_world(*q)
            out.append((gap, sx, sy, qx, qy, *pa.rotate(*n), 0.0))


def candidates(oa: Outline, pa: Pose, ob: Outline, pb: Pose, margin: float) -> list[tuple]:
    """Contact candidates between A and B (gap < margin).

    Returns:
        list of ``(gap, pax, pay, pbx, pby, nx, ny, curvature)``: gap [m], the touching
        points on A and on B (world) [m], the unit normal from B toward A, and the curvature
        of the feature that touches [1/m] (for the tactile array; inf at corners).
    """
    if math.hypot(pa.x - pb.x, pa.y - pb.y) > oa.bound + ob.bound + margin:
        return []
    out: list[tuple] = []
    _corners_vs(oa, pa, ob, pb, margin, False, out)
    _corners_vs(ob, pb, oa, pa, margin, True, out)
    _arcs_vs(oa, pa, ob, pb, margin, False, out)
    _arcs_vs(ob, pb, oa, pa, margin, True, out)
    _params_vs_lines(oa, pa, ob, pb, margin, False, out)
    _params_vs_lines(ob, pb, oa, pa, margin, True, out)
    _params_vs_params(oa, pa, ob, pb, margin, out)
    if len(out) < 2:
        return out
    kept: list[tuple] = []
    for cand in out:
        if not any(
            abs(cand[1] - k[1]) + abs(cand[2] - k[2]) + abs(cand[3] - k[3]) + abs(cand[4] - k[4])
            < 4e-9
            for k in kept
        ):
            kept.append(cand)
    return kept
