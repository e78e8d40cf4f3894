"""Feature skeletons: the discrete Voronoi medial axis (DVMA) of boundary samples, pruned
(thesis §4.4.3, Figs. 4.9-4.13).

Pipeline of :func:`feature_skeleton`, following the thesis (after Brandt & Algazi and
Ogniewicz):

1. Voronoi diagram of the boundary samples (the dual of qhull's Delaunay triangulation,
   :mod:`planner.skeleton.voronoi`); its finite edges are the DVMA (Fig. 4.11).
2. Keep the edges with both ends inside the feature region (rebuilt from the samples,
   :mod:`planner.skeleton.region`).
3. Edge-length pruning (Fig. 4.11): drop Voronoi edges longer than ``max_edge_length``.
   Medial-axis edges of a boundary sampled every ``s`` are at most about ``s`` long, and
   noise of standard deviation ``sigma`` moves a Voronoi vertex of medial radius ``r`` by
   about ``sigma r / s``, so the default threshold is ``2 s + 4 sigma (1 + r / s)``, with
   ``s`` the *local* spacing at the edge's two generating samples (the longer of their
   steps along the boundary: finger speed varies) and ``r`` the larger radius at the edge's
   ends; the skeleton stays connected. Then drop edges whose two generating samples are
   closer than ``min_generator_distance`` (default ``1.2 s + 2 sigma``, local: neighbours on
   the same side of the boundary) or subtend less than ``min_angle_deg`` (default 45
   degrees) seen from the edge's end of larger radius (noise spurs pointing from the axis
   to the boundary; Attali's theta-regular medial axis; a right-angle corner's branch
   subtends 90 degrees).
4. Keep the connected skeleton with the most edges (Fig. 4.13, sharply turning features).
5. Remove terminal arcs shorter than ``min_branch_length`` (Fig. 4.12; default
   ``2 s_90 + 4 sigma`` with ``s_90`` the 90th percentile of the spacing); with
   ``branching=False`` keep only the longest path (or, when the skeleton has loops, the
   loops and the paths between them).
6. Significance pruning (:mod:`planner.skeleton.significance`): peel end points while the
   shape rebuilt from the medial disks changes by less than ``min_significance`` (default
   0: off); it removes the spurs and the wandering axis that boundary errors grow on
   near-circular parts (a near-circle's medial axis is a point, a slightly elliptic one's
   a segment about four times the ellipticity long). Smooth outlines only: it also
   shortens the branches into sharp corners, by ``min_significance / (1 - sin(a/2))`` for a
   corner of angle ``a`` (whose tips the medial disks hardly reach).

The spacing ``s`` defaults to the median step (or nearest-neighbour distance for unordered
samples) and the noise ``sigma`` to a robust estimate from the residuals of local quadratic
fits along the boundary (:func:`planner.skeleton.region.estimate_noise`; it sees the
sawtooth of encoder-quantized positions, which second differences miss).

Each skeleton point carries its medial radius: the distance to its generating (= nearest)
boundary samples, so ``(points, radii)`` is the medial axis transform (MAT).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import shapely

from planner import checks
from planner.errors import InvalidParameter
from planner.skeleton import graph as g
from planner.skeleton.region import (
    boundary_loops,
    dedupe,
    estimate_noise,
    local_spacing,
    region_polygon,
    sampling_profile,
)
from planner.skeleton.significance import peel_insignificant
from planner.skeleton.voronoi import voronoi


@dataclass(frozen=True)
class SkeletonSettings:
    """Pruning settings of :func:`feature_skeleton`; ``None`` means "derive from spacing and
    noise" (see the module docstring for the defaults).

    Attributes:
        max_edge_length: longest Voronoi edge kept (thesis edge-length threshold) [m];
            ``None``: the local default of the module docstring.
        min_generator_distance: shortest distance between the two samples generating a kept
            Voronoi edge [m].
        min_angle_deg: smallest angle subtended by the generating samples of a kept edge,
            seen from its end of larger radius [deg] (0 disables the test).
        min_branch_length: terminal arcs shorter than this are pruned [m].
        min_significance: end points are peeled while the union of the medial disks moves
            by less than this (Hausdorff) [m]; 0 disables the stage.
        keep_largest: keep only the connected skeleton with the most edges (Fig. 4.13).
        branching: ``False`` for non-branching features: keep only the main path (Fig. 4.12).
        link_factor: samples closer than ``link_factor * spacing`` are neighbours on the
            boundary (used to rebuild the region) [-].
    """

    max_edge_length: float | None = None
    min_generator_distance: float | None = None
    min_branch_length: float | None = None
    min_angle_deg: float = 45.0
    min_significance: float = 0.0
    keep_largest: bool = True
    branching: bool = True
    link_factor: float = 3.0

    def __post_init__(self) -> None:
        for key in ("max_edge_length", "min_generator_distance", "min_branch_length"):
            if getattr(self, key) is not None:
                checks.nonnegative(key, getattr(self, key), "m")
        checks.nonnegative("min_significance", self.min_significance, "m")
        checks.in_range(
            "min_angle_deg", self.min_angle_deg, 0.0, 180.0, "deg", closed=(True, False)
        )
        checks.positive("link_factor", self.link_factor)
        for key in ("keep_largest", "branching"):
            if not isinstance(getattr(self, key), bool | np.bool_):
                raise InvalidParameter(f"{key}: expected True or False, got {getattr(self, key)!r}")

    @classmethod
    def of(cls, settings: SkeletonSettings | None = None, **overrides: object) -> SkeletonSettings:
        """``settings`` (default: all defaults) with the keyword ``overrides`` applied.

        Raises:
            InvalidParameter: an unknown setting or a bad value.
        """
        base = cls() if settings is None else settings
        if not isinstance(base, cls):
            raise InvalidParameter(
                f"settings: expected a SkeletonSettings, got {type(base).__name__}"
            )
        known = sorted(cls.__dataclass_fields__)
        unknown = sorted(set(overrides) - set(known))
        if unknown:
            raise InvalidParameter(
                f"feature_skeleton: unknown setting(s) {unknown}; expected any of {known}"
            )
        return replace(base, **overrides) if overrides else base

    def resolved(
        self, spacing: float, noise: float, spacing_high: float | None = None
    ) -> SkeletonSettings:
        """These settings with every ``None`` threshold replaced by its default at the
        typical ``spacing`` [m] (``feature_skeleton`` applies the edge thresholds with the
        local spacing of each edge); ``spacing_high``: spacing of the sparse parts [m]."""
        s_hi = spacing if spacing_high is None else max(spacing, spacing_high)
        return replace(
            self,
            max_edge_length=(
                2.0 * spacing + 4.0 * noise
                if self.max_edge_length is None
                else self.max_edge_length
            ),
            min_generator_distance=(
                1.2 * spacing + 2.0 * noise
                if self.min_generator_distance is None
                else self.min_generator_distance
            ),
            min_branch_length=(
                2.0 * s_hi + 4.0 * noise
                if self.min_branch_length is None
                else self.min_branch_length
            ),
        )


@dataclass(frozen=True)
class Skeleton:
    """A skeleton graph with its medial axis transform.

    Attributes:
        points: (K, 2) skeleton points in surface coordinates [m].
        edges: (E, 2) int indices into ``points``.
        radii: (K,) medial radius of each point: distance to the nearest boundary sample [m]
            (0 for a pseudo-skeleton).
        spacing: boundary sample spacing used [m].
        noise: boundary noise standard deviation used [m].
        settings: the resolved pruning settings.
        region: the feature region rebuilt from the samples (shapely geometry, or ``None``).
        stage_edges: number of edges after each pipeline stage (for reports).
    """

    points: np.ndarray
    edges: np.ndarray
    radii: np.ndarray
    spacing: float = 0.0
    noise: float = 0.0
    settings: SkeletonSettings = field(default_factory=SkeletonSettings)
    region: object = None
    stage_edges: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        for arr in (self.points, self.edges, self.radii):
            arr.setflags(write=False)

    @property
    def degrees(self) -> np.ndarray:
        """(K,) number of edges at each point."""
        return g.degrees(len(self.points), self.edges)

    @property
    def branch_points(self) -> np.ndarray:
        """Indices of points where three or more arcs meet (degree >= 3)."""
        return np.flatnonzero(self.degrees >= 3)

    @property
    def end_points(self) -> np.ndarray:
        """Indices of points with a single edge (degree 1)."""
        return np.flatnonzero(self.degrees == 1)

    @property
    def edge_lengths(self) -> np.ndarray:
        """(E,) length of each edge [m]."""
        return g.edge_lengths(self.points, self.edges)

    @property
    def length(self) -> float:
        """Total skeleton length [m]."""
        return float(self.edge_lengths.sum())

    @property
    def n_components(self) -> int:
        """Number of connected pieces."""
        if len(self.edges) == 0:
            return len(self.points)
        return g.component_labels(len(self.points), self.edges)[0]

    @property
    def has_loop(self) -> bool:
        """Whether the skeleton contains a closed loop (e.g. a ring feature)."""
        return g.has_cycle(len(self.points), self.edges)

    def graph(self):
        """(K, K) symmetric ``scipy.sparse`` adjacency matrix weighted by edge length [m]."""
        return g.adjacency(len(self.points), self.edges, self.edge_lengths)

    def segments(self) -> np.ndarray:
        """(E, 2, 2) edge end points [m], e.g. for ``LineCollection``."""
        return self.points[self.edges]


def dvma(boundary: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The unpruned discrete Voronoi medial axis: all finite Voronoi edges of the samples.

    Args:
        boundary: (M, 2) boundary samples [m].

    Returns:
        ``(vertices (V, 2) [m], edges (E, 2) int)`` (Fig. 4.11, before pruning).
    """
    pts = dedupe(checks.points("boundary", boundary, dims=(2,), min_count=4))
    vor = voronoi(pts)
    rv = np.asarray(vor.ridge_vertices, dtype=np.int64).reshape(-1, 2)
    return vor.vertices, rv[(rv >= 0).all(axis=1)]


