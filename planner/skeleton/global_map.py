"""The global skeleton and the feature map (thesis §4.5.3, Figs. 4.14-4.15).

The global skeleton is extracted from the Voronoi diagram of the points of all features by
keeping only the edges whose two generating points belong to **different** features (the
thesis' "simple extraction": only segments equidistant from two different features). Those
edges bound the cells of each feature, so they partition a bounding box (``domain``) into
one region per feature.

Generators (``generators=``):

- ``"boundary"`` (default): the boundary samples. The edges are then exactly equidistant
  from the feature *boundaries*, each region contains its feature, and the smallest disk
  radius along the skeleton is the clearance (half the smallest boundary gap).
- ``"skeleton"``: the feature skeleton points (the literal construction of Fig. 4.15);
  equidistant from the feature medial axes, which differs from the above when features
  have different widths.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
import shapely
from scipy.spatial import cKDTree

from planner import checks
from planner.errors import InvalidParameter
from planner.skeleton import graph as g
from planner.skeleton.feature import (
    SkeletonSettings,
    feature_skeleton,
    pseudo_skeleton,
    voronoi,
)
from planner.skeleton.region import dedupe
from planner.skeleton.segments import clip_segments, merge_segments, point_segment_distance

GENERATORS = ("boundary", "skeleton")


@dataclass(frozen=True)
class GlobalSkeleton:
    """The global skeleton of several features and the regions it bounds.

    Attributes:
        points: (K, 2) global skeleton points [m].
        edges: (E, 2) int indices into ``points``.
        radii: (K,) distance of each point to the nearest feature boundary sample [m].
        edge_features: (E, 2) indices of the two features each edge separates.
        edge_clearance: (E,) smallest distance along each edge to the feature boundaries
            (the smallest disk radius on the edge) [m].
        clearance: half the smallest distance between the boundaries of two different
            features = the smallest disk radius along the global skeleton [m].
        pair_clearance: (F, F) half the smallest distance between the boundaries of features
            i and j (``inf`` on the diagonal) [m].
        regions: one shapely polygon per feature, in input order; together they cover
            ``domain`` without overlap.
        domain: the partitioned box (bounding box of the samples grown by a margin) [m].
        boundaries: the (M_i, 2) boundary samples per feature [m].
        feature_skeletons: the feature skeletons (``generators="skeleton"``), else empty.
        generators: ``"boundary"`` or ``"skeleton"``.
    """

    points: np.ndarray
    edges: np.ndarray
    radii: np.ndarray
    edge_features: np.ndarray
    edge_clearance: np.ndarray
    clearance: float
    pair_clearance: np.ndarray
    regions: list
    domain: shapely.Polygon
    boundaries: tuple = ()
    feature_skeletons: tuple = ()
    generators: str = "boundary"

    @property
    def n_features(self) -> int:
        """Number of features F."""
        return len(self.regions)

    @property
    def region_areas(self) -> np.ndarray:
        """(F,) area of each region [m^2]."""
        return np.array([r.area for r in self.regions])

    @property
    def length(self) -> float:
        """Total length of the global skeleton inside the domain [m]."""
        d = self.points[self.edges[:, 0]] - self.points[self.edges[:, 1]]
        return float(np.hypot(d[:, 0], d[:, 1]).sum())

    def can_pass(self, i: int, j: int, tip_radius: float) -> bool:
        """Whether a fingertip of radius ``tip_radius`` [m] fits between features i and j
        (thesis §4.5.3: the disk radius along the global skeleton against the finger size).
        """
        F = self.n_features
        for name, k in (("i", i), ("j", j)):
            if not (isinstance(k, (int, np.integer)) and 0 <= k < F):
                raise InvalidParameter(f"{name}: expected a feature index in [0, {F}), got {k!r}")
        if i == j:
            raise InvalidParameter(f"i, j: expected two different features, got {i} twice")
        r = checks.nonnegative("tip_radius", tip_radius, "m")
        return bool(self.pair_clearance[i, j] >= r)

    def segments(self) -> np.ndarray:
        """(E, 2, 2) edge end points [m]."""
        return self.points[self.edges]


def check_boundaries(boundaries: object, min_count: int) -> list[np.ndarray]:
    if isinstance(boundaries, np.ndarray) and boundaries.ndim == 3:
        boundaries = list(boundaries)  # (F, M, 2): F features of M samples each
    if isinstance(boundaries, np.ndarray) or not hasattr(boundaries, "__len__"):
        raise InvalidParameter(
            "boundaries: expected a list of (M_i, 2) arrays, one per feature, got "
            f"{type(boundaries).__name__}"
        )
    if len(boundaries) < 2:
        raise InvalidParameter(f"boundaries: expected at least 2 features, got {len(boundaries)}")
    return [
        dedupe(checks.points(f"boundaries[{i}]", b, dims=(2,), min_count=min_count))
        for i, b in enumerate(boundaries)
    ]


def domain_polygon(points: np.ndarray, margin: float | None) -> shapely.Polygon:
    lo, hi = points.min(axis=0), points.max(axis=0)
    if margin is None:
        margin = 0.1 * float(max(hi - lo))
    if margin <= 0:
        margin = 1e-3 * max(1.0, float(np.abs(points).max()))
    return shapely.box(*(lo - margin), *(hi + margin))


def with_far_points(points: np.ndarray) -> np.ndarray:
    """Append 8 points 10 extents away so that every cell of ``points`` is bounded."""
    c = 0.5 * (points.min(axis=0) + points.max(axis=0))
    r = 10.0 * (float(np.hypot(*(points - c).T).max()) + 1e-9)
    t = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    return np.vstack([points, c + r * np.column_stack([np.cos(t), np.sin(t)])])


def pair_clearances(boundaries: list[np.ndarray]) -> np.ndarray:
    """(F, F) half the smallest distance between samples of features i and j [m]."""
    F = len(boundaries)
    out = np.full((F, F), np.inf)
    trees = [cKDTree(b) for b in boundaries]
    for i in range(F):
        for j in range(i + 1, F):
            b = boundaries[i]
            # an upper bound from a few samples lets the full query prune almost everything
            ub = float(trees[j].query(b[:: max(1, len(b) // 32)], k=1)[0].min())
            d, _ = trees[j].query(b, k=1, distance_upper_bound=ub * (1 + 1e-12) + 1e-300)
            out[i, j] = out[j, i] = 0.5 * min(float(d.min()), ub)
    return out


def global_skeleton(
    boundaries: list,
    *,
    generators: Literal["boundary", "skeleton"] = "boundary",
    margin: float | None = None,
    settings: SkeletonSettings | None = None,
    noise: float | None = None,
) -> GlobalSkeleton:
    """Global skeleton, regions and clearance of several features (thesis §4.5.3).

    Implements the extraction of Fig. 4.15: Voronoi diagram of the generators of all
    features, keeping only the edges shared by generators of two different features.

    Args:
        boundaries: list of (M_i, 2) boundary samples [m], one array per feature (F >= 2).
        generators: ``"boundary"`` (boundary samples, default) or ``"skeleton"`` (feature
            skeleton points; a feature enclosing no area uses its samples as pseudo-skeleton).
        margin: the domain is the samples' bounding box grown by ``margin`` [m] (default 10 %
            of its larger side).
        settings: pruning settings of each :func:`feature_skeleton`
            (``generators="skeleton"``; default: all derived).
        noise: boundary noise for :func:`feature_skeleton` [m] (``None``: estimated).

    Returns:
        :class:`GlobalSkeleton` (``points``, ``edges``, ``clearance`` [m], ``regions``).
    """
    if generators not in GENERATORS:
        raise InvalidParameter(f"generators: expected one of {GENERATORS}, got {generators!r}")
    margin = None if margin is None else checks.nonnegative("margin", margin, "m")
    bnd = check_boundaries(boundaries, 1)
    F = len(bnd)
    allb = np.concatenate(bnd)
    domain = domain_polygon(allb, margin)
    gens, skels = _generators(bnd, generators, noise, settings)
    G, lab, seg, gen_pt, pairs = _shared_edges(gens, domain)
    points, edges = merge_segments(seg)
    scale = float(np.ptp(allb, axis=0).max()) or 1.0
    points, edges, src = g.merge_close_points(points, edges, 1e-9 * scale)
    seg, gen_pt, pairs = points[edges], gen_pt[src], pairs[src]
    tree = cKDTree(allb)
    radii = tree.query(points)[0] if len(points) else np.zeros(0)
    if generators == "boundary":
        e_clear = point_segment_distance(gen_pt, seg)
    else:
        mid = seg.mean(axis=1)
        e_clear = (
            np.minimum(np.minimum(radii[edges[:, 0]], radii[edges[:, 1]]), tree.query(mid)[0])
            if len(edges)
            else np.zeros(0)
        )
    pc = pair_clearances(bnd)
    regions = _regions(seg, domain, G, lab, F)
    return GlobalSkeleton(
        points,
        edges,
        radii,
        pairs,
        e_clear,
        float(pc.min()),
        pc,
        regions,
        domain,
        tuple(bnd),
        skels,
        generators,
    )


def _generators(bnd: list, generators: str, noise, settings) -> tuple[list, tuple]:
    """The Voronoi generators of each feature: its boundary samples, or its skeleton's
    points (a feature enclosing no area: the pseudo-skeleton of its samples); and the
    feature skeletons (empty for boundary generators)."""
    if generators != "skeleton":
        return bnd, ()
    sk = []
    for i, b in enumerate(bnd):
        try:
            sk.append(feature_skeleton(b, noise=noise, settings=settings))
        except InvalidParameter:
            if len(b) < 2:
                raise InvalidParameter(
                    f"boundaries[{i}]: expected at least 2 samples to build a (pseudo-)skeleton"
                ) from None
            sk.append(pseudo_skeleton(b))
    return [s.points for s in sk], tuple(sk)


def _shared_edges(gens: list, domain: shapely.Polygon):
    """Fig. 4.15's extraction: the finite Voronoi edges between generators of two different
    features, clipped to the domain. Returns the unique generators ``G`` (K, 2) [m] with
    their feature labels (K,), the segments (E, 2, 2) [m], a generator of each (E, 2) and
    each one's sorted feature pair (E, 2)."""
    G = np.concatenate(gens)
    lab = np.concatenate([np.full(len(x), i) for i, x in enumerate(gens)])
    G, first = np.unique(G, axis=0, return_index=True)
    lab = lab[first]
    vor = voronoi(with_far_points(G))
    lab_far = np.concatenate([lab, np.full(8, -1)])
    rp = np.asarray(vor.ridge_points, dtype=np.int64)
    rv = np.asarray(vor.ridge_vertices, dtype=np.int64).reshape(-1, 2)
    la, lb = lab_far[rp[:, 0]], lab_far[rp[:, 1]]
    keep = (la >= 0) & (lb >= 0) & (la != lb) & (rv >= 0).all(axis=1)
    seg = vor.vertices[rv[keep]]
    gen_pt = G[rp[keep, 0]]
    pairs = np.sort(np.column_stack([la[keep], lb[keep]]), axis=1)
    seg, inside = clip_segments(seg, domain.bounds)
    return G, lab, seg[inside], gen_pt[inside], pairs[inside]


def _regions(
    seg: np.ndarray, domain: shapely.Polygon, gens: np.ndarray, lab: np.ndarray, F: int
) -> list:
    """Faces of the arrangement of the skeleton segments and the domain, one per feature."""
    lines = shapely.multilinestrings(list(seg)) if len(seg) else shapely.MultiLineString()
    noded = shapely.union_all([lines, domain.exterior])
    faces = list(shapely.get_parts(shapely.polygonize(shapely.get_parts(noded))))
    groups: list[list] = [[] for _ in range(F)]
    if faces:
        reps = shapely.get_coordinates(shapely.point_on_surface(faces))
        owner = lab[cKDTree(gens).query(reps)[1]]
        for f, o in zip(faces, owner, strict=True):
            groups[int(o)].append(f)
    return [shapely.union_all(gr) if gr else shapely.Polygon() for gr in groups]


__all__ = ["GENERATORS", "GlobalSkeleton", "global_skeleton", "pair_clearances"]
