"""Envelopes of circles centred on a polyline: the traced and estimated curves (§3.2.1).

The construction is the thesis' own (§3.4.1): offset every sample along its normal (the
parallel curve, eq. 3.10, with fans of circles at corners), delete every offset point closer
than |offset| to the generating curve (those are the points the fingertip cannot reach
without penetrating, Fig. 3.3), and mark where the parallel curve is cut — the **interference
points**, at the crossing of the two branches on either side of each gap. No polygon
clipping is involved, so it does not suffer from the dense-polyline dropouts of GEOS'
``buffer`` (DESIGN.md caveat).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.geometry.offset_removal import removed_mask, rownorm


@dataclass(frozen=True)
class Envelope:
    """The kept part of an offset curve.

    Attributes:
        points: (M, 2) envelope points in order [m] (crossings inserted at gaps).
        normals: (M, 2) unit normals of the generator carried to the envelope.
        source: (M,) index of the generating sample (-1 for an inserted crossing).
        crossings: (K, 2) the crossing points, one per gap [m].
        crossing_index: (K,) their index in ``points``.
        removed: (N,) True for generator samples whose offset point was deleted.
    """

    points: np.ndarray
    normals: np.ndarray
    source: np.ndarray
    crossings: np.ndarray
    crossing_index: np.ndarray
    removed: np.ndarray


def _segment_crossing(a0, a1, b0, b1) -> np.ndarray | None:
    """Intersection of the lines through (a0, a1) and (b0, b1), or None if parallel."""
    da, db = a1 - a0, b1 - b0
    den = da[0] * db[1] - da[1] * db[0]
    if abs(den) < 1e-300:
        return None
    t = ((b0[0] - a0[0]) * db[1] - (b0[1] - a0[1]) * db[0]) / den
    return a0 + t * da


def _circle3(p0, p1, p2):
    """Centre and radius of the circle through three points, or None if collinear."""
    ax, ay = p1 - p0
    bx, by = p2 - p0
    den = 2 * (ax * by - ay * bx)
    scale = max(np.hypot(ax, ay), np.hypot(bx, by))
    if abs(den) < 1e-9 * scale * scale:
        return None
    ux = (by * (ax * ax + ay * ay) - ay * (bx * bx + by * by)) / den
    uy = (ax * (bx * bx + by * by) - bx * (ax * ax + ay * ay)) / den
    c = p0 + np.array([ux, uy])
    return c, float(np.hypot(ux, uy))


def _refine_crossing(x, A, B):
    """Refine a crossing ``x`` of two branches through 3-point circles A and B (lists of
    three points each): the intersection of the fitted circles (or lines) nearest to x."""
    ca, cb = _circle3(*A), _circle3(*B)
    cands = []
    if ca is not None and cb is not None:
        (c1, r1), (c2, r2) = ca, cb
        d = np.linalg.norm(c2 - c1)
        if d > 0 and abs(r1 - r2) <= d <= r1 + r2:
            a = (r1 * r1 - r2 * r2 + d * d) / (2 * d)
            hh = np.sqrt(max(r1 * r1 - a * a, 0.0))
            m = c1 + a * (c2 - c1) / d
            perp = np.array([-(c2 - c1)[1], (c2 - c1)[0]]) / d
            cands = [m + hh * perp, m - hh * perp]
    elif (ca is None) != (cb is None):
        (c, rr), (p0, p1) = (ca, (A[0], A[2])) if cb is None else (cb, (B[0], B[2]))
        if cb is None:
            p0, p1 = B[0], B[2]
        else:
            p0, p1 = A[0], A[2]
        u = (p1 - p0) / np.linalg.norm(p1 - p0)
        w = p0 - c
        bq = float(w @ u)
        disc = bq * bq - (float(w @ w) - rr * rr)
        if disc >= 0:
            cands = [p0 + (-bq + sq) * u for sq in (np.sqrt(disc), -np.sqrt(disc))]
    if not cands:
        return x
    best = min(cands, key=lambda c: np.linalg.norm(c - x))
    step = max(np.linalg.norm(A[2] - A[0]), np.linalg.norm(B[2] - B[0]))
    return best if np.linalg.norm(best - x) < step else x


def _branch_crossing(tail: np.ndarray, head: np.ndarray):
    """First crossing of the tail branch (walking back from the gap) with the head branch.

    Returns (point, tail segment index, head segment index) or None.
    """
    import shapely

    if len(tail) < 2 or len(head) < 2:
        return None
    T, H = shapely.LineString(tail), shapely.LineString(head)
    x = shapely.intersection(T, H)
    if x.is_empty:
        return None
    pts = np.array(
        [g.coords[0] for g in getattr(x, "geoms", [x]) if g.geom_type == "Point"]
        + [c for g in getattr(x, "geoms", [x]) if g.geom_type != "Point" for c in g.coords]
    )
    if len(pts) == 0:
        return None
    st = np.concatenate([[0.0], np.cumsum(rownorm(np.diff(tail, axis=0)))])
    sh = np.concatenate([[0.0], np.cumsum(rownorm(np.diff(head, axis=0)))])
    pos_t = np.array([T.project(shapely.Point(p)) for p in pts])
    pos_h = np.array([H.project(shapely.Point(p)) for p in pts])
    # the crossing nearest to the gap on both branches: latest along the tail
    j = int(np.argmax(pos_t - pos_h))
    it = int(np.clip(np.searchsorted(st, pos_t[j], side="right") - 1, 0, len(tail) - 2))
    ih = int(np.clip(np.searchsorted(sh, pos_h[j], side="right") - 1, 0, len(head) - 2))
    return pts[j], it, ih


def offset_envelope(
    points: np.ndarray,
    normals: np.ndarray,
    offset: float,
    closed: bool,
    exclude: np.ndarray | None = None,
) -> Envelope:
    """The part of ``points + offset * normals`` at distance >= |offset| from the curve.

    Args:
        points: (N, 2) generator samples [m] (corner fans: repeated points with turning
            normals).
        normals: (N, 2) unit normals; positive ``offset`` moves along them.
        offset: signed offset distance [m] (the fingertip radius, or minus it).
        closed: whether the generator is a closed curve.
        exclude: (N,) samples whose offset points are removed regardless (the fans of
            corners that turn towards the offset side, which can never be on the envelope).

    Returns:
        :class:`Envelope`. Each gap's crossing is the intersection of the two branches next
        to it, refined through 3-point circles (exact on lines and arcs).
    """
    P = np.asarray(points, float)
    N = np.asarray(normals, float)
    r = abs(offset)
    Q = P + offset * N
    n = len(P)
    seg = rownorm(np.diff(P, axis=0))
    h = float(np.median(seg[seg > 0])) if np.any(seg > 0) else r
    removed = removed_mask(P, Q, r, closed, exclude, h)
    keep = ~removed
    if not keep.any():
        return Envelope(
            np.empty((0, 2)),
            np.empty((0, 2)),
            np.empty(0, int),
            np.empty((0, 2)),
            np.empty(0, int),
            removed,
        )
    order = np.arange(n)
    if closed and not keep[0]:
        order = np.roll(order, -int(np.argmax(keep)))
    kq, Qo, No = keep[order].copy(), Q[order], N[order]
    window = max(4, int(np.ceil(0.5 * r / h)))
    crossings, normals_x, after = [], [], []
    # walk the gaps; trimming may merge or shift them, so recompute as we go
    gaps = _gaps(kq, closed)
    for g, (a, b) in enumerate(gaps):
        if not kq[a % n]:
            continue  # merged into the previous gap by its trimming
        # search windows stop at the neighbouring gaps: each branch belongs to one gap
        lo = a - window if g == 0 else max(a - window, gaps[g - 1][1])
        hi = b + window if g == len(gaps) - 1 else min(b + window, gaps[g + 1][0])
        x, ta, hb = _gap_crossing(Qo, kq, a, b, lo, hi, closed, r)
        nn = No[ta] + No[hb]
        nrm = np.linalg.norm(nn)
        crossings.append(np.asarray(x, float))
        normals_x.append(nn / nrm if nrm > 1e-12 else No[ta])
        after.append(ta)
    return _assemble(Qo, No, order, kq, crossings, normals_x, after)


def _gaps(kq: np.ndarray, closed: bool) -> list[tuple[int, int]]:
    """The runs of removed samples as (last kept before, first kept after) index pairs (the
    wrap-around gap of a closed curve ends past ``n``)."""
    n = len(kq)
    kept = np.flatnonzero(kq)
    jumps = np.flatnonzero(np.diff(kept) > 1)
    gaps = [(int(kept[j]), int(kept[j + 1])) for j in jumps]
    if closed and len(kept) < n and (kept[-1] != n - 1 or kept[0] != 0):
        gaps.append((int(kept[-1]), int(kept[0]) + n))
    return gaps


def _gap_crossing(Qo, kq, a, b, lo, hi, closed, r):
    """The crossing [m] of the two offset branches around the gap ``(a, b)`` searched in
    ``[lo, hi]``, and the tail/head samples it joins. The branches' overshoot past the
    crossing is trimmed from ``kq`` (in place); without a branch crossing, the crossing of
    the gap's end segments (or their midpoint when that is farther than 4 r)."""
    n = len(Qo)
    if not closed:
        lo = max(lo, 0)
    idx_t = np.arange(lo, a + 2) % n
    idx_h = np.arange(b - 1, hi + 1)
    if not closed:
        idx_t = idx_t[(idx_t >= 0) & (idx_t < n)]
        idx_h = idx_h[idx_h < n]
    idx_h = idx_h % n
    res = _branch_crossing(Qo[idx_t], Qo[idx_h])
    if res is None:
        bb = b % n
        a1, b0 = (a + 1) % n, (b - 1) % n
        x = _segment_crossing(Qo[a], Qo[a1], Qo[b0], Qo[bb])
        if x is None or np.linalg.norm(x - Qo[a]) > 4 * r or np.linalg.norm(x - Qo[bb]) > 4 * r:
            x = 0.5 * (Qo[a] + Qo[bb])
        return x, a, bb
    x, it, ih = res
    ta, hb = int(idx_t[it]), int(idx_h[ih + 1])
    kq[idx_t[it + 1 :]] = False
    kq[idx_h[: ih + 1]] = False
    kq[ta] = True
    kq[hb] = True
    if closed or (ta >= 1 and hb + 1 < n):
        tail = _local_piece(Qo, ta, closed, head=False)
        head = _local_piece(Qo, hb - 1, closed, head=True)
        x = _refine_crossing(np.asarray(x), tail, head)
    return x, ta, hb


