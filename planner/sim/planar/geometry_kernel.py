"""Compiled contact search of the planar world (numba): every body pair in one call.

:func:`contacts_into` finds, for bodies at ``poses`` (nb, 3) ``[x, y, angle]`` and the pairs of
a :class:`~planner.sim.planar.packed_outlines.PackedOutlines`, the rows
``(i, j, gap, pax, pay, pbx, pby, nx, ny, curvature)`` of
:func:`planner.sim.planar.stepper.find_contacts`, in its order and with its semantics: per pair
the candidates of :func:`planner.sim.planar.contacts.candidates` (corners of A, corners of B,
convex arcs of A, of B, parametric pieces of A against lines of B, of B against lines of A,
parametric against parametric), the same duplicate merging, the same bounding-circle
rejection. It is a line-by-line transcription of :mod:`~planner.sim.planar.outline` and
:mod:`~planner.sim.planar.contacts`: closed-form closest points on lines and arcs, and on the
closed-form parametric pieces (header at ``F[h : h + PH]``, see
:mod:`~planner.sim.planar.packed_outlines`: ellipses ``c0 + c1 cos u + c2 sin u``, parabolas
``c0 + c1 u + c2 u^2``, Gaussians ``c0 + c1 u + c2 exp(-(u - m)^2 / (2 s^2))``) the
root of ``(c(u) - p) . c'(u) = 0`` (closest point) or ``c'(u) . n = 0`` (support point) by
Newton safeguarded by bisection on the bracket around the nearest table sample, and the
closest points of two pieces by two-variable Newton seeded by the closest table pair. It finds
the same candidates to round-off (tested to 1e-12 in ``tests/test_sim_geometry_kernel.py``);
no curved outline is approximated. Pairs with a piece the kernel does not know are reported
(``counts[k] = -1``) for the Python fallback of :mod:`planner.sim.planar.contact_search`.

Why one module: numba's on-disk cache (``cache=True``) is invalidated per source file only, so
a compiled function that inlines a helper from another file keeps the helper's old code after
that file changes. Every compiled piece of the contact search therefore lives here. (Callers
compiled in other files - the step kernel - must be recompiled when this file changes: delete
their ``__pycache__/*.nbi`` or touch their source.)
"""

from __future__ import annotations

import math

import numpy as np

from planner.jit import njit
from planner.sim.planar.packed_outlines import ARC, BLOCK, PH

__all__ = ["closest", "contacts_into", "contacts_kernel"]

TWO_PI = 2.0 * math.pi
DUPLICATE = 4e-9  # candidates whose touching points differ by less (L1, 4 coordinates) merge [m]
CLOSEST, EXTREME = 0, 1  # the two root problems on a parametric piece


@njit(cache=True)
def peval(F, h, u):
    """Point, first and second derivative of the piece at ``u``: 6 floats (x, y, x', y',
    x'', y'') of its closed form (kind 1 ellipse, 2 parabola, 3 Gaussian)."""
    c0x, c0y, c1x, c1y, c2x, c2y = F[h + 7], F[h + 8], F[h + 9], F[h + 10], F[h + 11], F[h + 12]
    if F[h] == 3.0:
        m, s = F[h + 15], F[h + 16]
        w = u - m
        g = math.exp(-(w * w) / (2.0 * s * s))
        g1, g2 = -w / (s * s) * g, (w * w / s**4 - 1.0 / (s * s)) * g
        return (
            c0x + c1x * u + c2x * g,
            c0y + c1y * u + c2y * g,
            c1x + c2x * g1,
            c1y + c2y * g1,
            c2x * g2,
            c2y * g2,
        )
    if F[h] == 1.0:
        cu, su = math.cos(u), math.sin(u)
        return (
            c0x + c1x * cu + c2x * su,
            c0y + c1y * cu + c2y * su,
            -c1x * su + c2x * cu,
            -c1y * su + c2y * cu,
            -c1x * cu - c2x * su,
            -c1y * cu - c2y * su,
        )
    return (
        c0x + c1x * u + c2x * u * u,
        c0y + c1y * u + c2y * u * u,
        c1x + 2.0 * c2x * u,
        c1y + 2.0 * c2y * u,
        2.0 * c2x,
        2.0 * c2y,
    )


