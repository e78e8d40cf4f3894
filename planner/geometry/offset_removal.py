"""Which points of an offset curve lie off the envelope: distance tests (§3.2.1, §3.4.1).

Every offset point is at exactly the offset distance r from its own foot on the generator;
it belongs to the envelope unless some other part of the generator is closer than r. The
exact test is a distance to the generator polyline; dense generators are tested exactly on a
sub-sampling and their gap edges re-cut by :func:`planner.geometry.envelope.offset_envelope`.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree


def rownorm(a: np.ndarray) -> np.ndarray:
    """Euclidean norms of the rows of an (N, 2) array (np.hypot: faster than linalg.norm)."""
    return np.hypot(a[:, 0], a[:, 1])


def polyline_distance(
    queries: np.ndarray,
    vertices: np.ndarray,
    closed: bool,
    k: int = 6,
    side: int = 0,
    tie: float = 0.0,
) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Distance from each query point to the polyline through ``vertices`` [m].

    Exact for the segments adjacent to the ``k`` nearest vertices of each query, which
    is the nearest segment whenever the polyline is sampled finely relative to the distance.

    Args:
        queries: (M, 2) points [m].
        vertices: (N, 2) polyline vertices (consecutive duplicates allowed) [m].
        closed: whether the last vertex connects to the first.
        k: number of nearest vertices whose segments are examined.
        side: if +1 (or -1), also report which queries lie strictly on the right (left) side
            — the wrong side for an offset along the left (right) normals — of any segment
            within ``tie`` of the nearest distance.
        tie: distance slack for that side test [m].

    Returns:
        distances (M,) [m]; with ``side``, also the (M,) wrong-side flags.
    """
    V = vertices
    keep = np.ones(len(V), bool)
    keep[1:] = np.any(V[1:] != V[:-1], axis=1)
    V = V[keep]
    n = len(V)
    if n == 1:
        d = np.linalg.norm(queries - V[0], axis=1)
        return (d, np.zeros(len(d), bool)) if side else d
    tree = cKDTree(V)
    k = min(k, n)
    _, idx = tree.query(queries, k=k, workers=-1)
    idx = idx.reshape(len(queries), k)
    dists, crosses = [], []
    for shift in (-1, 0):
        a = idx + shift
        if closed:
            a %= n
            b = (a + 1) % n
            valid = np.ones_like(a, bool)
        else:
            valid = (a >= 0) & (a < n - 1)
            a = np.clip(a, 0, n - 2)
            b = a + 1
        A, B = V[a], V[b]
        AB = B - A
        AQ = queries[:, None, :] - A
        den = np.einsum("mkj,mkj->mk", AB, AB)
        t = np.clip(np.einsum("mkj,mkj->mk", AQ, AB) / np.where(den > 0, den, 1.0), 0.0, 1.0)
        d = np.linalg.norm(AQ - t[..., None] * AB, axis=-1)
        dists.append(np.where(valid, d, np.inf))
        if side:
            crosses.append(
                (AB[..., 0] * AQ[..., 1] - AB[..., 1] * AQ[..., 0])
                / np.sqrt(np.where(den > 0, den, 1.0))
            )
    D = np.concatenate(dists, axis=1)
    best = D.min(axis=1)
    if not side:
        return best
    C = np.concatenate(crosses, axis=1)
    near = D <= best[:, None] + tie
    wrong = np.any(near & (side * C < -tie), axis=1)
    return best, wrong


def _ball_removed(Q: np.ndarray, P: np.ndarray, r: float, h: float) -> np.ndarray:
    """Offset points certainly closer than ``r`` to the polyline through ``P``.

    Conservative: a point is flagged only when it lies within ``r - hs/2`` of a vertex of a
    sub-sampled generator (vertex spacing ``hs`` ≈ r/64), hence truly closer than r. The
    points it misses lie within ``hs`` of the envelope's edges and are trimmed by the
    crossing search. A KD-tree over the offset points answers the ball queries; exact ties
    (every offset point is at exactly r from its own foot) stay outside the shrunken balls,
    which keeps the bounded nearest-neighbour queries on the small sub-sampled tree cheap.
    """
    hs = r / 64.0
    m = max(1, int(hs / max(h, 1e-300)))
    sub = P[::m]
    if m > 1:
        sub = np.vstack([sub, P[-1:]])
    hs_true = float(np.max(rownorm(np.diff(sub, axis=0)), initial=0.0))
    radius = r - 0.5 * max(hs_true, 1e-9 * r)
    if radius <= 0:
        radius = r * (1 - 1e-9)
    d, _ = cKDTree(sub).query(Q, k=1, distance_upper_bound=radius, workers=-1)
    removed = np.isfinite(d)
    return removed


