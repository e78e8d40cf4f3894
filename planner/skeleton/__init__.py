"""Feature modelling with shape skeletons (thesis §4.4.3 and §4.5.3, Figs. 4.9-4.15).

- :func:`feature_skeleton`: discrete Voronoi medial axis (DVMA) of one feature's boundary
  samples, pruned; a :class:`Skeleton` with ``points`` (K, 2) [m], ``edges`` (E, 2) and
  ``radii`` (K,) [m] (the medial axis transform).
- :func:`pseudo_skeleton`: the traced path of a feature traced along (cusp, step).
- :func:`reconstruct` and :func:`regeneration_error`: the feature as a union of disks and
  Brandt's regeneration error.
- :func:`global_skeleton`: the global skeleton of several features, their regions,
  clearance, and navigation along it.
- :mod:`planner.skeleton.export`: GeoJSON and npz export.
"""

from planner.skeleton.feature import (
    Skeleton,
    SkeletonSettings,
    dvma,
    feature_skeleton,
    pseudo_skeleton,
)

__all__ = [
    "Skeleton",
    "SkeletonSettings",
    "dvma",
    "feature_skeleton",
    "pseudo_skeleton",
]