def feature_skeleton(
    boundary: np.ndarray,
    spacing: float | None = None,
    *,
    noise: float | None = None,
    settings: SkeletonSettings | None = None,
    **overrides: object,
) -> Skeleton:
    """The skeleton (medial axis transform) of one feature from its boundary samples.

    Implements the DVMA and its pruning of thesis §4.4.3 (Figs. 4.11-4.13); see the module
    docstring for the stages and the default thresholds.

    Args:
        boundary: (M, 2) boundary samples in surface coordinates [m], ordered along the trace
            or not, possibly noisy and not closed; M >= 4.
        spacing: sample spacing along the boundary (finger speed / sample rate) [m];
            estimated when ``None`` (median step along the trace, or median
            nearest-neighbour distance for unordered samples). Thresholds use the local
            spacing where the samples are sparser than this.
        noise: standard deviation of the boundary noise [m]; estimated from the samples
            when ``None``.
        settings: the pruning :class:`SkeletonSettings` (default: all derived).
        **overrides: fields of :class:`SkeletonSettings` to change (``max_edge_length``,
            ``min_generator_distance``, ``min_branch_length`` [m], ``min_angle_deg``,
            ``keep_largest``, ``branching``, ``link_factor``).

    Returns:
        The pruned :class:`Skeleton` (``points`` (K, 2), ``edges`` (E, 2), ``radii`` (K,)).
        A feature whose axis degenerates to a point (a disk, a square sampled at its
        corners) gives one point and no edge.

    Raises:
        InvalidParameter: bad shapes or values, unknown settings, samples enclosing no area.
    """
    pts = dedupe(checks.points("boundary", boundary, dims=(2,), min_count=4))
    base = SkeletonSettings.of(settings, **overrides)
    spacing = None if spacing is None else checks.positive("spacing", spacing, "m")
    noise = None if noise is None else checks.nonnegative("noise", noise, "m")

    vor = voronoi(pts)
    profile = sampling_profile(pts)
    if spacing is None:
        spacing = profile.spacing
    loops = boundary_loops(pts, spacing, base.link_factor, vor.delaunay_edges, profile)
    region = region_polygon(pts, loops)
    if noise is None:
        noise = estimate_noise(pts, list(loops.loops))
    s_high = max(spacing, profile.spacing_high)
    s = base.resolved(spacing, noise, s_high)
    # local spacing of each Voronoi edge: the sparser of its two generating samples
    s_loc = local_spacing(pts, loops, spacing, 2.0 * s_high)
    stages: dict = {}
    inside = shapely.contains_xy(region, vor.vertices[:, 0], vor.vertices[:, 1])
    edges, radii = _filtered_edges(pts, vor, inside, s_loc, noise, base, s, stages)
    points, edges, radii = _pruned_graph(pts, vor.vertices, edges, radii, s, stages)
    if inside.any():
        points, edges, radii = _degenerate_axis(pts, vor.vertices, inside, points, edges, radii,
                                                stages)  # fmt: skip
    return Skeleton(
        points.copy(),
        edges.astype(np.int64),
        radii.copy(),
        float(spacing),
        float(noise),
        s,
        region,
        stages,
    )


