"""Significance pruning of a medial axis: peel what the boundary data cannot resolve.

The medial axis is unstable: a boundary moved by ``delta`` can grow a branch of any length
(a near-circle's axis is a point, an ellipse's with semi-axes ``a >= b`` a segment of length
``2 (a - b^2 / a)``, about ``4 (a - b)``; a dent of depth ``delta`` grows a spur across the
feature). The medial axis *transform* is stable in the other direction: the shape rebuilt
as the union of the medial disks changes little when an insignificant branch is removed.
This module peels end points of the skeleton while the shape rebuilt from what remains stays
within ``tolerance`` of the shape rebuilt from the whole skeleton (Hausdorff distance of the
unions of disks; Shaked & Bruckstein's "pruning medial axes", the residual of Ogniewicz that
the thesis cites in §4.4.3).

A disk ``(x, r_x)`` lies within ``e`` of the disk ``(y, r_y)`` when
``|x - y| + r_x - r_y <= e``, so the loss of removing a set ``S`` of skeleton points while
keeping ``K`` is ``max_{x in S} min_{y in K} (|x - y| + r_x - r_y)``. Points are peeled one
end point at a time, the end point of smallest loss first, until the next one would exceed
the tolerance. A genuine axis end is shortened by at most ``tolerance``; spurs and the axes of
near-circles whose disks the rest covers to within ``tolerance`` disappear.
"""

from __future__ import annotations

import numpy as np

from planner.skeleton import graph as g

__all__ = ["peel_insignificant"]


def _loss_matrix(points: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """(K, K) ``|p_i - p_j| + r_i - r_j`` [m]: how far disk ``i`` sticks out of disk ``j``."""
    d = np.hypot(*(points[:, None, :2] - points[None, :, :2]).transpose(2, 0, 1))
    return d + radii[:, None] - radii[None, :]


def peel_insignificant(
    points: np.ndarray, edges: np.ndarray, radii: np.ndarray, tolerance: float
) -> np.ndarray:
    """Peel end points while the rebuilt shape stays within ``tolerance``.

    Args:
        points: (K, 2) skeleton points [m].
        edges: (E, 2) point indices (a forest, or a graph with loops: loop points are never
            end points and stay).
        radii: (K,) medial radius of each point [m].
        tolerance: largest Hausdorff change of the union of medial disks [m].

    Returns:
        (K,) mask of the points kept (at least one point of each connected piece).
    """
    n = len(points)
    alive = np.ones(n, dtype=bool)
    if n < 2 or len(edges) == 0 or tolerance <= 0:
        return alive
    D = _loss_matrix(np.asarray(points, float), np.asarray(radii, float))
    deg = g.degrees(n, edges).astype(np.int64)
    nbrs = [[] for _ in range(n)]
    for a, b in edges:
        nbrs[a].append(b)
        nbrs[b].append(a)
    removed = np.zeros(n, dtype=bool)
    cover = np.full(n, -np.inf)  # loss of each removed point against the alive ones
    owner = np.full(n, -1)  # the alive point covering it best
    while True:
        leaves = np.flatnonzero(alive & (deg == 1))
        if leaves.size == 0:
            break
        best, best_loss = -1, np.inf
        for leaf in leaves:
            loss = _peel_loss(D, alive, removed, cover, owner, leaf)
            if loss < best_loss:
                best, best_loss = leaf, loss
        if best_loss > tolerance:
            break
        alive[best] = False
        removed[best] = True
        for j in nbrs[best]:
            deg[j] -= 1
        deg[best] = 0
        stale = removed & ((owner == best) | (np.arange(n) == best))
        cols = np.flatnonzero(alive)
        sub = D[np.ix_(np.flatnonzero(stale), cols)]
        cover[stale] = sub.min(axis=1)
        owner[stale] = cols[sub.argmin(axis=1)]
    return alive


def _peel_loss(D, alive, removed, cover, owner, leaf: int) -> float:
    """Loss [m] after also removing ``leaf``: the largest cover of the removed points."""
    keep = alive.copy()
    keep[leaf] = False
    if not keep.any():
        return np.inf
    own = float(D[leaf, keep].min())
    hit = removed & (owner == leaf)
    rest = float(cover[removed & ~hit].max()) if (removed & ~hit).any() else 0.0
    moved = (
        float(D[np.ix_(np.flatnonzero(hit), np.flatnonzero(keep))].min(axis=1).max())
        if hit.any()
        else 0.0
    )
    return max(own, rest, moved)
