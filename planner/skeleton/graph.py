"""Skeleton graphs: degrees, components, arcs, pruning of terminal arcs, longest paths.

A skeleton is stored as ``points`` (K, 2) [m] and ``edges`` (E, 2) integer indices into
``points``. Everything here is vectorized with numpy and ``scipy.sparse.csgraph`` (no
networkx): an *arc* is a maximal chain of edges whose inner nodes have degree 2 (thesis
§4.4.3: "skeleton arcs"); a *terminal arc* ends in an end point (degree 1).
"""

from __future__ import annotations

import numpy as np
from scipy import sparse
from scipy.sparse import csgraph


def edge_lengths(points: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Euclidean length of every edge.

    Args:
        points: (K, 2) node positions [m].
        edges: (E, 2) node indices.

    Returns:
        (E,) edge lengths [m].
    """
    if edges.size == 0:
        return np.zeros(0)
    d = points[edges[:, 0]] - points[edges[:, 1]]
    return np.hypot(d[:, 0], d[:, 1])


def degrees(n: int, edges: np.ndarray) -> np.ndarray:
    """(n,) number of edges at each node."""
    return np.bincount(edges.ravel(), minlength=n)


def adjacency(n: int, edges: np.ndarray, weights: np.ndarray | None = None) -> sparse.csr_matrix:
    """Symmetric (n, n) sparse adjacency matrix, weighted by ``weights`` (E,) if given.

    Zero weights are replaced by a tiny positive value so that csgraph keeps the edge.
    """
    w = np.ones(len(edges)) if weights is None else np.maximum(weights, 1e-300)
    m = sparse.coo_matrix((w, (edges[:, 0], edges[:, 1])), shape=(n, n))
    return (m + m.T).tocsr()


def component_labels(n: int, edges: np.ndarray) -> tuple[int, np.ndarray]:
    """Connected components: ``(count, labels (n,))`` (isolated nodes are their own)."""
    return csgraph.connected_components(adjacency(n, edges), directed=False)


def largest_component_mask(n: int, edges: np.ndarray) -> np.ndarray:
    """(E,) mask of the edges of the connected component with the most edges.

    Implements the thesis' rule for sharply turning features (§4.4.3, Fig. 4.13): "the
    connected skeleton with the most edges can be taken as the medial axis".
    """
    if len(edges) == 0:
        return np.zeros(0, dtype=bool)
    _, labels = component_labels(n, edges)
    per_edge = labels[edges[:, 0]]
    counts = np.bincount(per_edge)
    return per_edge == int(np.argmax(counts))


def arc_labels(n: int, edges: np.ndarray) -> tuple[int, np.ndarray]:
    """Split a graph into arcs (chains between nodes whose degree is not 2).

    Returns:
        ``(count, labels)``: ``labels`` (E,) is the arc index of every edge. A closed loop of
        degree-2 nodes is one arc.
    """
    if len(edges) == 0:
        return 0, np.zeros(0, dtype=np.int64)
    deg = degrees(n, edges)
    inner = deg == 2
    both = inner[edges[:, 0]] & inner[edges[:, 1]]
    _, comp = component_labels(n, edges[both])
    lab = np.where(
        inner[edges[:, 0]], comp[edges[:, 0]], np.where(inner[edges[:, 1]], comp[edges[:, 1]], -1)
    )
    lone = lab < 0
    lab[lone] = n + np.flatnonzero(lone)
    uniq, inv = np.unique(lab, return_inverse=True)
    return len(uniq), inv.ravel()


def terminal_arcs(
    n: int, edges: np.ndarray, lengths: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Arcs and which of them are terminal.

    Args:
        n: number of nodes.
        edges: (E, 2) node indices.
        lengths: (E,) edge lengths [m].

    Returns:
        ``(labels (E,), arc_length (A,) [m], terminal (A,) bool)``; an arc is terminal when
        exactly one of its ends is an end point (an arc with two end points is a whole
        component and never terminal).
    """
    count, labels = arc_labels(n, edges)
    deg = degrees(n, edges)
    arc_len = np.bincount(labels, weights=lengths, minlength=count)
    ends = (deg[edges[:, 0]] == 1).astype(int) + (deg[edges[:, 1]] == 1)
    n_ends = np.bincount(labels, weights=ends, minlength=count)
    return labels, arc_len, n_ends == 1


def prune_terminal_arcs(
    points: np.ndarray, edges: np.ndarray, min_length: float, max_rounds: int = 50
) -> np.ndarray:
    """Remove terminal arcs shorter than ``min_length``, repeatedly; when every remaining
    arc is a short terminal one, the longest is kept (the graph is never emptied).

    Implements the thesis' arc pruning (§4.4.3, Fig. 4.12): "removing the skeleton arcs which
    are smaller than a threshold length, defined using the noise present in the data".

    Args:
        points: (K, 2) node positions [m].
        edges: (E, 2) node indices.
        min_length: arcs ending in an end point and shorter than this are removed [m]
            (``inf`` removes every terminal arc: what remains are loops and the paths
            between them).
        max_rounds: safety bound on the number of peeling rounds.

    Returns:
        (E,) mask of the edges kept.
    """
    keep = np.ones(len(edges), dtype=bool)
    n = len(points)
    lengths = edge_lengths(points, edges)
    for _ in range(max_rounds):
        sub = np.flatnonzero(keep)
        if sub.size == 0:
            break
        labels, arc_len, term = terminal_arcs(n, edges[sub], lengths[sub])
        drop_arc = term & (arc_len < min_length)
        if not drop_arc.any():
            break
        if drop_arc[labels].all():  # everything is short: keep the longest arc
            drop_arc[np.argmax(np.where(drop_arc, arc_len, -np.inf))] = False
        keep[sub[drop_arc[labels]]] = False
    return keep


def longest_path(points: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Node indices of the longest shortest path (the diameter) of the component of node 0's
    largest component; for a tree this is its longest path.

    Args:
        points: (K, 2) node positions [m].
        edges: (E, 2) node indices (a forest; the component with most edges is used).

    Returns:
        (P,) node indices along the path, end to end.
    """
    n = len(points)
    if len(edges) == 0:
        return np.zeros(0, dtype=np.int64)
    graph = adjacency(n, edges, edge_lengths(points, edges))
    start = int(edges[largest_component_mask(n, edges)][0, 0])
    d0 = csgraph.dijkstra(graph, directed=False, indices=start)
    a = int(np.argmax(np.where(np.isfinite(d0), d0, -1.0)))
    d1, pred = csgraph.dijkstra(graph, directed=False, indices=a, return_predecessors=True)
    b = int(np.argmax(np.where(np.isfinite(d1), d1, -1.0)))
    path = [b]
    while path[-1] != a:
        path.append(int(pred[path[-1]]))
    return np.asarray(path[::-1], dtype=np.int64)


def path_edges(path: np.ndarray) -> np.ndarray:
    """(P-1, 2) edges joining consecutive nodes of ``path`` (P,)."""
    return np.column_stack([path[:-1], path[1:]]) if len(path) > 1 else np.zeros((0, 2), int)


def has_cycle(n: int, edges: np.ndarray) -> bool:
    """Whether the graph has a cycle (E > K - C over the nodes that carry edges)."""
    if len(edges) == 0:
        return False
    used = np.unique(edges)
    count, labels = component_labels(n, edges)
    n_comp = len(np.unique(labels[used]))
    return len(edges) > used.size - n_comp


def merge_close_points(
    points: np.ndarray, edges: np.ndarray, tol: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Merge nodes closer than ``tol`` (qhull may emit nearly equal Voronoi vertices for
    cocircular samples) and drop the self-loops and repeated edges this creates.

    Args:
        points: (K, 2) node positions [m].
        edges: (E, 2) node indices.
        tol: merge distance [m].

    Returns:
        ``(points (K', 2), edges (E', 2), source (E',))``: ``source`` is the index in the
        input ``edges`` of each output edge; merged nodes sit at their group's first node.
        Unused nodes are dropped; ``points`` may have extra columns (carried along).
    """
    from scipy.spatial import cKDTree

    src = np.arange(len(edges))
    if len(points) and len(edges):
        used = np.unique(edges)
        pairs = used[cKDTree(points[used, :2]).query_pairs(tol, output_type="ndarray")]
        if len(pairs):
            _, rep = component_labels(len(points), pairs)
            first = np.full(rep.max() + 1, -1)
            order = np.arange(len(points))[::-1]
            first[rep[order]] = order
            e = np.sort(rep[edges], axis=1)
            ok = np.flatnonzero(e[:, 0] != e[:, 1])
            _, idx = np.unique(e[ok], axis=0, return_index=True)
            src = ok[np.sort(idx)]
            edges = first[e[src]]
    pts, new_edges = compact(points, edges)
    return pts, new_edges, src


def compact(
    points: np.ndarray, edges: np.ndarray, *per_point: np.ndarray
) -> tuple[np.ndarray, ...]:
    """Drop nodes no edge uses and renumber edges.

    Args:
        points: (K, 2) node positions.
        edges: (E, 2) node indices.
        *per_point: further (K, ...) arrays to subset alike (e.g. radii).

    Returns:
        ``(points, edges, *per_point)`` restricted to the used nodes.
    """
    used = np.unique(edges)
    remap = np.full(len(points), -1, dtype=np.int64)
    remap[used] = np.arange(used.size)
    new_edges = remap[edges] if len(edges) else np.zeros((0, 2), dtype=np.int64)
    return (points[used], new_edges.reshape(-1, 2), *(a[used] for a in per_point))


__all__ = [
    "adjacency",
    "arc_labels",
    "compact",
    "component_labels",
    "degrees",
    "edge_lengths",
    "has_cycle",
    "largest_component_mask",
    "longest_path",
    "merge_close_points",
    "path_edges",
    "prune_terminal_arcs",
    "terminal_arcs",
]