def _filtered_edges(pts, vor, inside, s_loc, noise, base, s, stages):
    """The Voronoi edges kept by the first stages (finite, inside the feature, short enough
    for the local spacing and noise, generated by distant enough samples, angle test) and
    the radius [m] at every Voronoi vertex they use; counts into ``stages``."""
    pairs = np.asarray(vor.ridge_points, dtype=np.int64)
    s_edge = np.maximum(s_loc[pairs[:, 0]], s_loc[pairs[:, 1]])
    verts = vor.vertices
    rv = np.asarray(vor.ridge_vertices, dtype=np.int64).reshape(-1, 2)
    keep = (rv >= 0).all(axis=1)
    stages["dvma"] = int(keep.sum())
    keep[keep] = inside[rv[keep, 0]] & inside[rv[keep, 1]]
    stages["inside"] = int(keep.sum())
    e_len = np.full(len(rv), np.inf)
    e_len[keep] = g.edge_lengths(verts, rv[keep])
    gen = np.hypot(*(pts[pairs[:, 0]] - pts[pairs[:, 1]]).T)
    r_max = np.zeros(len(rv))
    r_max[keep] = np.maximum(
        np.hypot(*(verts[rv[keep, 0]] - pts[pairs[keep, 0]]).T),
        np.hypot(*(verts[rv[keep, 1]] - pts[pairs[keep, 0]]).T),
    )
    if base.max_edge_length is None:  # local threshold: noise moves vertices by ~noise*r/s
        max_len = 2.0 * s_edge + 4.0 * noise * (1.0 + r_max / s_edge)
    else:
        max_len = s.max_edge_length
    if base.min_generator_distance is None:
        min_gen = 1.2 * s_edge + 2.0 * noise
    else:
        min_gen = s.min_generator_distance
    keep &= (e_len <= max_len) & (gen >= min_gen)
    if s.min_angle_deg > 0:
        keep &= gen >= 2.0 * r_max * np.sin(np.deg2rad(s.min_angle_deg) / 2)
    stages["length"] = int(keep.sum())
    edges = rv[keep]
    radii = np.zeros(len(verts))
    gen_pt = pts[pairs[keep, 0]]
    for col in (0, 1):
        radii[edges[:, col]] = np.hypot(*(verts[edges[:, col]] - gen_pt).T)
    return edges, radii


