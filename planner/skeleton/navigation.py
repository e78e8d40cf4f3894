"""Using the feature map: safest paths, unexplored regions, the full negative MAT
(thesis §4.5.3 and §5.3).

- :func:`safest_path`: "if the goal is to avoid features, the trajectory of the global
  skeleton depicts the safest navigation path that is the farthest from all features" — a
  shortest path along the global skeleton, using only edges wide enough for the fingertip.
- :func:`region_report`: "larger regions that do not closely bound a feature (to within a
  fingertip diameter) may need to be explored further".
- :func:`negative_medial_axis`: the full negative MAT (medial axis of the space between
  features, including arcs equidistant from two points of one feature), for comparison
  with the global skeleton.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from scipy.sparse import csgraph
from scipy.spatial import cKDTree

from planner import checks
from planner.errors import InfeasibleProblem, InvalidParameter
from planner.skeleton import graph as g
from planner.skeleton.feature import Skeleton, SkeletonSettings, voronoi
from planner.skeleton.global_map import GlobalSkeleton, with_far_points
from planner.skeleton.region import boundary_loops, estimate_spacing, region_polygon
from planner.skeleton.segments import clip_segments, merge_segments, point_segment_distance


@dataclass(frozen=True)
class NavigationPath:
    """A path along the global skeleton.

    Attributes:
        points: (P, 2) way points from start to goal [m].
        length: path length [m].
        min_clearance: smallest distance from the path's skeleton edges to a feature
            boundary [m] (the start and goal legs are not counted).
    """

    points: np.ndarray
    length: float
    min_clearance: float


def _point(value: object, name: str) -> np.ndarray:
    """A (1, 2) finite point from an (x, y) pair, or InvalidParameter."""
    arr = checks.points(name, np.atleast_2d(np.asarray(value, dtype=object)), dims=(2,))
    if arr.shape != (1, 2):
        raise InvalidParameter(f"{name}: expected one (x, y) point [m], got {checks.shown(value)}")
    return arr


def safest_path(
    gs: GlobalSkeleton, start: np.ndarray, goal: np.ndarray, tip_radius: float = 0.0
) -> NavigationPath:
    """Shortest path along the global skeleton between two points, avoiding features.

    ``start`` and ``goal`` are joined to the closest point of their nearest usable edge; only
    edges whose clearance (smallest disk radius on them) is at least ``tip_radius`` are used.

    Args:
        gs: the global skeleton.
        start: (2,) start point [m].
        goal: (2,) goal point [m].
        tip_radius: fingertip radius r_f [m] (0 uses every edge).

    Returns:
        :class:`NavigationPath`.

    Raises:
        InfeasibleProblem: no path along edges of sufficient clearance.
    """
    s, t = _point(start, "start"), _point(goal, "goal")
    r = checks.nonnegative("tip_radius", tip_radius, "m")
    ok = gs.edge_clearance >= r
    edges = gs.edges[ok]
    if len(edges) == 0:
        raise InfeasibleProblem(
            f"no global skeleton edge has clearance >= tip_radius {r:g} m "
            f"(largest: {gs.edge_clearance.max(initial=0.0):g} m)"
        )
    clearance = gs.edge_clearance[ok]
    seg = gs.points[edges]
    # join start and goal to their nearest usable edge at its closest point (nodes n, n+1)
    n = len(gs.points)
    extra_pts, extra_edges, extra_clear = [], [], []
    for k, p in enumerate((s[0], t[0])):
        d = point_segment_distance(np.broadcast_to(p, (len(seg), 2)), seg)
        e = int(np.argmin(d))
        a0, d0 = seg[e, 0], seg[e, 1] - seg[e, 0]
        tt = float(np.clip(np.dot(p - a0, d0) / max(np.dot(d0, d0), 1e-300), 0.0, 1.0))
        extra_pts.append(a0 + tt * d0)
        extra_edges += [(n + k, edges[e, 0]), (n + k, edges[e, 1])]
        extra_clear += [clearance[e], clearance[e]]
    if np.allclose(extra_pts[0], extra_pts[1]) or set(extra_edges[0:2]) == set(extra_edges[2:4]):
        extra_edges.append((n, n + 1))  # both on the same edge
        extra_clear.append(min(extra_clear))
    all_pts = np.vstack([gs.points, extra_pts])
    all_edges = np.vstack([edges, np.array(extra_edges)])
    all_clear = np.concatenate([clearance, extra_clear])
    graph = g.adjacency(len(all_pts), all_edges, g.edge_lengths(all_pts, all_edges))
    dist, pred = csgraph.dijkstra(graph, directed=False, indices=n, return_predecessors=True)
    if not np.isfinite(dist[n + 1]):
        raise InfeasibleProblem(
            f"start and goal are not connected along global skeleton edges with clearance "
            f">= tip_radius {r:g} m"
        )
    path = [n + 1]
    while path[-1] != n:
        path.append(int(pred[path[-1]]))
    nodes = np.asarray(path[::-1])
    pts = np.vstack([s, all_pts[nodes], t])
    pts = pts[np.r_[True, np.any(np.diff(pts, axis=0) != 0, axis=1)]]
    length = float(np.hypot(*np.diff(pts, axis=0).T).sum())
    key = {tuple(e): c for e, c in zip(np.sort(all_edges, axis=1).tolist(), all_clear, strict=True)}
    pair = np.sort(np.column_stack([nodes[:-1], nodes[1:]]), axis=1)
    clear = min((key[tuple(q)] for q in pair.tolist()), default=np.inf)
    return NavigationPath(pts, length, float(clear))


@dataclass(frozen=True)
class RegionInfo:
    """How well a region of the feature map is explained by its feature.

    Attributes:
        feature: feature index.
        area: region area [m^2].
        feature_area: area enclosed by the feature's boundary samples (0 if none) [m^2].
        largest_gap: radius of the largest disk in the region, outside the features, free
            of that feature's boundary samples [m] (room for an undiscovered feature).
        needs_exploration: ``largest_gap`` exceeds the threshold (a fingertip diameter).
    """

    feature: int
    area: float
    feature_area: float
    largest_gap: float
    needs_exploration: bool


def region_report(
    gs: GlobalSkeleton, tip_radius: float, step: float | None = None
) -> list[RegionInfo]:
    """Flag regions that do not closely bound their feature (thesis §4.5.3, §5.3).

    The largest gap is evaluated at the vertices of the Voronoi diagram of all boundary
    samples (the centres of maximal empty disks) and along the region outline sampled every
    ``step``; a region needs exploration when it exceeds one fingertip diameter
    ``2 tip_radius``.

    Args:
        gs: the global skeleton.
        tip_radius: fingertip radius r_f [m] (> 0).
        step: sampling step along region outlines [m] (default: 1/50 of the domain size).

    Returns:
        One :class:`RegionInfo` per feature, in input order.
    """
    r = checks.positive("tip_radius", tip_radius, "m")
    size = max(np.ptp(np.asarray(gs.domain.exterior.coords), axis=0))
    step = size / 50.0 if step is None else checks.positive("step", step, "m")
    allb = np.concatenate(gs.boundaries)
    tree = cKDTree(allb)
    feats = []
    for b in gs.boundaries:
        try:
            feats.append(region_polygon(b, boundary_loops(b, estimate_spacing(b))))
        except InvalidParameter:
            feats.append(shapely.Polygon())
    cand = voronoi(with_far_points(allb)).vertices
    x0, y0, x1, y1 = gs.domain.bounds
    cand = cand[(cand[:, 0] >= x0) & (cand[:, 0] <= x1) & (cand[:, 1] >= y0) & (cand[:, 1] <= y1)]
    out = []
    for i, reg in enumerate(gs.regions):
        if reg.is_empty:
            out.append(RegionInfo(i, 0.0, float(feats[i].area), 0.0, False))
            continue
        outline = shapely.get_coordinates(shapely.segmentize(reg.boundary, step))
        inside = cand[shapely.contains_xy(reg, cand[:, 0], cand[:, 1])]
        pts = np.vstack([outline, inside])
        free = (
            ~np.any(
                [shapely.contains_xy(f, pts[:, 0], pts[:, 1]) for f in feats if not f.is_empty],
                axis=0,
            )
            if any(not f.is_empty for f in feats)
            else np.ones(len(pts), dtype=bool)
        )
        gap = float(tree.query(pts[free])[0].max()) if free.any() else 0.0
        out.append(RegionInfo(i, float(reg.area), float(feats[i].area), gap, gap > 2 * r))
    return out


def negative_medial_axis(
    boundaries: list, spacing: float | None = None, margin: float | None = None
) -> Skeleton:
    """The full negative MAT: the DVMA of all boundary samples outside every feature.

    Unlike the global skeleton it keeps arcs equidistant from two samples of the *same*
    feature (e.g. inside a concave feature), which "would distort the description of feature
    spacing" (thesis §4.5.3). Edges between neighbouring samples of one contour (generators
    closer than ``2 spacing``) are dropped; the result is clipped to the global domain.

    Args:
        boundaries: list of (M_i, 2) boundary samples [m].
        spacing: sample spacing [m] (estimated per feature when None; the largest is used).
        margin: domain margin [m], as in :func:`global_skeleton`.

    Returns:
        A :class:`Skeleton` (radii: distance to the nearest sample [m]).
    """
    from planner.skeleton.global_map import check_boundaries, domain_polygon

    bnd = check_boundaries(boundaries, 4)
    if spacing is None:
        spacing = max(estimate_spacing(b) for b in bnd)
    spacing = checks.positive("spacing", spacing, "m")
    allb = np.concatenate(bnd)
    margin = None if margin is None else checks.nonnegative("margin", margin, "m")
    domain = domain_polygon(allb, margin)
    feats = []
    for b in bnd:
        try:
            feats.append(region_polygon(b, boundary_loops(b, spacing)))
        except InvalidParameter:
            pass
    vor = voronoi(with_far_points(allb))
    rp = np.asarray(vor.ridge_points, dtype=np.int64)
    rv = np.asarray(vor.ridge_vertices, dtype=np.int64).reshape(-1, 2)
    n = len(allb)
    keep = (rp < n).all(axis=1) & (rv >= 0).all(axis=1)
    gen = np.hypot(*(allb[np.minimum(rp[:, 0], n - 1)] - allb[np.minimum(rp[:, 1], n - 1)]).T)
    keep &= gen >= 2.0 * spacing
    seg, inside = clip_segments(vor.vertices[rv[keep]], domain.bounds)
    seg = seg[inside]
    mid = seg.mean(axis=1)
    out = np.ones(len(seg), dtype=bool)
    for f in feats:
        out &= ~shapely.contains_xy(f, mid[:, 0], mid[:, 1])
    points, edges = merge_segments(seg[out])
    scale = float(np.ptp(allb, axis=0).max()) or 1.0
    points, edges, _ = g.merge_close_points(points, edges, 1e-9 * scale)
    radii = cKDTree(allb).query(points)[0] if len(points) else np.zeros(0)
    return Skeleton(
        points,
        edges,
        radii,
        float(spacing),
        0.0,
        SkeletonSettings(),
        domain,
        {"negative_mat": len(edges)},
    )


__all__ = ["NavigationPath", "RegionInfo", "negative_medial_axis", "region_report", "safest_path"]
