"""Export skeletons, regions and the global skeleton as GeoJSON (GIS/CAD tools open it) and
as npz arrays.

Coordinates are surface coordinates in metres, written as they are (no geographic CRS:
GIS tools show them as a plain Cartesian plane).
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import mapping

from planner.skeleton.feature import Skeleton
from planner.skeleton.global_map import GlobalSkeleton


def _lines(points: np.ndarray, edges: np.ndarray) -> shapely.MultiLineString:
    if len(edges) == 0:
        return shapely.MultiLineString()
    return shapely.multilinestrings(list(points[edges]))


def to_geojson(
    skeletons: Sequence[Skeleton] = (),
    gs: GlobalSkeleton | None = None,
    names: Sequence[str] | None = None,
) -> dict:
    """A GeoJSON FeatureCollection of the feature skeletons, regions and global skeleton.

    Args:
        skeletons: feature skeletons, one per feature.
        gs: the global skeleton (its regions and skeleton are added when given).
        names: feature names (default ``feature_<i>``).

    Returns:
        A JSON-serialisable dict; every GeoJSON Feature has ``properties.layer`` in
        ``{"feature_skeleton", "region", "global_skeleton"}`` and ``properties.feature``.
    """
    n = max(len(skeletons), gs.n_features if gs is not None else 0)
    names = list(names) if names is not None else [f"feature_{i}" for i in range(n)]
    feats = []
    for i, sk in enumerate(skeletons):
        feats.append(
            {
                "type": "Feature",
                "geometry": mapping(_lines(sk.points, sk.edges)),
                "properties": {
                    "layer": "feature_skeleton",
                    "feature": i,
                    "name": names[i],
                    "length_m": sk.length,
                    "branch_points": int(len(sk.branch_points)),
                    "end_points": int(len(sk.end_points)),
                    "mean_radius_m": float(np.mean(sk.radii)) if len(sk.radii) else 0.0,
                },
            }
        )
    if gs is not None:
        for i, reg in enumerate(gs.regions):
            feats.append(
                {
                    "type": "Feature",
                    "geometry": mapping(reg),
                    "properties": {
                        "layer": "region",
                        "feature": i,
                        "name": names[i],
                        "area_m2": float(reg.area),
                    },
                }
            )
        feats.append(
            {
                "type": "Feature",
                "geometry": mapping(_lines(gs.points, gs.edges)),
                "properties": {
                    "layer": "global_skeleton",
                    "feature": None,
                    "clearance_m": gs.clearance,
                    "length_m": gs.length,
                },
            }
        )
    return {"type": "FeatureCollection", "features": feats}


def write_geojson(
    path: str | Path,
    skeletons: Sequence[Skeleton] = (),
    gs: GlobalSkeleton | None = None,
    names: Sequence[str] | None = None,
) -> Path:
    """Write :func:`to_geojson` to ``path``; returns the path."""
    path = Path(path)
    path.write_text(json.dumps(to_geojson(skeletons, gs, names), allow_nan=False))
    return path


def to_arrays(
    skeletons: Sequence[Skeleton] = (), gs: GlobalSkeleton | None = None
) -> dict[str, np.ndarray]:
    """Flat arrays for ``numpy.savez``: per feature ``skeleton_<i>_points`` (K, 2) [m],
    ``skeleton_<i>_edges`` (E, 2), ``skeleton_<i>_radii`` (K,) [m]; for the global skeleton
    ``global_points``, ``global_edges``, ``global_radii``, ``global_edge_features``,
    ``region_areas`` (F,) [m^2] and ``pair_clearance`` (F, F) [m]."""
    out: dict[str, np.ndarray] = {}
    for i, sk in enumerate(skeletons):
        out[f"skeleton_{i}_points"] = np.asarray(sk.points)
        out[f"skeleton_{i}_edges"] = np.asarray(sk.edges)
        out[f"skeleton_{i}_radii"] = np.asarray(sk.radii)
    if gs is not None:
        out["global_points"] = gs.points
        out["global_edges"] = gs.edges
        out["global_radii"] = gs.radii
        out["global_edge_features"] = gs.edge_features
        out["region_areas"] = gs.region_areas
        out["pair_clearance"] = gs.pair_clearance
    return out


def write_npz(
    path: str | Path, skeletons: Sequence[Skeleton] = (), gs: GlobalSkeleton | None = None
) -> Path:
    """Write :func:`to_arrays` to a compressed ``.npz`` file; returns the path."""
    path = Path(path)
    np.savez_compressed(path, **to_arrays(skeletons, gs))
    return path


__all__ = ["to_arrays", "to_geojson", "write_geojson", "write_npz"]