def _pruned_graph(pts, verts, edges, radii, s, stages):
    """The kept edges as a graph, pruned: close vertices merged, the largest component,
    short terminal arcs, the main path (without branching) and insignificant points."""
    scale = float(np.ptp(pts, axis=0).max())
    merged, edges, _ = g.merge_close_points(np.column_stack([verts, radii]), edges, 1e-9 * scale)
    points, radii = merged[:, :2], merged[:, 2]
    if s.keep_largest and len(edges):
        points, edges, radii = g.compact(
            points, edges[g.largest_component_mask(len(points), edges)], radii
        )
    stages["largest"] = len(edges)
    if len(edges):
        keep_e = g.prune_terminal_arcs(points, edges, s.min_branch_length)
        points, edges, radii = g.compact(points, edges[keep_e], radii)
    stages["arcs"] = len(edges)
    if not s.branching and len(edges):
        if g.has_cycle(len(points), edges):
            keep_e = g.prune_terminal_arcs(points, edges, np.inf)
            points, edges, radii = g.compact(points, edges[keep_e], radii)
        else:
            path = g.longest_path(points, edges)
            points, edges, radii = points[path], g.path_edges(np.arange(len(path))), radii[path]
        stages["main_path"] = len(edges)
    if len(edges) and s.min_significance > 0:
        alive = peel_insignificant(points, edges, radii, s.min_significance)
        points, edges, radii = _keep_points(points, edges, radii, alive)
        stages["significance"] = len(edges)
        if len(edges) == 0:
            stages["single_point"] = 1
    return points, edges, radii


