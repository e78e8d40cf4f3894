"""Plain data returned by the detection package: curvature features, macro features and the
curvature signals they are read from (thesis §3.2.2, Definitions 1 and 2)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class CurvatureFeature:
    """A curvature feature found in fingertip data (thesis §3.2.2, Definition 1).

    Attributes:
        sign: ``+1`` for a convex (positive curvature) feature, ``-1`` for a concave one.
        start: arclength along the fingertip-centre path, from its first sample, where the
            feature region begins [m].
        end: arclength where it ends [m] (``end >= start``).
        peak: arclength of the extreme of the detection signal inside the region [m].
        position: (2,) or (3,) point on the estimated surface under the peak, in the frame of
            the input data [m].
        peak_curvature: value of the detection signal at the peak [1/m] (outward convention:
            convex > 0); its meaning depends on ``algorithm`` (see
            :func:`planner.detection.detect_features`).
        algorithm: which algorithm of thesis Fig. 3.8 found it (1-4), or 0 for the App. B.2
            scheme / ground truth.
    """

    sign: int
    start: float
    end: float
    peak: float
    position: np.ndarray
    peak_curvature: float = float("nan")
    algorithm: int = 0

    @property
    def extent(self) -> float:
        """Length of the feature region along the fingertip-centre path [m]."""
        return self.end - self.start

    def __repr__(self) -> str:
        pos = ", ".join(f"{v:.4g}" for v in np.asarray(self.position))
        return (
            f"CurvatureFeature(sign={self.sign:+d}, start={self.start:.4g}, "
            f"end={self.end:.4g}, peak={self.peak:.4g}, position=({pos}))"
        )


@dataclass(frozen=True, eq=False)
class MacroFeature:
    """A pattern of curvature features lying within ``tip_radius`` of each other
    (thesis §3.2.2, Definition 2 and Table 3.1).

    Attributes:
        kind: one of ``"bump"``, ``"pit"``, ``"ridge"``, ``"ravine"``, ``"step"``, ``"cusp"``,
            ``"unknown"``.
        position: (2,) or (3,) representative point on the estimated surface [m]: the centre
            of the extent of its curvature features.
        start: arclength where its first curvature feature begins [m].
        end: arclength where its last curvature feature ends [m].
        signs: the sign pattern along the path, e.g. ``"-+-"``.
        features: the curvature features it is made of, in path order.
    """

    kind: str
    position: np.ndarray
    start: float
    end: float
    signs: str
    features: tuple[CurvatureFeature, ...]

    def __repr__(self) -> str:
        pos = ", ".join(f"{v:.4g}" for v in np.asarray(self.position))
        return (
            f"MacroFeature(kind={self.kind!r}, signs={self.signs!r}, "
            f"start={self.start:.4g}, end={self.end:.4g}, position=({pos}))"
        )


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


__all__ = ["CurvatureFeature", "CurvatureSignal", "MacroFeature"]