def _local_piece(Q, i: int, closed: bool, head: bool) -> list:
    """Three points [m] whose circle (or line) stands for a branch on its crossing segment
    ``(i, i + 1)`` in :func:`_refine_crossing`: the samples around the segment's kept end
    (``i + 1`` on the head branch, ``i`` on the tail), as before, unless either triple of
    samples that holds the segment is collinear - then the segment lies on a straight
    piece and its two ends (and their midpoint) are returned. The centred triple can
    straddle the junction of a straight piece with a curved one (a wall's offset meeting
    its top corner's fan when the step is less than a sample spacing taller than the
    fingertip radius): its circle put the interference point 66 nm off the exact
    ``(x0 - r, r)``. Noisy samples are never collinear: they keep the centred triple."""
    n = len(Q)
    k = i + 1 if head else i
    centred = [Q[(k - 1) % n], Q[k % n], Q[(k + 1) % n]]
    if not closed and (i - 1 < 0 or i + 2 >= n):
        return centred
    p = [Q[m % n] for m in (i - 1, i, i + 1, i + 2)]
    if _circle3(p[0], p[1], p[2]) is None or _circle3(p[1], p[2], p[3]) is None:
        return [p[1], 0.5 * (p[1] + p[2]), p[2]]
    return centred


def _assemble(Qo, No, order, kq, crossings, normals_x, after) -> Envelope:
    """The kept offset samples with the crossings inserted after their tail samples."""
    n = len(Qo)
    kept = np.flatnonzero(kq)
    out_p, out_n, out_src = Qo[kept], No[kept], order[kept]
    cross_idx = np.empty(0, int)
    if crossings:
        ins = np.searchsorted(kept, np.array(after), side="right")
        srt = np.argsort(ins, kind="stable")
        ins = ins[srt]
        out_p = np.insert(out_p, ins, np.array(crossings)[srt], axis=0)
        out_n = np.insert(out_n, ins, np.array(normals_x)[srt], axis=0)
        out_src = np.insert(out_src, ins, -1)
        cross_idx = ins + np.arange(len(ins))
        crossings = list(np.array(crossings)[srt])
    removed_out = np.ones(n, bool)
    removed_out[order[kept]] = False
    return Envelope(
        out_p, out_n, out_src, np.array(crossings).reshape(-1, 2), cross_idx, removed_out
    )