def _degenerate_axis(pts, verts, inside, points, edges, radii, stages):
    """A disk-like feature whose axis degenerates to a point (or whose whole medial axis fell
    to the edge-length test, leaving only shallow pieces near a boundary defect): the
    innermost Voronoi vertex, the centre of the largest inscribed disk; else unchanged."""
    cand = np.flatnonzero(inside)
    r_in = np.hypot(*(verts[cand] - pts[_nearest(pts, verts[cand])]).T)
    shallow = len(points) > 0 and float(radii.max()) < 0.5 * float(r_in.max())
    if shallow or (len(edges) == 0 and "single_point" not in stages):
        best = cand[np.argmax(r_in)]
        points, edges = verts[best : best + 1], np.zeros((0, 2), np.int64)
        radii = np.array([r_in.max()])
        stages["single_point"] = 1
    return points, edges, radii


def _keep_points(points, edges, radii, alive: np.ndarray):
    """The skeleton restricted to the points ``alive`` (K,) (a lone point survives)."""
    e = edges[alive[edges[:, 0]] & alive[edges[:, 1]]]
    if len(e):
        return g.compact(points, e, radii)
    i = np.flatnonzero(alive)[:1]
    return points[i], np.zeros((0, 2), np.int64), radii[i]


def _nearest(samples: np.ndarray, query: np.ndarray) -> np.ndarray:
    """(Q,) index of the nearest sample to each query point."""
    from scipy.spatial import cKDTree

    return cKDTree(samples).query(query)[1]


def pseudo_skeleton(path: np.ndarray, spacing: float | None = None) -> Skeleton:
    """The pseudo-skeleton of a feature traced *along* rather than around (cusp, step).

    Thesis §4.4.3: "the path obtained by tracing along such a feature can be used as a
    pseudo-skeleton". Points are the traced samples in order (exact repeats removed), edges
    join consecutive samples, radii are zero.

    Args:
        path: (P, 2) traced samples in trace order [m], P >= 2.
        spacing: sample spacing [m] (estimated when ``None``; informational).

    Returns:
        A :class:`Skeleton` that is a single path.
    """
    pts = checks.points("path", path, dims=(2,), min_count=2)
    keep = np.ones(len(pts), dtype=bool)
    keep[1:] = (np.diff(pts, axis=0) != 0).any(axis=1)
    pts = pts[keep]
    if len(pts) < 2:
        raise InvalidParameter("path: expected at least 2 distinct consecutive samples")
    spacing = None if spacing is None else checks.positive("spacing", spacing, "m")
    if spacing is None:
        spacing = float(np.median(np.hypot(*np.diff(pts, axis=0).T)))
    edges = g.path_edges(np.arange(len(pts)))
    return Skeleton(
        pts, edges, np.zeros(len(pts)), spacing, 0.0, SkeletonSettings(), None, {"path": len(edges)}
    )


__all__ = ["Skeleton", "SkeletonSettings", "dvma", "feature_skeleton", "pseudo_skeleton", "voronoi"]