@njit(cache=True)
def _g(F, h, mode, ax, ay, u):
    """The function whose root Newton seeks, and its derivative: closest point to (ax, ay)
    (``mode`` CLOSEST) or support point along the normal (ax, ay) (``mode`` EXTREME)."""
    x, y, d1x, d1y, d2x, d2y = peval(F, h, u)
    if mode == CLOSEST:
        rx, ry = x - ax, y - ay
        return rx * d1x + ry * d1y, d1x**2 + d1y**2 + rx * d2x + ry * d2y
    return d1x * ax + d1y * ay, d2x * ax + d2y * ay


@njit(cache=True)
def _newton(F, h, mode, ax, ay, u, lo, hi):
    """Root in [lo, hi]: Newton, bisection when it leaves the bracket (as ``outline._newton``)."""
    glo = _g(F, h, mode, ax, ay, lo)[0]
    for _ in range(60):
        g, dg = _g(F, h, mode, ax, ay, u)
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


@njit(cache=True)
def _bracket(F, h, i):
    n, t = int(F[h + 5]), int(F[h + 6])
    lo, hi = F[t + max(i - 1, 0)], F[t + min(i + 1, n - 1)]
    if F[h + 4] != 0.0 and (i == 0 or i == n - 1):
        step = F[t + 1] - F[t]
        lo, hi = F[t + i] - step, F[t + i] + step
    return min(lo, hi), max(lo, hi)


@njit(cache=True)
def _normal(F, h, d1x, d1y):
    tx, ty = F[h + 3] * d1x, F[h + 3] * d1y
    s = math.hypot(tx, ty)
    return -ty / s, tx / s


@njit(cache=True)
def _block(F, h, kb):
    """Sample range [k0, k1) and bounding circle (cx, cy, r) of seed-table block ``kb``."""
    n, bo = int(F[h + 5]), int(F[h + 14]) + 3 * kb
    return BLOCK * kb, min(BLOCK * kb + BLOCK, n), F[bo], F[bo + 1], F[bo + 2]


@njit(cache=True)
def _nearest_sample(F, h, px, py):
    """Index of the first table sample nearest to (px, py) (numpy's argmin of the distances):
    the block whose circle is nearest first, then every block that could hold a sample as
    near (or tied, lower index first)."""
    n, t, nblk = int(F[h + 5]), int(F[h + 6]), int(F[h + 13])
    first, low = 0, math.inf
    for kb in range(nblk):
        _, _, cx, cy, r = _block(F, h, kb)
        lb = math.sqrt((cx - px) ** 2 + (cy - py) ** 2) - r
        if lb < low:
            first, low = kb, lb
    i, best = n, math.inf
    for step in range(nblk + 1):
        kb = first if step == 0 else step - 1
        if step > 0 and kb == first:
            continue
        k0, k1, cx, cy, r = _block(F, h, kb)
        lb = math.sqrt((cx - px) ** 2 + (cy - py) ** 2) - r
        if step > 0 and lb > 0.0 and lb * lb > best:
            continue
        for k in range(k0, k1):
            d2 = (F[t + n + k] - px) ** 2 + (F[t + 2 * n + k] - py) ** 2
            if d2 < best or (d2 == best and k < i):
                i, best = k, d2
    return i


