"""The region of a feature, rebuilt from its boundary samples (thesis §4.4.3).

Boundary tracing yields samples that are usually ordered along the trace, but may be noisy,
unordered, or not closed. The samples are split into *loops* (closed contours such as the
outer and inner contour of a ring, or one contour whose trace has gaps) and the region is
their even-odd combination (a shapely polygon), used to keep the Voronoi edges inside the
feature.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from scipy import sparse
from scipy.sparse import csgraph
from scipy.spatial import cKDTree

from planner.errors import InvalidParameter


def estimate_spacing(points: np.ndarray) -> float:
    """Sample spacing: the median step when the samples are in trace order (median step at
    most twice the median nearest-neighbour distance), else the median nearest-neighbour
    distance (evaluated on at most 2000 evenly strided samples).

    Args:
        points: (M, 2) boundary samples [m], no repeated rows, M >= 2.

    Returns:
        Estimated sample spacing [m] (> 0).
    """
    stride = max(1, len(points) // 2000)
    d, _ = cKDTree(points).query(points[::stride], k=2)
    d = d[:, 1]
    d = d[d > 0]
    if d.size == 0:
        raise InvalidParameter("boundary: all samples coincide; cannot estimate the spacing")
    nn = float(np.median(d))
    step = np.hypot(*np.diff(points, axis=0).T)
    step = step[step > 0]
    if step.size:
        m = float(np.median(step))
        if m <= 2.0 * nn:
            return m
    return nn


@dataclass(frozen=True)
class SamplingProfile:
    """How the boundary samples are spaced.

    Attributes:
        ordered: samples are in trace order (median step <= 2 median neighbour distances).
        spacing: typical spacing: median step (ordered) or median neighbour distance [m].
        spacing_high: 90th percentile of the steps (ordered) or of the distance to the
            second-nearest sample (unordered): the spacing of the sparse parts [m].
    """

    ordered: bool
    spacing: float
    spacing_high: float


def sampling_profile(points: np.ndarray) -> SamplingProfile:
    """Measure the spacing of (M, 2) boundary samples [m] (no repeated rows, M >= 3)."""
    stride = max(1, len(points) // 2000)
    d, _ = cKDTree(points).query(points[::stride], k=3)
    nn = d[:, 1][d[:, 1] > 0]
    if nn.size == 0:
        raise InvalidParameter("boundary: all samples coincide; cannot estimate the spacing")
    nn_med = float(np.median(nn))
    step = np.hypot(*np.diff(points, axis=0).T)
    step = step[step > 0]
    if step.size and float(np.median(step)) <= 2.0 * nn_med:
        return SamplingProfile(True, float(np.median(step)), float(np.quantile(step, 0.9)))
    return SamplingProfile(False, nn_med, float(np.quantile(d[:, 2], 0.9)))


def local_spacing(
    points: np.ndarray, loops: BoundaryLoops, default: float, cap: float
) -> np.ndarray:
    """(M,) spacing at each sample: the longer of its two steps along its loop [m].

    Samples outside every loop get ``default``; values are clipped to ``[default, cap]``.
    """
    out = np.full(len(points), default)
    for loop in loops.loops:
        p = points[loop]
        nxt = np.hypot(*(np.roll(p, -1, axis=0) - p).T)
        out[loop] = np.maximum(nxt, np.roll(nxt, 1))
    return np.clip(out, default, max(cap, default))


#: half-width of the window of the local fit in :func:`estimate_noise` [samples]
NOISE_HALF_WINDOW = 5


def estimate_noise(points: np.ndarray, loops: list[np.ndarray]) -> float:
    """Robust estimate of the boundary noise standard deviation from ordered loops.

    Each sample's residual is its distance, normal to the local chord, from the quadratic
    fitted by least squares to the ``2 k + 1`` samples around it (``k =``
    :data:`NOISE_HALF_WINDOW`, fewer on short loops), in the local frame of that chord: the
    curvature of a smooth outline is fitted, whatever the spacing. With i.i.d. noise of
    standard deviation sigma the residual at the window's centre has variance
    ``sigma^2 (1 - h)`` (``h`` the centre's leverage in a uniform quadratic fit, divided
    out); the median absolute deviation ignores corners.

    The residual from a fit over several samples, not the second difference of three
    neighbours, because positions read through quantized joint encoders are a sawtooth:
    runs of samples on a line a little off the outline, then a jump back. The second
    difference is zero along the runs and only the jumps (a minority, which the median
    discards) see it: a traced ridge's 30 um sawtooth (10 um standard deviation) was
    estimated at 0.04 um, and the DVMA's edge-length threshold, which scales with the noise,
    then cut its medial axis into pieces.

    Args:
        points: (M, 2) boundary samples [m].
        loops: index arrays of ordered closed loops (see :func:`boundary_loops`).

    Returns:
        sigma estimate [m] (0 when there are too few samples).
    """
    res = []
    for loop in loops:
        k = min(NOISE_HALF_WINDOW, (loop.size - 1) // 2)
        if k >= 2:
            res.append(_fit_residuals(points[loop], k))
    r = np.concatenate(res) if res else np.zeros(0)
    if r.size == 0:
        return 0.0
    return float(1.4826 * np.median(np.abs(r - np.median(r))))


def _fit_residuals(p: np.ndarray, k: int) -> np.ndarray:
    """Residuals [m] of the samples of a closed loop ``p`` (M, 2) from the quadratic fitted
    to the ``2 k + 1`` samples around each (in the frame of the window's chord), divided by
    ``sqrt(1 - h)``, ``h`` the leverage of the centre of a uniform quadratic fit (so that
    i.i.d. noise of standard deviation sigma gives residuals of standard deviation sigma)."""
    w = 2 * k + 1
    idx = (np.arange(len(p))[:, None] + np.arange(-k, k + 1)[None, :]) % len(p)
    win = p[idx] - p[:, None, :]
    chord = win[:, -1] - win[:, 0]
    length = np.hypot(chord[:, 0], chord[:, 1])
    ok = length > 0
    t = chord[ok] / length[ok, None]
    n = np.column_stack([-t[:, 1], t[:, 0]])
    scale = length[ok, None]
    x = np.einsum("mwk,mk->mw", win[ok], t) / scale
    y = np.einsum("mwk,mk->mw", win[ok], n)
    A = np.stack([np.ones_like(x), x, x * x], axis=-1)
    beta = (
        np.linalg.pinv(np.einsum("mwi,mwj->mij", A, A)) @ np.einsum("mwi,mw->mi", A, y)[..., None]
    )
    h = 3.0 * (3.0 * w * w - 7.0) / (4.0 * w * (w * w - 4.0))
    return beta[:, 0, 0] / np.sqrt(1.0 - h)


def _ordered_chains(points: np.ndarray, link: float) -> list[np.ndarray]:
    """Split samples given in trace order at steps longer than ``link``."""
    step = np.hypot(*np.diff(points, axis=0).T)
    gaps = np.flatnonzero(step > link)
    bounds = np.concatenate([[0], gaps + 1, [len(points)]])
    return [np.arange(a, b) for a, b in zip(bounds[:-1], bounds[1:], strict=True) if b > a]


def _mst_chains(points: np.ndarray, link: float, pairs: np.ndarray | None) -> list[np.ndarray]:
    """Order unordered samples: per component of the short-edge graph, the MST diameter."""
    n = len(points)
    if pairs is None:
        pairs = np.array(sorted(cKDTree(points).query_pairs(link)), dtype=np.int64).reshape(-1, 2)
    d = np.hypot(*(points[pairs[:, 0]] - points[pairs[:, 1]]).T)
    short = d <= link
    pairs, d = pairs[short], np.maximum(d[short], 1e-300)
    g = sparse.coo_matrix((d, (pairs[:, 0], pairs[:, 1])), shape=(n, n)).tocsr()
    tree = csgraph.minimum_spanning_tree(g)
    tree = tree + tree.T
    count, labels = csgraph.connected_components(tree, directed=False)
    chains = []
    sizes = np.bincount(labels, minlength=count)
    for c in np.flatnonzero(sizes >= 3):
        start = int(np.flatnonzero(labels == c)[0])
        d0 = csgraph.dijkstra(tree, indices=start)
        a = int(np.argmax(np.where(np.isfinite(d0), d0, -1.0)))
        d1, pred = csgraph.dijkstra(tree, indices=a, return_predecessors=True)
        b = int(np.argmax(np.where(np.isfinite(d1), d1, -1.0)))
        path = [b]
        while path[-1] != a:
            path.append(int(pred[path[-1]]))
        chains.append(np.asarray(path[::-1]))
    return chains


@dataclass(frozen=True)
class BoundaryLoops:
    """Boundary samples grouped into closed loops.

    Attributes:
        loops: index arrays into the samples, each an ordered closed contour.
        ordered: whether the input order was used (else an MST ordering was built).
        link: the link distance used [m].
    """

    loops: tuple[np.ndarray, ...]
    ordered: bool
    link: float = 0.0


def boundary_loops(
    points: np.ndarray,
    spacing: float,
    link_factor: float = 3.0,
    pairs: np.ndarray | None = None,
    profile: SamplingProfile | None = None,
) -> BoundaryLoops:
    """Group boundary samples into closed loops.

    Samples in trace order are split at steps longer than the link distance
    ``link_factor * max(spacing, spacing_high)``; a piece whose ends are within the link
    distance is a closed contour on its own (e.g. each contour of a ring), the other pieces
    are joined in order into one contour (a trace with gaps, or one that is not closed).
    Unordered samples are ordered per connected component of the graph of sample pairs
    closer than the link distance, along the longest path of its minimum spanning tree.

    Args:
        points: (M, 2) boundary samples [m].
        spacing: sample spacing [m].
        link_factor: samples closer than the link distance are neighbours on a contour [-].
        pairs: optional (P, 2) candidate neighbour pairs (e.g. Delaunay edges).
        profile: the samples' :class:`SamplingProfile` (measured when None).

    Returns:
        The loops (pieces with fewer than 3 samples are left out).
    """
    profile = profile or sampling_profile(points)
    link = link_factor * max(spacing, profile.spacing_high)
    if profile.ordered:
        chains = _ordered_chains(points, link)
    else:
        chains = _mst_chains(points, link, pairs)
    closed, open_ = [], []
    for c in chains:
        if c.size < 3:
            continue
        gap = np.hypot(*(points[c[0]] - points[c[-1]]))
        (closed if gap <= link else open_).append(c)
    if profile.ordered and open_:
        closed.append(np.concatenate(open_))
    else:
        closed.extend(open_)
    return BoundaryLoops(tuple(closed), profile.ordered, link)


def region_polygon(points: np.ndarray, loops: BoundaryLoops | list[np.ndarray]) -> shapely.Geometry:
    """The feature region: even-odd combination of the polygons of the loops.

    Args:
        points: (M, 2) boundary samples [m].
        loops: the loops (see :func:`boundary_loops`).

    Returns:
        A shapely Polygon or MultiPolygon [m].

    Raises:
        InvalidParameter: the loops enclose no area (e.g. samples along a line: a feature
            traced *along*, whose skeleton is the traced path, see ``pseudo_skeleton``).
    """
    seq = loops.loops if isinstance(loops, BoundaryLoops) else loops
    region = shapely.Polygon()
    for loop in seq:
        if loop.size < 3:
            continue
        poly = shapely.Polygon(points[loop])
        if not poly.is_valid:
            poly = shapely.make_valid(poly)
            poly = shapely.union_all(  # a trace that overlaps its start: keep the areas
                [g for g in shapely.get_parts(poly) if g.geom_type.endswith("Polygon")]
            )
        region = shapely.symmetric_difference(region, poly)
    if region.is_empty or region.area <= 0:
        raise InvalidParameter(
            "boundary: the samples enclose no area (collinear, or fewer than 3 per contour); "
            "expected samples around a feature. For a feature traced along (cusp, step) use "
            "planner.skeleton.pseudo_skeleton(path)"
        )
    return region


def dedupe(points: np.ndarray) -> np.ndarray:
    """Drop exactly repeated rows of ``points`` (M, 2), keeping the first occurrence in order."""
    _, first = np.unique(points, axis=0, return_index=True)
    if first.size == points.shape[0]:
        return points
    return points[np.sort(first)]


__all__ = [
    "dedupe",
    "BoundaryLoops",
    "boundary_loops",
    "estimate_noise",
    "estimate_spacing",
    "local_spacing",
    "sampling_profile",
    "SamplingProfile",
    "region_polygon",
]
