"""The explorer's one door to :mod:`planner.detection` (thesis §3.3, algorithm 3 of Fig. 3.8).

Everything of the explorer that needs curvature features goes through :func:`analyse_path`,
which returns the explorer's own plain records (:class:`PathFeature`, :class:`PathAnalysis`).
When :mod:`planner.detection` changes its trace or feature types, only this module changes.

A path is a sequence of fingertip centres in the **plate frame** ``(u, v, w)``: ``(u, v)`` in
the nominal plane of the plate, ``w`` the height above it [m]. The path is unrolled into the
vertical developable strip it sweeps: abscissa = arclength of its ``(u, v)`` projection,
ordinate = ``w``; the material lies below (``w`` decreasing), as for a profile traced in +x.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["PathAnalysis", "PathFeature", "analyse_path", "collapse_pattern"]


@dataclass(frozen=True)
class PathFeature:
    """A curvature feature found along a path.

    Attributes:
        sign: +1 convex, -1 concave.
        s: horizontal arclength of the peak along the path [m].
        start, end: horizontal arclength of the region [m].
        point: (2,) ``(u, v)`` of the peak in the plate frame [m].
        index: fractional sample index of the peak in the input path.
    """

    sign: int
    s: float
    start: float
    end: float
    point: np.ndarray
    index: float


@dataclass(frozen=True)
class PathAnalysis:
    """Curvature features of one path and their sign pattern.

    Attributes:
        features: the curvature features in path order.
        pattern: the collapsed sign pattern (runs of equal signs merged, e.g. ``"-++-"`` ->
            ``"-+-"``), ``""`` when nothing was found.
        s: (N,) horizontal arclength of the samples [m].
        w: (N,) fingertip-centre height above the plate [m].
        uv: (N, 2) the samples' ``(u, v)`` in the plate frame [m].
    """

    features: tuple[PathFeature, ...]
    pattern: str
    s: np.ndarray
    w: np.ndarray
    uv: np.ndarray | None = None

    def point_at(self, i: int) -> np.ndarray:
        """(2,) ``(u, v)`` of sample ``i`` [m]."""
        return np.asarray(self.uv[i], float)


def collapse_pattern(signs) -> str:
    """Sign pattern with runs merged: ``[-1, 1, 1, -1] -> "-+-"``."""
    out = ""
    for x in signs:
        c = "+" if x > 0 else "-"
        if not out or out[-1] != c:
            out += c
    return out


def analyse_path(
    centers_uvw: np.ndarray,
    tip_radius: float,
    *,
    algorithm: int = 3,
    min_length: float = 0.0,
    smoothing: float | None = None,
) -> PathAnalysis:
    """Detect curvature features along a fingertip-centre path (algorithm 3 by default).

    Args:
        centers_uvw: (N, 3) fingertip centres in the plate frame, in time order [m].
        tip_radius: fingertip radius r_f [m].
        algorithm: detection algorithm of thesis Fig. 3.8 (3: traced-curve curvature).
        min_length: paths shorter than this (horizontal) give no features [m].
        smoothing: Gaussian smoothing scale along the path [m] (default ``r_f/10``, the
            detector's scale at the thesis' noise level; its own noise estimate is too
            optimistic for the 0.05 mm steps of quantized encoders, which then read as
            curvature).

    Returns:
        :class:`PathAnalysis`.
    """
    from planner.detection import detect_features

    P = np.asarray(centers_uvw, dtype=float)
    d = np.hypot(np.diff(P[:, 0]), np.diff(P[:, 1]))
    keep = np.concatenate([[True], d > 1e-7])  # the detector needs strictly moving samples
    P = P[keep]
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(P[:, 0]), np.diff(P[:, 1])))])
    w = P[:, 2]
    if len(P) < 20 or s[-1] <= max(min_length, 4 * tip_radius / 10):
        return PathAnalysis((), "", s, w, P[:, :2])
    strip = np.column_stack([s, w])
    try:
        scale = tip_radius / 10 if smoothing is None else smoothing
        found = detect_features(
            strip, tip_radius, algorithm, material_side="right", smoothing_scale=scale
        )
    except Exception:  # too few samples after decimation etc.: no features on this path
        return PathAnalysis((), "", s, w, P[:, :2])
    # the detector's arclength is along the 2-D strip (s, w); map it back to samples
    s_strip = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(strip, axis=0), axis=1))])
    idx = np.arange(len(P), dtype=float)
    feats = []
    for f in found:
        i = float(np.interp(f.peak, s_strip, idx))
        sh = float(np.interp(i, idx, s))
        pt = np.array([np.interp(i, idx, P[:, 0]), np.interp(i, idx, P[:, 1])])
        feats.append(
            PathFeature(
                sign=int(f.sign),
                s=sh,
                start=float(np.interp(np.interp(f.start, s_strip, idx), idx, s)),
                end=float(np.interp(np.interp(f.end, s_strip, idx), idx, s)),
                point=pt,
                index=i,
            )
        )
    return PathAnalysis(tuple(feats), collapse_pattern(f.sign for f in feats), s, w, P[:, :2])
