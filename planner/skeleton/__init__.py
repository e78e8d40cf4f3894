"""Feature modelling with shape skeletons (thesis §4.4.3 and §4.5.3, Figs. 4.9-4.15).

- :func:`feature_skeleton`: discrete Voronoi medial axis (DVMA) of one feature's boundary
  samples, pruned; a :class:`Skeleton` with ``points`` (K, 2) [m], ``edges`` (E, 2) and
  ``radii`` (K,) [m] (the medial axis transform), branch/end points, length, graph.
- :func:`pseudo_skeleton`: the traced path of a feature traced along (cusp, step).
- :func:`reconstruct`, :func:`regeneration_error`: the feature as a union of disks and
  Brandt's regeneration error.
- :func:`global_skeleton`: the global skeleton of several features, their regions and
  clearance; :func:`safest_path`, :func:`region_report`, :func:`negative_medial_axis`.
- :func:`write_geojson`, :func:`write_npz`: export.
"""

from planner.skeleton.export import to_arrays, to_geojson, write_geojson, write_npz
from planner.skeleton.feature import (
    Skeleton,
    SkeletonSettings,
    dvma,
    feature_skeleton,
    pseudo_skeleton,
)
from planner.skeleton.global_map import GlobalSkeleton, global_skeleton
from planner.skeleton.mat import RegenerationError, reconstruct, regeneration_error
from planner.skeleton.navigation import (
    NavigationPath,
    RegionInfo,
    negative_medial_axis,
    region_report,
    safest_path,
)

__all__ = [
    "GlobalSkeleton",
    "NavigationPath",
    "RegenerationError",
    "RegionInfo",
    "Skeleton",
    "SkeletonSettings",
    "dvma",
    "feature_skeleton",
    "global_skeleton",
    "negative_medial_axis",
    "pseudo_skeleton",
    "reconstruct",
    "regeneration_error",
    "region_report",
    "safest_path",
    "to_arrays",
    "to_geojson",
    "write_geojson",
    "write_npz",
]