@njit(cache=True)
def _lowest_sample(F, h, nx, ny):
    """Index of the first table sample lowest along n (numpy's argmin of ``p . n``), pruned
    by the blocks' circles as :func:`_nearest_sample`."""
    n, t, nblk = int(F[h + 5]), int(F[h + 6]), int(F[h + 13])
    first, low = 0, math.inf
    for kb in range(nblk):
        _, _, cx, cy, r = _block(F, h, kb)
        lb = cx * nx + cy * ny - r
        if lb < low:
            first, low = kb, lb
    i, best = n, math.inf
    for step in range(nblk + 1):
        kb = first if step == 0 else step - 1
        if step > 0 and kb == first:
            continue
        k0, k1, cx, cy, r = _block(F, h, kb)
        if step > 0 and cx * nx + cy * ny - r > best:
            continue
        for k in range(k0, k1):
            v = F[t + n + k] * nx + F[t + 2 * n + k] * ny
            if v < best or (v == best and k < i):
                i, best = k, v
    return i


@njit(cache=True)
def param_closest(F, h, px, py):
    """Closest point of the piece to (px, py): ``(d2, qx, qy, nx, ny, interior)``."""
    t = int(F[h + 6])
    i = _nearest_sample(F, h, px, py)
    lo, hi = _bracket(F, h, i)
    if _g(F, h, CLOSEST, px, py, lo)[0] < 0 < _g(F, h, CLOSEST, px, py, hi)[0]:
        u = _newton(F, h, CLOSEST, px, py, F[t + i], lo, hi)
        interior = True
    else:
        u = F[t + i]
        interior = False
    x, y, d1x, d1y = peval(F, h, u)[:4]
    nx, ny = _normal(F, h, d1x, d1y)
    return (x - px) ** 2 + (y - py) ** 2, x, y, nx, ny, interior


@njit(cache=True)
def param_extreme(F, h, nx, ny):
    """Support point along ``-n``: ``(min_u c(u) . n, x, y, interior)``."""
    t = int(F[h + 6])
    i = _lowest_sample(F, h, nx, ny)
    lo, hi = _bracket(F, h, i)
    if not (_g(F, h, EXTREME, nx, ny, lo)[0] < 0 < _g(F, h, EXTREME, nx, ny, hi)[0]):
        return math.inf, 0.0, 0.0, False
    u = _newton(F, h, EXTREME, nx, ny, F[t + i], lo, hi)
    x, y = peval(F, h, u)[:2]
    return x * nx + y * ny, x, y, True


@njit(cache=True)
def _nearest_pair(F, ha, hb, bx, by, c, s, dx, dy):
    """Indices (i, j) of the first nearest pair of table samples of a and of b (b's samples
    (bx, by) already in a's frame by (c, s, dx, dy); numpy's row-major argmin), pruned by
    the blocks' circles."""
    na, ta, nb = int(F[ha + 5]), int(F[ha + 6]), int(F[hb + 5])
    nba, nbb = int(F[ha + 13]), int(F[hb + 13])
    cb = np.empty((nbb, 3))  # b's block circles in a's frame
    for kb in range(nbb):
        _, _, x, y, r = _block(F, hb, kb)
        cb[kb, 0], cb[kb, 1], cb[kb, 2] = c * x + -s * y + dx, s * x + c * y + dy, r
    lbs = np.empty((nba, nbb))
    first, low = 0, math.inf
    for ka in range(nba):
        _, _, cx, cy, ra = _block(F, ha, ka)
        for kb in range(nbb):
            lb = math.sqrt((cx - cb[kb, 0]) ** 2 + (cy - cb[kb, 1]) ** 2) - ra - cb[kb, 2]
            lbs[ka, kb] = lb
            if lb < low:
                first, low = ka * nbb + kb, lb
    i, j, best = na, nb, math.inf
    for step in range(nba * nbb + 1):
        kk = first if step == 0 else step - 1
        if step > 0 and kk == first:
            continue
        ka, kb = kk // nbb, kk % nbb
        lb = lbs[ka, kb]
        if step > 0 and lb > 0.0 and lb * lb > best:
            continue
        a0, a1 = _block(F, ha, ka)[:2]
        b0, b1 = _block(F, hb, kb)[:2]
        for p in range(a0, a1):
            ax, ay = F[ta + na + p], F[ta + 2 * na + p]
            for q in range(b0, b1):
                d2 = (ax - bx[q]) ** 2 + (ay - by[q]) ** 2
                if d2 < best or (d2 == best and (p < i or (p == i and q < j))):
                    i, j, best = p, q, d2
    return i, j


