"""Compiled contact search of the planar world: every body pair in one numba call.

:func:`find_contacts_packed` returns, for bodies at ``poses`` (nb, 3) ``[x, y, angle]`` and the
pairs of a :class:`~planner.sim.planar.packed_outlines.PackedOutlines`, the rows
``(i, j, gap, pax, pay, pbx, pby, nx, ny, curvature)`` of
:func:`planner.sim.planar.stepper.find_contacts`, in its order and with its semantics: per pair
the candidates of :func:`planner.sim.planar.contacts.candidates` (corners of A, corners of B,
convex arcs of A, of B, parametric pieces of A against lines of B, of B against lines of A,
parametric against parametric), the same duplicate merging, the same bounding-circle
rejection. The kernel is a line-by-line transcription of :mod:`~planner.sim.planar.outline`
and :mod:`~planner.sim.planar.contacts` (closed-form line and arc closest points, safeguarded
Newton on parametric pieces seeded from the same 257-sample tables), so it finds the same
candidates to round-off (tested to 1e-12 in ``tests/test_sim_geometry_kernel.py``); no
curved outline is approximated.

Fallback: a pair with a body holding a parametric piece the kernel does not know (a
Gaussian bump, a spline; ``PackedOutlines.I[b, 8] == 0``) is skipped by the kernel and
computed by the Python :func:`~planner.sim.planar.contacts.candidates`, in place.
"""

from __future__ import annotations

import math

import numpy as np

from planner.errors import InvalidParameter
from planner.sim.planar.contacts import Pose, candidates
from planner.sim.planar.packed_outlines import PH, PackedOutlines
from planner.sim.planar.param_kernel import param_closest, param_extreme, param_pair, peval

try:  # numba is a dependency; keep the library importable without it
    from numba import njit
except ImportError:  # pragma: no cover - exercised only without numba

    def njit(*args, **kwargs):
        if args and callable(args[0]):
            return args[0]
        return lambda f: f


__all__ = ["ContactSearch", "contacts_into", "contacts_kernel", "find_contacts_packed"]

TWO_PI = 2.0 * math.pi
DUPLICATE = 4e-9  # candidates whose touching points differ by less (L1, 4 coordinates) merge [m]


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
def closest(F, I, b, px, py):  # noqa: E741
    """Signed distance of body-frame point (px, py) to body b: ``(d, qx, qy, nx, ny)``
    (transcribes :func:`planner.sim.planar.outline.closest_point`; unsigned at an open
    outline's ends)."""
    bd2, bsig, binner = math.inf, -math.inf, True
    bqx = bqy = bnx = bny = 0.0
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
        if _better(d2, sig, bd2, bsig):
            bd2, bsig, binner, bqx, bqy, bnx, bny = d2, sig, inner, qx, qy, nx, ny
    o = I[b, 2]
    for k in range(I[b, 3]):
        r = o + 6 * k
        cx, cy, rad, phi0, sweep = F[r], F[r + 1], F[r + 2], F[r + 3], F[r + 4]
        sgn = 1.0 if F[r + 5] != 0.0 else -1.0
        dx, dy = px - cx, py - cy
        full = abs(sweep) >= TWO_PI - 1e-15  # a full circle: no angle needed
        inside = full or _arc_contains(phi0, sweep, math.atan2(dy, dx))
        for e in range(1 if inside else 2):
            if inside:  # the radial direction (cos, sin of atan2(dy, dx), to round-off)
                dist = math.sqrt(dx * dx + dy * dy)
                ux, uy = (dx / dist, dy / dist) if dist > 0.0 else (1.0, 0.0)
            else:
                ang = phi0 if e == 0 else phi0 + sweep
                ux, uy = math.cos(ang), math.sin(ang)
            qx, qy = cx + rad * ux, cy + rad * uy
            d2 = (px - qx) ** 2 + (py - qy) ** 2
            nx, ny = sgn * ux, sgn * uy
            sig = (px - qx) * nx + (py - qy) * ny
            if _better(d2, sig, bd2, bsig):
                bd2, bsig, binner, bqx, bqy, bnx, bny = d2, sig, inside, qx, qy, nx, ny
    o = I[b, 6]
    for k in range(I[b, 7]):
        d2, qx, qy, nx, ny, inner = param_closest(F, o + PH * k, px, py)
        sig = (px - qx) * nx + (py - qy) * ny
        if _better(d2, sig, bd2, bsig):
            bd2, bsig, binner, bqx, bqy, bnx, bny = d2, sig, inner, qx, qy, nx, ny
    d = math.sqrt(bd2)
    if not binner and d > 1e-13:
        s = 1.0 if bsig >= 0 or _is_end(F, I[b, 9], bqx, bqy) else -1.0
        return s * d, bqx, bqy, s * (px - bqx) / d, s * (py - bqy) / d
    return (px - bqx) * bnx + (py - bqy) * bny, bqx, bqy, bnx, bny


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
def _corners_vs(F, I, a, Pa, b, Pb, margin, flip, out, n, i, j):  # noqa: E741
    o = I[a, 4]
    for k in range(I[a, 5]):
        wx, wy = _to_world(Pa, F[o + 2 * k], F[o + 2 * k + 1])
        d, qx, qy, nx, ny = _point_vs(F, I, b, Pb, wx, wy)
        if d < margin:
            _push(out, n, i, j, d, wx, wy, qx, qy, nx, ny, math.inf, flip)
            n += 1
    return n


