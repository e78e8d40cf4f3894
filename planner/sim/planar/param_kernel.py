"""Compiled queries on the closed-form parametric pieces of a packed outline (numba).

Transcribes :func:`planner.sim.planar.outline._param_closest`, ``param_extreme`` and
``param_pair`` for the pieces :mod:`planner.sim.planar.packed_outlines` recognises: a piece
header at ``F[h : h + PH]`` holds ``kind, u0, u1, direction, periodic, ntab, tab`` and the
coefficients ``c0, c1, c2`` (2-vectors) of

* ``TRIG``: ``c(u) = c0 + c1 cos u + c2 sin u`` (ellipses);
* ``QUAD``: ``c(u) = c0 + c1 u + c2 u^2`` (parabolas);

the seed table (``ntab`` parameters, x, y) starts at ``F[tab]``. The queries are exact: the
closest point to a point solves ``(c(u) - p) . c'(u) = 0``, the support point along a normal
``c'(u) . n = 0``, by Newton safeguarded by bisection on the bracket around the nearest table
sample (to machine precision); the closest points of two pieces by two-variable Newton on
the stationarity conditions of ``|c_a(u) - c_b(w)|^2`` seeded by the closest table pair.
"""

from __future__ import annotations

import math

import numpy as np

try:  # numba is a dependency; keep the library importable without it
    from numba import njit
except ImportError:  # pragma: no cover - exercised only without numba

    def njit(*args, **kwargs):
        if args and callable(args[0]):
            return args[0]
        return lambda f: f


__all__ = ["param_closest", "param_extreme", "param_pair", "peval"]

CLOSEST, EXTREME = 0, 1


@njit(cache=True)
def peval(F, h, u):
    """Point, first and second derivative of the piece at ``u``: 6 floats (x, y, x', y',
    x'', y'')."""
    c0x, c0y, c1x, c1y, c2x, c2y = F[h + 7], F[h + 8], F[h + 9], F[h + 10], F[h + 11], F[h + 12]
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
def param_closest(F, h, px, py):
    """Closest point of the piece to (px, py): ``(d2, qx, qy, nx, ny, interior)``."""
    n, t = int(F[h + 5]), int(F[h + 6])
    i, best = 0, math.inf
    for k in range(n):
        d2 = (F[t + n + k] - px) ** 2 + (F[t + 2 * n + k] - py) ** 2
        if d2 < best:
            i, best = k, d2
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
    n, t = int(F[h + 5]), int(F[h + 6])
    i, best = 0, math.inf
    for k in range(n):
        v = F[t + n + k] * nx + F[t + 2 * n + k] * ny
        if v < best:
            i, best = k, v
    lo, hi = _bracket(F, h, i)
    if not (_g(F, h, EXTREME, nx, ny, lo)[0] < 0 < _g(F, h, EXTREME, nx, ny, hi)[0]):
        return math.inf, 0.0, 0.0, False
    u = _newton(F, h, EXTREME, nx, ny, F[t + i], lo, hi)
    x, y = peval(F, h, u)[:2]
    return x * nx + y * ny, x, y, True


@njit(cache=True)
def param_pair(F, ha, hb, c, s, dx, dy):
    """Closest points of pieces a and b, b mapped into a's frame by rotation (c, s) and
    shift (dx, dy): ``(u, w, converged)``."""
    na, ta, nb, tb = int(F[ha + 5]), int(F[ha + 6]), int(F[hb + 5]), int(F[hb + 6])
    bx, by = np.empty(nb), np.empty(nb)
    for k in range(nb):
        x, y = F[tb + nb + k], F[tb + 2 * nb + k]
        bx[k], by[k] = c * x + -s * y + dx, s * x + c * y + dy
    i = j = 0
    best = math.inf
    for p in range(na):
        ax, ay = F[ta + na + p], F[ta + 2 * na + p]
        for q in range(nb):
            d2 = (ax - bx[q]) ** 2 + (ay - by[q]) ** 2
            if d2 < best:
                i, j, best = p, q, d2
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