@njit(cache=True)
def param_pair(F, ha, hb, c, s, dx, dy):
    """Closest points of pieces a and b, b mapped into a's frame by rotation (c, s) and
    shift (dx, dy): ``(u, w, converged)``."""
    ta, nb, tb = int(F[ha + 6]), int(F[hb + 5]), int(F[hb + 6])
    bx, by = np.empty(nb), np.empty(nb)
    for k in range(nb):
        x, y = F[tb + nb + k], F[tb + 2 * nb + k]
        bx[k], by[k] = c * x + -s * y + dx, s * x + c * y + dy
    i, j = _nearest_pair(F, ha, hb, bx, by, c, s, dx, dy)
    u, w = F[ta + i], F[tb + j]
    du = dw = 0.0
    for _ in range(50):
        px, py, a1x, a1y, a2x, a2y = peval(F, ha, u)
        qx, qy, b1x, b1y, b2x, b2y = peval(F, hb, w)
        qx, qy = c * qx - s * qy + dx, s * qx + c * qy + dy
        b1x, b1y = c * b1x - s * b1y, s * b1x + c * b1y
        b2x, b2y = c * b2x - s * b2y, s * b2x + c * b2y
        rx, ry = px - qx, py - qy
        f1, f2 = rx * a1x + ry * a1y, -(rx * b1x + ry * b1y)
        j11 = a1x * a1x + a1y * a1y + (rx * a2x + ry * a2y)
        j12 = -(a1x * b1x + a1y * b1y)
        j22 = b1x * b1x + b1y * b1y - (rx * b2x + ry * b2y)
        det = j11 * j22 - j12 * j12
        if det == 0.0 or not math.isfinite(det):
            return u, w, False
        du = (-f1 * j22 + f2 * j12) / det
        dw = (-j11 * f2 + j12 * f1) / det
        u, w = u + du, w + dw
        if abs(du) + abs(dw) < 1e-15 * (1 + abs(u) + abs(w)):
            return u, w, True
    return u, w, abs(du) + abs(dw) < 1e-10


@njit(cache=True)
def _to_world(P, px, py):
    return P[2] + P[0] * px - P[1] * py, P[3] + P[1] * px + P[0] * py


@njit(cache=True)
def _rotate(P, vx, vy):
    return P[0] * vx - P[1] * vy, P[1] * vx + P[0] * vy


@njit(cache=True)
def _to_body(P, px, py):
    dx, dy = px - P[2], py - P[3]
    return P[0] * dx + P[1] * dy, -P[1] * dx + P[0] * dy


@njit(cache=True)
def _unrotate(P, vx, vy):
    return P[0] * vx + P[1] * vy, -P[1] * vx + P[0] * vy


@njit(cache=True)
def _arc_contains(phi0, sweep, phi):
    if abs(sweep) >= TWO_PI - 1e-15:
        return True
    d = (phi - phi0) % TWO_PI if sweep > 0 else (phi0 - phi) % TWO_PI
    return d <= abs(sweep) + 1e-12


@njit(cache=True)
def _better(d2, sig, bd2, bsig):
    return d2 < bd2 - 1e-24 or (abs(d2 - bd2) <= 1e-24 and sig > bsig)


@njit(cache=True)
def _same_point(ax, ay, bx, by):
    return abs(ax - bx) + abs(ay - by) <= 1e-12 * (1.0 + abs(ax) + abs(ay))