@njit(cache=True)
def _arcs_vs(F, I, a, Pa, b, Pb, margin, flip, out, n, i, j):  # noqa: E741
    o = I[a, 2]
    for k in range(I[a, 3]):
        r = o + 6 * k
        if F[r + 5] == 0.0:
            continue
        rad = F[r + 2]
        wx, wy = _to_world(Pa, F[r], F[r + 1])
        d, qx, qy, nx, ny = _point_vs(F, I, b, Pb, wx, wy)
        gap = d - rad
        if gap >= margin:
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
            if gap >= margin:
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
            _push(out, n, i, j, gap, sx, sy, wx, wy, vx, vy, 0.0, False)
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
    """Candidates of every known pair written into ``out`` (cap, 10); returns their number n.

    ``counts[k]`` receives the rows of pair k, -1 for a pair left to the Python fallback (a
    body with an unknown parametric piece). When ``n > cap`` the buffer was too small (its
    rows are incomplete and n is an upper bound): call again with at least n rows.
    """
    n = 0
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
        n = _corners_vs(F, I, a, Pa, b, Pb, m, False, out, n, a, b)
        n = _corners_vs(F, I, b, Pb, a, Pa, m, True, out, n, a, b)
        n = _arcs_vs(F, I, a, Pa, b, Pb, m, False, out, n, a, b)
        n = _arcs_vs(F, I, b, Pb, a, Pa, m, True, out, n, a, b)
        n = _params_vs_lines(F, I, a, Pa, b, Pb, m, False, out, n, a, b)
        n = _params_vs_lines(F, I, b, Pb, a, Pa, m, True, out, n, a, b)
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


def _array(x) -> np.ndarray:
    """``x`` as a writable C-contiguous float64 array (one compiled signature)."""
    if (
        type(x) is np.ndarray
        and x.dtype == np.float64
        and x.flags.c_contiguous
        and x.flags.writeable
    ):
        return x
    return np.array(x, dtype=np.float64, order="C")


class ContactSearch:
    """The compiled contact search over one :class:`PackedOutlines`, with its scratch buffers
    (the mutable half of a model/data split: one per world, reused every step).

    Calling it gives :func:`find_contacts_packed`'s rows (a new array each call).
    """

    def __init__(self, packed: PackedOutlines, capacity: int = 32) -> None:
        self.packed = packed
        self._nb = len(packed.outlines)
        self._np = len(packed.pairs)
        self._out = np.empty((max(int(capacity), 1), 10))
        self._counts = np.empty(self._np, np.int64)

    def __call__(self, poses, margins) -> np.ndarray:
        """Rows ``(i, j, gap, pax, pay, pbx, pby, nx, ny, curvature)`` (n, 10); see
        :func:`find_contacts_packed` for the arguments."""
        pk = self.packed
        poses = _array(poses)
        if poses.shape != (self._nb, 3):
            raise InvalidParameter(
                f"poses: expected shape ({self._nb}, 3) [m, m, rad], got {poses.shape}"
            )
        margins = self._margins(margins)
        n = contacts_into(pk.F, pk.I, poses, pk.pairs, margins, self._out, self._counts)
        if n > len(self._out):
            self._out = np.empty((2 * n, 10))
            n = contacts_into(pk.F, pk.I, poses, pk.pairs, margins, self._out, self._counts)
        rows = self._out[:n].copy()
        return rows if pk.all_known else self._fallback(rows, poses, margins)

    def _margins(self, margins) -> np.ndarray:
        if isinstance(margins, float | int):
            return np.full(self._np, float(margins))
        margins = _array(margins)
        if margins.shape == (self._np,):
            return margins
        if margins.size != 1:
            raise InvalidParameter(
                f"margins: expected one float or shape ({self._np},) [m], got {margins.shape}"
            )
        return np.full(self._np, float(margins.ravel()[0]))

    def _fallback(self, rows, poses, margins) -> np.ndarray:
        """Insert the Python candidates of the pairs the kernel skipped, in pair order."""
        pk = self.packed
        parts, at = [], 0
        for k, (i, j) in enumerate(pk.pairs):
            c = int(self._counts[k])
            if c >= 0:
                parts.append(rows[at : at + c])
                at += c
                continue
            oa, ob = pk.outlines[i], pk.outlines[j]
            got = candidates(oa, Pose(*poses[i]), ob, Pose(*poses[j]), float(margins[k]))
            parts.append(np.array([(i, j, *g) for g in got], float).reshape(-1, 10))
        return np.concatenate(parts) if parts else rows


def find_contacts_packed(packed: PackedOutlines, poses, margins) -> np.ndarray:
    """Contact candidates of the packed bodies at ``poses``.

    Args:
        packed: the bodies' outlines and the pairs to test.
        poses: (nb, 3) ``[x, y, angle]`` of each body's outline frame [m, rad].
        margins: (np,) per pair of ``packed.pairs`` (or one float): candidates with a gap
            below it are returned [m].

    Returns:
        (n, 10) rows ``(i, j, gap, pax, pay, pbx, pby, nx, ny, curvature)``: body indices (as
        floats), gap [m], touching points on i and on j [m], unit normal from j toward i,
        curvature of the touching feature [1/m] (inf at corners) - the tuples of
        :func:`planner.sim.planar.stepper.find_contacts`, in its order. A stepping loop keeps
        one :class:`ContactSearch` instead (same rows, no buffer allocation per call).
    """
    return ContactSearch(packed)(poses, margins)
