"""Medial axis transform: reconstruction as a union of disks and the regeneration error.

The MAT of a feature is its skeleton points with their radii (thesis §4.4.3: "if the
features are to be reconstructed, the entire MAT is needed"). The reconstruction is the
union of the disks and, along every edge, of the convex hull of its two end disks; Brandt
and Algazi's regeneration error compares it with the feature region.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely

from planner.errors import InvalidParameter
from planner.skeleton.feature import Skeleton


def reconstruct(skeleton: Skeleton, quad_segs: int = 16) -> shapely.Geometry:
    """The feature regenerated from its MAT: union of the medial disks and edge hulls.

    Args:
        skeleton: a skeleton with ``points`` (K, 2) [m] and ``radii`` (K,) [m].
        quad_segs: segments per quarter circle of each disk.

    Returns:
        shapely Polygon or MultiPolygon [m] (empty when all radii are zero).
    """
    if quad_segs < 1:
        raise InvalidParameter(f"quad_segs: expected an integer >= 1, got {quad_segs}")
    r = np.asarray(skeleton.radii)
    ok = r > 0
    if not ok.any():
        return shapely.Polygon()
    disks = np.empty(len(r), dtype=object)
    disks[:] = shapely.Polygon()
    disks[ok] = shapely.buffer(shapely.points(skeleton.points[ok]), r[ok], quad_segs=quad_segs)
    parts = [disks[ok]]
    if len(skeleton.edges):
        e = skeleton.edges[ok[skeleton.edges].all(axis=1)]
        if len(e):
            pairs = shapely.multipolygons(np.stack([disks[e[:, 0]], disks[e[:, 1]]], axis=1))
            parts.append(shapely.convex_hull(pairs))
    return shapely.union_all(np.concatenate(parts))


@dataclass(frozen=True)
class RegenerationError:
    """How well the MAT regenerates the feature (Brandt's regeneration error).

    Attributes:
        area_ratio: area of the symmetric difference between region and reconstruction,
            divided by the region's area [-].
        hausdorff: Hausdorff distance between the two outlines [m].
        region_area: area of the feature region [m^2].
        reconstructed_area: area of the reconstruction [m^2].
    """

    area_ratio: float
    hausdorff: float
    region_area: float
    reconstructed_area: float


def regeneration_error(
    skeleton: Skeleton, region: shapely.Geometry | None = None, quad_segs: int = 16
) -> RegenerationError:
    """Regeneration error of a skeleton's MAT against the feature region.

    Args:
        skeleton: the skeleton (its ``region`` is used when ``region`` is None).
        region: the feature region [m] (shapely polygon).
        quad_segs: disk resolution of the reconstruction.

    Returns:
        :class:`RegenerationError`.
    """
    region = skeleton.region if region is None else region
    if region is None or shapely.is_empty(region) or shapely.area(region) <= 0:
        raise InvalidParameter(
            "region: expected a polygon with positive area (pass region=... for a skeleton "
            "without one, e.g. a pseudo-skeleton)"
        )
    rec = reconstruct(skeleton, quad_segs)
    if rec.is_empty:
        return RegenerationError(1.0, float("inf"), float(region.area), 0.0)
    diff = shapely.symmetric_difference(region, rec).area
    haus = shapely.hausdorff_distance(region.boundary, rec.boundary)
    return RegenerationError(
        float(diff / region.area), float(haus), float(region.area), float(rec.area)
    )


__all__ = ["RegenerationError", "reconstruct", "regeneration_error"]
