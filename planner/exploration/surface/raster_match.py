"""Type identification by raster pattern matching (thesis §4.4.1, the flow chart's alternative).

"Rather than using an explicit flow chart for identification, the finger can also move over
the surface (perhaps in a raster-scanning fashion) and record all the curvature feature regions
detected. These regions can then be pattern-matched against the possible feature types."

Every raster line is analysed on its own (:func:`analyse_path`); the curvature features of all
lines are clustered in the plate (single linkage, gap ``2 r_f``); each cluster is one macro
feature. Its pattern is matched against the six kinds with the cues of
:mod:`planner.exploration.surface.identify`: the line that rises or dips most gives the
across cues (relief, level change, feet, crease); the **shape of the cluster** replaces the
along crossing - an elongated cluster (a ridge, ravine, step or cusp met by many lines at
points along a line) is flat along its axis, a compact one (bump, pit) is not.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.exploration.surface.detection_adapter import analyse_path, collapse_pattern
from planner.exploration.surface.identify import (
    Crossing,
    TypeDecision,
    end_slopes,
    identify,
    level_change,
    relief,
)

__all__ = ["RasterFeature", "raster_identify"]


@dataclass(frozen=True)
class RasterFeature:
    """A macro feature found by the raster.

    Attributes:
        decision: the :class:`TypeDecision` (kind, confidence, scores).
        points: (K, 2) curvature-feature points of the cluster in the plate frame [m].
        signs: (K,) their signs.
        elongation: major over minor extent of the cluster [-].
        lines: indices of the raster lines that met it.
        relief: relief of the line that rises or dips most over it [m] (see
            :func:`~planner.exploration.surface.identify.relief`).
    """

    decision: TypeDecision
    points: np.ndarray
    signs: np.ndarray
    elongation: float
    lines: tuple[int, ...]
    relief: float = 0.0

    @property
    def centre(self) -> np.ndarray:
        """(2,) middle of the cluster's curvature features [m]."""
        return 0.5 * (self.points.min(axis=0) + self.points.max(axis=0))

    def axis(self, line_direction=(1.0, 0.0), elongated: float = 2.5) -> np.ndarray:
        """(2,) unit direction *across* the feature: normal to the cluster's long axis when
        it is ``elongated`` times longer than wide (a ridge met by many lines), else
        ``line_direction``."""
        d = np.asarray(line_direction, float)
        if len(self.points) < 3 or self.elongation <= elongated:
            return d / np.linalg.norm(d)
        w, v = np.linalg.eigh(np.cov(self.points.T))
        major = v[:, -1]
        return np.array([-major[1], major[0]])


def _clusters(points: np.ndarray, gap: float) -> np.ndarray:
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    pairs = cKDTree(points).query_pairs(gap, output_type="ndarray")
    n = len(points)
    m = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    return connected_components(m, directed=False)[1]


def _elongation(Q: np.ndarray, tip_radius: float) -> float:
    """Major over minor standard deviation of points (minor floored at r_f/4) [-]."""
    if len(Q) < 3:
        return 0.0
    ext = np.sqrt(np.maximum(np.linalg.eigvalsh(np.cov(Q.T)), 0.0))
    return float(ext[-1] / max(ext[0], 0.25 * tip_radius))


def _window(analysis, members, tip_radius: float):
    s = np.array([f.s for f in members])
    lo, hi = s.min() - 1.25 * tip_radius, s.max() + 1.25 * tip_radius
    sel = (analysis.s >= lo) & (analysis.s <= hi)
    return analysis.s[sel], analysis.w[sel]


def raster_identify(
    lines, tip_radius: float, *, elongation_threshold: float = 2.5
) -> list[RasterFeature]:
    """Cluster the curvature features of raster lines and match each cluster to a kind.

    Args:
        lines: sequence of (N_i, 3) fingertip-centre paths in the plate frame [m].
        tip_radius: r_f [m].
        elongation_threshold: clusters longer than this times their width are elongated.

    Returns:
        One :class:`RasterFeature` per cluster, largest first.
    """
    analyses = [analyse_path(np.asarray(p, float), tip_radius) for p in lines]
    pts, sg, line_of, feats = [], [], [], []
    for i, a in enumerate(analyses):
        for f in a.features:
            pts.append(f.point)
            sg.append(f.sign)
            line_of.append(i)
            feats.append(f)
    if not pts:
        return []
    P = np.array(pts)
    labels = _clusters(P, 2.0 * tip_radius)
    out = []
    for lab in np.unique(labels):
        idx = np.flatnonzero(labels == lab)
        Q = P[idx]
        elong = max(_elongation(Q[np.array(sg)[idx] == k], tip_radius) for k in (1, -1))
        best, best_c = None, None
        for li in sorted({line_of[j] for j in idx}):
            members = [feats[j] for j in idx if line_of[j] == li]
            s, w = _window(analyses[li], members, tip_radius)
            if len(s) < 12:
                continue
            c = Crossing(
                collapse_pattern(m.sign for m in members),
                "across",
                level_change(w),
                relief(s, w),
                end_slopes(s, w),
            )
            score = len(c.pattern) + (abs(c.relief) + abs(c.level_change)) / tip_radius
            if best is None or score > best:
                best, best_c = score, c
        if best_c is None:
            continue
        elongated = elong > elongation_threshold
        along = Crossing("", "along", 0.0, 0.0 if elongated else best_c.relief)
        dec = identify([best_c, along])
        out.append(
            RasterFeature(
                dec,
                Q,
                np.array(sg)[idx],
                elong,
                tuple(sorted({line_of[j] for j in idx})),
                best_c.relief,
            )
        )
    out.sort(key=lambda r: -len(r.points))
    return out