@njit(cache=True)
def _keep(best, d2, sig, inner, qx, qy, nx, ny):
    """The nearer of ``best = (d2, sig, inner, qx, qy, nx, ny, sx, sy)`` and a piece's
    closest point; pieces meeting at the best point add their normals to ``(sx, sy)``, the
    corner's sign (transcribes ``outline._keep``)."""
    same = _same_point(qx, qy, best[3], best[4])
    sx, sy = (best[7] + nx, best[8] + ny) if same else (nx, ny)
    if _better(d2, sig, best[0], best[1]):
        return (d2, sig, inner, qx, qy, nx, ny, sx, sy)
    if same:
        return (best[0], best[1], best[2], best[3], best[4], best[5], best[6], sx, sy)
    return best


@njit(cache=True)
def _is_end(F, e, qx, qy):
    """Whether (qx, qy) is one of the two ends stored at F[e:e+4] (e < 0: a closed outline)."""
    if e < 0:
        return False
    for k in range(2):
        ex, ey = F[e + 2 * k], F[e + 2 * k + 1]
        if abs(qx - ex) + abs(qy - ey) <= 1e-12 * (1.0 + abs(ex) + abs(ey)):
            return True
    return False


@njit(cache=True)
def _depth(F, I, b):  # noqa: E741
    """How deep body b's outline reaches behind its face [m] (inf: closed, or a half-plane;
    :attr:`planner.sim.planar.outline.Outline.depth`)."""
    e = I[b, 9]
    return math.inf if e < 0 else F[e + 4]


@njit(cache=True)
def closest(F, I, b, px, py):  # noqa: E741
    """Signed distance of body-frame point (px, py) to body b: ``(d, qx, qy, nx, ny)``
    (transcribes :func:`planner.sim.planar.outline.closest_point`; unsigned at an open
    outline's ends, ``inf`` beyond its body's depth (:func:`_depth`); at a corner signed by
    the sum of the normals of the pieces meeting there, :func:`_keep`)."""
    best = (math.inf, -math.inf, True, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)  # see _keep
    o = I[b, 0]
    for k in range(I[b, 1]):
        r = o + 6 * k
        ax, ay, ex, ey, nx, ny = (
            F[r],
            F[r + 1],
            F[r + 2] - F[r],
            F[r + 3] - F[r + 1],
            F[r + 4],
            F[r + 5],
        )
        t = ((px - ax) * ex + (py - ay) * ey) / (ex * ex + ey * ey)
        inner = 0.0 < t < 1.0
        t = min(max(t, 0.0), 1.0)
        qx, qy = ax + t * ex, ay + t * ey
        d2 = (px - qx) ** 2 + (py - qy) ** 2
        sig = (px - qx) * nx + (py - qy) * ny
        best = _keep(best, d2, sig, inner, qx, qy, nx, ny)
    o = I[b, 2]
    for k in range(I[b, 3]):
        r = o + ARC * k
        cx, cy, rad, phi0, sweep = F[r], F[r + 1], F[r + 2], F[r + 3], F[r + 4]
        sgn = 1.0 if F[r + 5] != 0.0 else -1.0
        dx, dy = px - cx, py - cy
        dist = math.sqrt(dx * dx + dy * dy)
        if (dist - rad) ** 2 > best[0] * (1.0 + 1e-9) + 1e-24:
            continue  # no point of the circle can beat (or tie) the best so far
        full = abs(sweep) >= TWO_PI - 1e-15  # a full circle: no angle needed
        inside = full or _arc_contains(phi0, sweep, math.atan2(dy, dx))
        for e in range(1 if inside else 2):
            if inside:  # the radial direction (cos, sin of atan2(dy, dx), to round-off)
                ux, uy = (dx / dist, dy / dist) if dist > 0.0 else (1.0, 0.0)
            else:  # the ends' directions, cos/sin of phi0 and phi0 + sweep (packed)
                ux, uy = F[r + 6 + 2 * e], F[r + 7 + 2 * e]
            qx, qy = cx + rad * ux, cy + rad * uy
            d2 = (px - qx) ** 2 + (py - qy) ** 2
            nx, ny = sgn * ux, sgn * uy
            sig = (px - qx) * nx + (py - qy) * ny
            best = _keep(best, d2, sig, inside, qx, qy, nx, ny)
    o = I[b, 6]
    for k in range(I[b, 7]):
        d2, qx, qy, nx, ny, inner = param_closest(F, o + PH * k, px, py)
        sig = (px - qx) * nx + (py - qy) * ny
        best = _keep(best, d2, sig, inner, qx, qy, nx, ny)
    bd2, _, binner, bqx, bqy, bnx, bny, bsx, bsy = best
    d = math.sqrt(bd2)
    if not binner and d > 1e-13:
        out = (px - bqx) * bsx + (py - bqy) * bsy >= 0.0
        s = 1.0 if out or _is_end(F, I[b, 9], bqx, bqy) else -1.0
        if s * d < -_depth(F, I, b):  # beyond an open outline's body: no contact
            return math.inf, bqx, bqy, s * (px - bqx) / d, s * (py - bqy) / d
        return s * d, bqx, bqy, s * (px - bqx) / d, s * (py - bqy) / d
    sd = (px - bqx) * bnx + (py - bqy) * bny
    if sd < -_depth(F, I, b):  # beyond an open outline's body: no contact
        return math.inf, bqx, bqy, bnx, bny
    return sd, bqx, bqy, bnx, bny