DIRECT_LIMIT = 4000  # generators up to this many samples get the direct exact test
COARSE_FRACTION = 1.0 / 32.0  # coarse spacing of the coarse-to-fine test, in offsets


def _removed_exact(P, Q, r, closed, exclude, h, tol=None) -> np.ndarray:
    """Exact test: offset points closer than ``r - tol`` to the polyline through ``P``.

    ``tol`` (default: the chords' largest possible sagitta h²/(4r)) keeps true ties — every
    offset point is at exactly r from its own foot — from being removed by chord error.
    """
    if tol is None:
        seg = rownorm(np.diff(P, axis=0))
        hmax = float(seg.max()) if len(seg) else 0.0
        tol = hmax * hmax / (4 * r) + 1e-12 * r
    removed = _ball_removed(Q, P, r, h)
    todo = ~removed
    if exclude is not None:
        todo &= ~exclude
    if todo.any():
        removed[todo] = polyline_distance(Q[todo], P, closed) < r - tol
    if exclude is not None:
        removed |= exclude
        _drop_tie_runs(removed, exclude, Q, r, closed)
    return removed


def _drop_tie_runs(
    removed: np.ndarray, exclude: np.ndarray, Q: np.ndarray, r: float, closed: bool
) -> None:
    """Remove, in place, kept runs shorter than r/4 that touch an excluded (concave-corner)
    sample.

    Both branches of a concave corner are cut before they reach it, so such runs are ties
    (offset points within the test's tolerance of the offset distance from a tangential
    neighbour, as where a wire touches a plane), not envelope.
    """
    n = len(removed)
    kept = ~removed
    if not kept.any() or not exclude.any():
        return
    idx = np.flatnonzero(kept)
    breaks = np.flatnonzero(np.diff(idx) > 1)
    starts = np.concatenate([[idx[0]], idx[breaks + 1]])
    ends = np.concatenate([idx[breaks], [idx[-1]]])
    for a, b in zip(starts, ends, strict=True):
        before, after = a - 1, b + 1
        if closed:
            before, after = before % n, after % n
        touch = (0 <= before < n and exclude[before]) or (0 <= after < n and exclude[after])
        if touch and np.sum(rownorm(np.diff(Q[a : b + 1], axis=0))) < r / 4:
            removed[a : b + 1] = True


def removed_mask(P, Q, r, closed, exclude, h) -> np.ndarray:
    """Which offset points are off the envelope.

    Up to :data:`DIRECT_LIMIT` samples: the exact test. Above: the exact test on a
    sub-sampling of spacing ≈ r/32, carried to the fine samples (a fine sample is removed when
    both coarse samples around it are); the edges of every gap are then re-cut exactly by the
    crossing search of :func:`offset_envelope` on the fine branches. Concavities narrower
    than the coarse spacing (r/32) are not resolved this way: smooth noisy data first.
    """
    n = len(P)
    hc = COARSE_FRACTION * r
    # sub-sample by the larger of the generator's and the offset curve's arclength, so that
    # both keep about hc between coarse samples (curved pieces and fans are sampled finely)
    step = np.maximum(rownorm(np.diff(P, axis=0)), rownorm(np.diff(Q, axis=0)))
    w = np.concatenate([[0.0], np.cumsum(step)])
    if n <= DIRECT_LIMIT or w[-1] / hc > n / 2:
        return _removed_exact(P, Q, r, closed, exclude, h)
    ci = np.searchsorted(w, np.arange(0.0, w[-1], hc))
    if exclude is not None:  # keep the edges of every excluded stretch
        edge = np.flatnonzero(np.diff(exclude.astype(np.int8)))
        ci = np.concatenate([ci, edge, edge + 1])
    ci = np.unique(np.concatenate([ci, [n - 1]]))
    k = np.searchsorted(ci, np.arange(n), side="right") - 1
    k1 = np.minimum(k + 1, len(ci) - 1)
    # how far the fine curve strays from the coarse chords: the coarse test's slack
    A, B = P[ci[k]], P[ci[k1]]
    AB, AX = B - A, P - A
    den = np.einsum("ij,ij->i", AB, AB)
    t = np.clip(np.einsum("ij,ij->i", AX, AB) / np.where(den > 0, den, 1.0), 0.0, 1.0)
    dev = float(np.max(rownorm(AX - t[:, None] * AB)))
    rc = _removed_exact(
        P[ci],
        Q[ci],
        r,
        closed,
        None if exclude is None else exclude[ci],
        hc,
        tol=dev + hc * hc / (4 * r) + 1e-12 * r,
    )
    removed = np.where(ci[k] == np.arange(n), rc[k], rc[k] & rc[k1])
    if exclude is not None:
        removed |= exclude
        _drop_tie_runs(removed, exclude, Q, r, closed)
    return removed


__all__ = ["polyline_distance", "removed_mask", "rownorm"]
