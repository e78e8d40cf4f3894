"""The Voronoi diagram of 2-D samples as arrays, from their Delaunay triangulation.

``scipy.spatial.Voronoi`` builds Python lists of regions and ridges, which costs more than
qhull's Delaunay triangulation itself. The finite part of the Voronoi diagram is the dual of
the triangulation: one vertex per triangle (its circumcentre) and one ridge per pair of
adjacent triangles, separating the two samples of their shared edge. Ridges going to
infinity (hull edges) are left out: no skeleton uses them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.errors import InvalidParameter


@dataclass(frozen=True)
class VoronoiGraph:
    """Finite Voronoi diagram of (M, 2) samples.

    Attributes:
        vertices: (T, 2) Voronoi vertices = circumcentres of the Delaunay triangles [m]
            (coincident for cocircular samples).
        ridge_vertices: (R, 2) int indices into ``vertices`` of each finite Voronoi edge.
        ridge_points: (R, 2) int indices into the samples of the two generators of each edge
            (the edge lies on their perpendicular bisector).
        delaunay_edges: (D, 2) int indices of the samples joined by every Delaunay edge,
            hull edges included.
    """

    vertices: np.ndarray
    ridge_vertices: np.ndarray
    ridge_points: np.ndarray
    delaunay_edges: np.ndarray


def circumcenters(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """(T, 2) circumcentres of triangles with corners ``a``, ``b``, ``c`` (each (T, 2)) [m];
    NaN for degenerate (collinear) triangles."""
    b1, c1 = b - a, c - a
    d = 2.0 * (b1[:, 0] * c1[:, 1] - b1[:, 1] * c1[:, 0])
    bb, cc = np.einsum("ij,ij->i", b1, b1), np.einsum("ij,ij->i", c1, c1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ux = (c1[:, 1] * bb - b1[:, 1] * cc) / d
        uy = (b1[:, 0] * cc - c1[:, 0] * bb) / d
    out = a + np.column_stack([ux, uy])
    out[d == 0] = np.nan
    return out


def voronoi(points: np.ndarray) -> VoronoiGraph:
    """Finite Voronoi diagram of (M, 2) samples [m] (M >= 4, not all collinear).

    Raises:
        InvalidParameter: too few samples, or qhull cannot triangulate them.
    """
    from scipy.spatial import Delaunay, QhullError

    if len(points) < 4:
        raise InvalidParameter(f"boundary: expected at least 4 distinct samples, got {len(points)}")
    try:
        tri = Delaunay(points)
    except QhullError as exc:
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else "qhull failed"
        raise InvalidParameter(
            "boundary: the Voronoi diagram cannot be built (samples collinear or "
            f"degenerate?): {first}"
        ) from None
    simp, nb = tri.simplices, tri.neighbors
    verts = circumcenters(*(points[simp[:, k]] for k in range(3)))
    t = np.repeat(np.arange(len(simp)), 3)
    k = np.tile(np.arange(3), len(simp))
    n = nb.ravel()
    once = (n > t) | (n < 0)  # each interior edge once, and the hull edges
    t, k, n = t[once], k[once], n[once]
    rp = np.column_stack([simp[t, (k + 1) % 3], simp[t, (k + 2) % 3]]).astype(np.int64)
    rv = np.column_stack([t, n]).astype(np.int64)
    ok = (n >= 0) & np.isfinite(verts[rv]).all(axis=(1, 2))
    return VoronoiGraph(verts, rv[ok], rp[ok], rp)


__all__ = ["VoronoiGraph", "circumcenters", "voronoi"]