@njit(cache=True)
def _point_vs(F, I, b, P, px, py):
    lx, ly = _to_body(P, px, py)
    d, qx, qy, nx, ny = closest(F, I, b, lx, ly)
    wx, wy = _to_world(P, qx, qy)
    vx, vy = _rotate(P, nx, ny)
    return d, wx, wy, vx, vy


@njit(cache=True)
def _push(out, n, i, j, gap, ax, ay, bx, by, nx, ny, k, flip):
    """Write row n when it fits (the caller counts it anyway, to size a larger buffer)."""
    if n >= out.shape[0]:
        return
    if flip:
        ax, ay, bx, by, nx, ny = bx, by, ax, ay, -nx, -ny
    row = out[n]
    row[0], row[1], row[2], row[3], row[4] = i, j, gap, ax, ay
    row[5], row[6], row[7], row[8], row[9] = bx, by, nx, ny, k


@njit(cache=True)
def _beyond(F, I, b, Pb, wx, wy, reach):
    """Whether (wx, wy) is farther than ``bound_b + reach`` from closed body b's origin: its
    distance to b's outline then exceeds ``reach`` (the query would be rejected, so skipping
    it changes no result). Open outlines are never skipped (behind a face is inside)."""
    if I[b, 9] >= 0:
        return False
    lim = F[b] + reach
    dx, dy = wx - Pb[2], wy - Pb[3]
    return lim > 0.0 and dx * dx + dy * dy > lim * lim


@njit(cache=True)
def _corners_vs(F, I, a, Pa, b, Pb, margin, flip, out, n, i, j):  # noqa: E741
    o = I[a, 4]
    for k in range(I[a, 5]):
        wx, wy = _to_world(Pa, F[o + 2 * k], F[o + 2 * k + 1])
        if _beyond(F, I, b, Pb, wx, wy, margin):
            continue
        d, qx, qy, nx, ny = _point_vs(F, I, b, Pb, wx, wy)
        if d < margin:
            _push(out, n, i, j, d, wx, wy, qx, qy, nx, ny, math.inf, flip)
            n += 1
    return n


@njit(cache=True)
def _arcs_vs(F, I, a, Pa, b, Pb, margin, flip, out, n, i, j):  # noqa: E741
    o = I[a, 2]
    for k in range(I[a, 3]):
        r = o + ARC * k
        if F[r + 5] == 0.0:
            continue
        rad = F[r + 2]
        wx, wy = _to_world(Pa, F[r], F[r + 1])
        if _beyond(F, I, b, Pb, wx, wy, margin + rad):
            continue
        d, qx, qy, nx, ny = _point_vs(F, I, b, Pb, wx, wy)
        gap = d - rad
        if gap >= margin or gap < -_depth(F, I, b):  # (beyond an open outline's body)
            continue
        lx, ly = _unrotate(Pa, -nx, -ny)
        full = abs(F[r + 4]) >= TWO_PI - 1e-15
        if not full and not _arc_contains(F[r + 3], F[r + 4], math.atan2(ly, lx)):
            continue
        _push(out, n, i, j, gap, wx - rad * nx, wy - rad * ny, qx, qy, nx, ny, 1.0 / rad, flip)
        n += 1
    return n