def polyline_normals(
    points: np.ndarray, closed: bool, corner_angle: float, fan_step: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Generator samples for offsetting a polyline: vertex normals, with fans at corners.

    Smooth vertices (turning angle <= ``corner_angle``) get the bisector of their two
    segment normals; corners get a fan of normals from the incoming to the outgoing segment
    normal in steps of at most ``fan_step`` [rad] (the buffer construction).

    Returns:
        (points (M, 2), normals (M, 2), vertex index (M,), signed turn of that vertex (M,)
        [rad], left/concave positive).
    """
    P = np.asarray(points, float)
    n = len(P)
    d = np.diff(np.vstack([P, P[:1]]) if closed else P, axis=0)
    t = d / rownorm(d)[:, None]
    seg_n = np.stack([-t[:, 1], t[:, 0]], axis=-1)
    if closed:
        n_in, n_out = np.roll(seg_n, 1, axis=0), seg_n
    else:
        n_in = np.vstack([seg_n[:1], seg_n])
        n_out = np.vstack([seg_n, seg_n[-1:]])
    cross = n_in[:, 0] * n_out[:, 1] - n_in[:, 1] * n_out[:, 0]
    turn = np.arctan2(cross, np.einsum("ij,ij->i", n_in, n_out))
    bis = n_in + n_out
    bis /= np.maximum(rownorm(bis), 1e-300)[:, None]
    sharp = np.abs(turn) > corner_angle
    if not sharp.any():
        return P, bis, np.arange(n), turn
    counts = np.ones(n, int)
    counts[sharp] = np.maximum(2, np.ceil(np.abs(turn[sharp]) / fan_step)).astype(int) + 1
    vid = np.repeat(np.arange(n), counts)
    normals = bis[vid]
    rows = np.flatnonzero(sharp[vid])  # the fan samples only: trigonometry where needed
    v = vid[rows]
    frac = (rows - (np.cumsum(counts) - counts)[v]) / (counts[v] - 1)
    ang = np.arctan2(n_in[v, 1], n_in[v, 0]) + frac * turn[v]
    normals[rows, 0] = np.cos(ang)
    normals[rows, 1] = np.sin(ang)
    return P[vid], normals, vid, turn[vid]


__all__ = ["Envelope", "offset_envelope", "polyline_normals"]
