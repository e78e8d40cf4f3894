"""The curvature signal a detection algorithm thresholds (thesis §3.3, App. B.2). The feature
types are :class:`planner.geometry.features.CurvatureFeature` and
:class:`planner.geometry.features.MacroFeature`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class CurvatureSignal:
    """The detection signal an algorithm thresholds, sampled along the path.

    Attributes:
        algorithm: 1-4 (thesis Fig. 3.8).
        s: (M,) arclength along the fingertip-centre path from its first sample [m].
        curvature: (M,) detection signal, outward convention (convex > 0) [1/m].
        upper: convex threshold [1/m]; samples with ``curvature > upper`` are convex.
        lower: concave threshold [1/m]; samples with ``curvature < lower`` are concave.
        surface: (M, D) estimated-surface point belonging to each sample [m] (D = 2 or 3).
        traced: (M, D) smoothed fingertip-centre point belonging to each sample [m].
        index: (M,) index (possibly fractional) of the input sample each value belongs to.
        scale: Gaussian smoothing scale used along the path [m].
    """

    algorithm: int
    s: np.ndarray
    curvature: np.ndarray
    upper: float
    lower: float
    surface: np.ndarray
    traced: np.ndarray
    index: np.ndarray
    scale: float = float("nan")


__all__ = ["CurvatureSignal"]