@njit(cache=True)
def _params_vs_lines(F, I, a, Pa, b, Pb, margin, flip, out, n, i, j):  # noqa: E741
    for kp in range(I[a, 7]):
        h = I[a, 6] + PH * kp
        for kl in range(I[b, 1]):
            r = I[b, 0] + 6 * kl
            wax, way = _to_world(Pb, F[r], F[r + 1])
            wbx, wby = _to_world(Pb, F[r + 2], F[r + 3])
            wnx, wny = _rotate(Pb, F[r + 4], F[r + 5])
            lax, lay = _to_body(Pa, wax, way)
            lbx, lby = _to_body(Pa, wbx, wby)
            lnx, lny = _unrotate(Pa, wnx, wny)
            hv, x, y, inner = param_extreme(F, h, lnx, lny)
            if not inner:
                continue
            gap = hv - (lax * lnx + lay * lny)
            if gap >= margin or gap < -_depth(F, I, b):  # (beyond an open outline's body)
                continue
            fx, fy = x - gap * lnx, y - gap * lny
            ex, ey = lbx - lax, lby - lay
            t = ((fx - lax) * ex + (fy - lay) * ey) / (ex * ex + ey * ey)
            if not 0.0 <= t <= 1.0:
                continue
            sx, sy = _to_world(Pa, x, y)
            qx, qy = _to_world(Pa, fx, fy)
            _push(out, n, i, j, gap, sx, sy, qx, qy, wnx, wny, 0.0, flip)
            n += 1
    return n


@njit(cache=True)
def _params_vs_params(F, I, a, Pa, b, Pb, margin, out, n, i, j):  # noqa: E741
    if I[a, 7] == 0 or I[b, 7] == 0:
        return n
    c = Pa[0] * Pb[0] + Pa[1] * Pb[1]
    s = Pa[0] * Pb[1] - Pa[1] * Pb[0]
    dx, dy = _to_body(Pa, Pb[2], Pb[3])
    for ka in range(I[a, 7]):
        ha = I[a, 6] + PH * ka
        for kb in range(I[b, 7]):
            hb = I[b, 6] + PH * kb
            u, w, ok = param_pair(F, ha, hb, c, s, dx, dy)
            if not ok:
                continue
            px, py = peval(F, ha, u)[:2]
            qbx, qby, b1x, b1y = peval(F, hb, w)[:4]
            qx, qy = c * qbx - s * qby + dx, s * qbx + c * qby + dy
            tx, ty = F[hb + 3] * b1x, F[hb + 3] * b1y
            ln = math.hypot(tx, ty)
            nbx, nby = -ty / ln, tx / ln
            nx, ny = c * nbx - s * nby, s * nbx + c * nby
            gap = (px - qx) * nx + (py - qy) * ny
            if gap >= margin:
                continue
            sx, sy = _to_world(Pa, px, py)
            wx, wy = _to_world(Pa, qx, qy)
            vx, vy = _rotate(Pa, nx, ny)
            _push(out, n, i, j, gap, sx, sy, wx, wy, vx, vy, 0.0, n < 0)
            n += 1
    return n


@njit(cache=True)
def _merge(out, start, n):
    """Drop candidates whose touching points repeat an earlier one's (keep the first)."""
    m = start
    for r in range(start, n):
        dup = False
        for k in range(start, m):
            e = abs(out[r, 3] - out[k, 3]) + abs(out[r, 4] - out[k, 4])
            e = e + abs(out[r, 5] - out[k, 5]) + abs(out[r, 6] - out[k, 6])
            if e < DUPLICATE:
                dup = True
                break
        if not dup:
            if m != r:
                out[m] = out[r]
            m += 1
    return m


@njit(cache=True)
def contacts_into(F, I, poses, pairs, margins, out, counts):  # noqa: E741
    """Candidates of every known pair written into ``out``; returns their number n.

    Args:
        F: (nf,) float64 packed geometry (:attr:`PackedOutlines.F`).
        I: (nb, 10) int64 offsets and counts (:attr:`PackedOutlines.I`).
        poses: (nb, 3) ``[x, y, angle]`` of each body's outline frame [m, rad].
        pairs: (np, 2) int64 body pairs ``(i, j)`` to test, in output order.
        margins: (np,) float64: candidates of pair k with a gap below ``margins[k]`` [m].
        out: (cap, 10) float64, receives the rows ``(i, j, gap, pax, pay, pbx, pby, nx, ny,
            curvature)`` of :func:`planner.sim.planar.stepper.find_contacts` (body indices
            as floats, gap [m], touching points on i and j [m], unit normal from j toward i,
            curvature of the touching feature [1/m], inf at corners).
        counts: (np,) int64, receives the number of rows of each pair; -1 for a pair left to
            the Python fallback (a body with a parametric piece the kernel does not know).

    When ``n > cap`` the buffer was too small (its rows are incomplete and n is an upper
    bound): call again with at least n rows.
    """
    # runtime (non-literal) values: one compiled specialization of each helper instead of
    # one per literal argument (compile time)
    n = counts.shape[0] * 0
    no = n < 0
    yes = not no
    cap = out.shape[0]
    T = np.empty((poses.shape[0], 4))  # placements (cos, sin, x, y), one per body
    for b in range(poses.shape[0]):
        T[b, 0], T[b, 1] = math.cos(poses[b, 2]), math.sin(poses[b, 2])
        T[b, 2], T[b, 3] = poses[b, 0], poses[b, 1]
    for k in range(pairs.shape[0]):
        a, b = pairs[k, 0], pairs[k, 1]
        counts[k] = 0
        if I[a, 8] == 0 or I[b, 8] == 0:
            counts[k] = -1
            continue
        m = margins[k]
        Pa = (T[a, 0], T[a, 1], T[a, 2], T[a, 3])
        Pb = (T[b, 0], T[b, 1], T[b, 2], T[b, 3])
        if math.hypot(Pa[2] - Pb[2], Pa[3] - Pb[3]) > F[a] + F[b] + m:
            continue
        start = n
        n = _corners_vs(F, I, a, Pa, b, Pb, m, no, out, n, a, b)
        n = _corners_vs(F, I, b, Pb, a, Pa, m, yes, out, n, a, b)
        n = _arcs_vs(F, I, a, Pa, b, Pb, m, no, out, n, a, b)
        n = _arcs_vs(F, I, b, Pb, a, Pa, m, yes, out, n, a, b)
        n = _params_vs_lines(F, I, a, Pa, b, Pb, m, no, out, n, a, b)
        n = _params_vs_lines(F, I, b, Pb, a, Pa, m, yes, out, n, a, b)
        n = _params_vs_params(F, I, a, Pa, b, Pb, m, out, n, a, b)
        if n - start >= 2 and n <= cap:
            n = _merge(out, start, n)
        counts[k] = n - start
    return n


@njit(cache=True)
def contacts_kernel(F, I, poses, pairs, margins):  # noqa: E741
    """Candidates of every known pair: ``(rows (n, 10), counts (np,))`` (see
    :func:`contacts_into`; this one allocates its result, for callers inside numba)."""
    counts = np.empty(pairs.shape[0], np.int64)
    out = np.empty((16, 10))
    n = contacts_into(F, I, poses, pairs, margins, out, counts)
    if n > out.shape[0]:
        out = np.empty((n, 10))
        n = contacts_into(F, I, poses, pairs, margins, out, counts)
    return out[:n], counts
