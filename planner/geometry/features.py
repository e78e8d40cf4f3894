"""Curvature and macro features of thesis §3.2.2 (Definitions 1 and 2, Table 3.1).

A *curvature feature* (Definition 1) is a compact region where a principal curvature of the
surface exceeds the fingertip curvature: ``k_i > 1/r_f`` (positive, convex) or
``k_i < -1/r_f`` (negative, concave). A *macro feature* (Definition 2) is a group of curvature
features each within ``r_f`` of another one, classified by its pattern (Table 3.1).

This module works on 1-D curvature signals sampled along a path (``curvature_features_1d``,
``macro_features_1d``). The 2-D maps over a surface grid live in
:mod:`planner.geometry.feature_maps` and are re-exported here.

Table 3.1, as read from the text of §3.2.2-3.2.3 (its pictures did not survive OCR)
----------------------------------------------------------------------------------------
Signs are those of the first principal curvature ``k1`` (``|k1| >= |k2|``) met in order when
crossing the macro feature; ``eps`` means ``|k| <= 1/r_f`` (no curvature feature); the gaps
between grouped curvature features are at most ``r_f`` wide.

========  ================================  ==============================================
kind      pattern of k1 across              condition on k2 in the inner feature
========  ================================  ==============================================
cusp      ``+`` or ``-`` (one feature)      -- (a convex or concave cusp / sharp edge)
step      ``-, +`` or ``+, -``              -- (concave foot and convex top of a step)
bump      ``-, +, -``                       ``k2 > 1/r_f`` (the inner region is convex in
                                            both directions: a ring of ``-`` around a cap)
ridge     ``-, +, -``                       ``|k2| <= 1/r_f`` (``eps``: straight crest)
pit       ``+, -, +``                       ``k2 < -1/r_f``
ravine    ``+, -, +``                       ``|k2| <= 1/r_f``
unknown   anything else                     --
========  ================================  ==============================================

On a 1-D path, ``k2`` is only known if the caller passes it; without it the ``-, +, -`` and
``+, -, +`` patterns are read as bump and pit, which is how §3.2.3 reads Fig. 3.7 (the bump of
eq. 3.13 with ``a = 15``, ``r_f = 1``: two negative features around one positive one). A wire
lying on a plane seen across its axis is ``-, +, -`` too (a bump, or a ridge when ``k2`` says
the crest is straight).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from planner.geometry.feature_maps import (  # 2-D maps, re-exported
    CurvatureRegion,
    FeatureMap,
    MacroRegion,
    curvature_feature_map,
    multiscale_feature_maps,
)

MACRO_KINDS = ("bump", "pit", "ridge", "ravine", "step", "cusp", "unknown")


@dataclass(frozen=True, eq=False)
class CurvatureFeature:
    """A curvature feature (Definition 1 of §3.2.2): a region where the curvature exceeds
    ``+1/r_f`` (convex) or falls below ``-1/r_f`` (concave). The one type for exact profile
    features (:meth:`planner.geometry.profiles.Profile.curvature_features`), features of a
    curvature signal (:func:`curvature_features_1d`) and detected features
    (:func:`planner.detection.detect_features`).

    Attributes:
        sign: ``+1`` convex (positive curvature), ``-1`` concave.
        start: where the region begins along the path [m] (profile arclength for exact
            features; fingertip-centre arclength from the first sample for detections).
        end: where it ends [m] (``end >= start``; equal for a sharp corner).
        peak: where the curvature (or the detection signal) is extreme [m].
        position: (2,) or (3,) point of the surface at ``peak`` [m], or ``None`` when the
            path has no points (a bare curvature signal).
        peak_curvature: curvature (or detection signal) at the peak [1/m], outward
            convention (convex > 0; ``±inf`` at a sharp corner).
        algorithm: which algorithm of thesis Fig. 3.8 found it (1-4), 0 for ground truth or
            the App. B.2 scheme.
        open_start: the region begins at the first sample (its true start is unknown).
        open_end: the region ends at the last sample (its true end is unknown).
    """

    sign: int
    start: float
    end: float
    peak: float
    position: np.ndarray | None = None
    peak_curvature: float = float("nan")
    algorithm: int = 0
    open_start: bool = False
    open_end: bool = False

    @property
    def extent(self) -> float:
        """Length of the region, ``end - start`` [m]."""
        return self.end - self.start

    @property
    def width(self) -> float:
        """Same as :attr:`extent` [m]."""
        return self.end - self.start

    def __repr__(self) -> str:
        pos = "None"
        if self.position is not None:
            pos = "(" + ", ".join(f"{v:.4g}" for v in np.asarray(self.position)) + ")"
        return (
            f"CurvatureFeature(sign={self.sign:+d}, start={self.start:.4g}, "
            f"end={self.end:.4g}, peak={self.peak:.4g}, position={pos})"
        )


@dataclass(frozen=True, eq=False)
class MacroFeature:
    """A group of curvature features each within ``r_f`` of the next (Definition 2 and
    Table 3.1 of §3.2.2).

    Attributes:
        kind: one of :data:`MACRO_KINDS`.
        start: start of its first curvature feature [m].
        end: end of its last curvature feature [m].
        signs: the sign pattern of its members in path order, e.g. ``"-+-"``.
        features: the member curvature features, in path order.
        position: (2,) or (3,) mean of the member positions [m], or ``None`` when the
            members carry no position.
    """

    kind: str
    start: float
    end: float
    signs: str
    features: tuple[CurvatureFeature, ...]
    position: np.ndarray | None = None

    @property
    def members(self) -> tuple[CurvatureFeature, ...]:
        """Same as :attr:`features` (the name the surface analysis uses)."""
        return self.features

    @property
    def pattern(self) -> str:
        """Same as :attr:`signs` (the name the surface analysis uses)."""
        return self.signs

    def __repr__(self) -> str:
        pos = "None"
        if self.position is not None:
            pos = "(" + ", ".join(f"{v:.4g}" for v in np.asarray(self.position)) + ")"
        return (
            f"MacroFeature(kind={self.kind!r}, signs={self.signs!r}, "
            f"start={self.start:.4g}, end={self.end:.4g}, position={pos})"
        )


#: former names, kept for :mod:`planner.geometry.surface_analysis`
CurvatureFeature1D = CurvatureFeature
MacroFeature1D = MacroFeature


#: the 1-D extension of Table 3.1 along a fingertip path (``flat_crests=True``)
FLAT_CRESTS = {"-++-": "ridge", "+--+": "ravine"}


def sign_text(signs: Sequence[int]) -> str:
    """``"+"``/``"-"`` text of a sequence of +1/-1 signs, e.g. ``[-1, 1, -1] -> "-+-"``."""
    return "".join("+" if x > 0 else "-" for x in signs)


def threshold_runs(k: np.ndarray, upper: float, lower: float) -> list[tuple[int, int, int, int]]:
    """Definition 1 on a sampled signal: the maximal runs of samples with ``k > upper``
    (sign +1) or ``k < lower`` (sign -1), strict inequalities.

    The one implementation of the thresholding of §3.2.2 (exact profiles, curvature
    signals, detection signals and the App. B.2 scheme all call it).

    Args:
        k: (N,) curvature or detection signal [1/m]; non-finite values count as 0
            (never a feature).
        upper: convex threshold [1/m] (``1/r_f`` in Definition 1).
        lower: concave threshold [1/m] (``-1/r_f``).

    Returns:
        ``[(sign, first, last, peak), ...]`` sample indices (inclusive), sorted by ``first``;
        ``peak`` is where ``sign * k`` is largest in the run.
    """
    sig = np.where(np.isfinite(k), k, 0.0)
    out: list[tuple[int, int, int, int]] = []
    for sign, mask in ((1, sig > upper), (-1, sig < lower)):
        m = np.concatenate([[False], mask, [False]]).astype(np.int8)
        d = np.diff(m)
        for a, b in zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1) - 1, strict=True):
            a, b = int(a), int(b)
            out.append((sign, a, b, a + int(np.argmax(sign * sig[a : b + 1]))))
    out.sort(key=lambda r: r[1])
    return out


def _check_signal(s: object, k: object) -> tuple[np.ndarray, np.ndarray]:
    s = checks.series("s", s, min_count=2, unit="m")
    k = checks.series("k", k, n=s.size, unit="1/m")
    if np.any(np.diff(s) <= 0.0):
        bad = int(np.argmax(np.diff(s) <= 0.0))
        raise InvalidParameter(
            f"s: expected strictly increasing values [m], got s[{bad}]={float(s[bad])!r} >= "
            f"s[{bad + 1}]={float(s[bad + 1])!r}"
        )
    return s, k


def _crossing(s: np.ndarray, k: np.ndarray, i: int, level: float) -> float:
    """Linear interpolation of where ``k`` equals ``level`` between samples ``i`` and ``i+1``."""
    k0, k1 = k[i], k[i + 1]
    t = (level - k0) / (k1 - k0)
    return float(s[i] + t * (s[i + 1] - s[i]))


def curvature_features_1d(
    s: np.ndarray, k: np.ndarray, tip_radius: float
) -> list[CurvatureFeature]:
    """Curvature features of a curvature signal sampled along a path (Definition 1, §3.2.2).

    A sample belongs to a positive feature when ``k > 1/r_f`` and to a negative one when
    ``k < -1/r_f`` (strict inequalities); each maximal run of such samples is one feature.
    Its ``start``/``end`` are the threshold crossings, linearly interpolated between the last
    sample outside and the first sample inside (so they do not depend on where the samples
    fall, to second order in the spacing).

    Args:
        s: (N,) strictly increasing path parameter, usually arc length [m].
        k: (N,) signed curvature at ``s``, convex positive (outward normal) [1/m].
        tip_radius: fingertip radius ``r_f`` [m] (same length unit as ``s``).

    Returns:
        The features in order of ``start``.

    Raises:
        InvalidParameter: bad shapes, non-finite values, non-increasing ``s`` or
            ``tip_radius <= 0``.
    """
    r = checks.positive("tip_radius", tip_radius, "m")
    s, k = _check_signal(s, k)
    thr = 1.0 / r
    last = s.size - 1
    features = [
        CurvatureFeature(
            sign=sign,
            start=float(s[0]) if i0 == 0 else _crossing(s, k, i0 - 1, sign * thr),
            end=float(s[-1]) if i1 == last else _crossing(s, k, i1, sign * thr),
            peak=float(s[ip]),
            peak_curvature=float(k[ip]),
            open_start=bool(i0 == 0),
            open_end=bool(i1 == last),
        )
        for sign, i0, i1, ip in threshold_runs(k, thr, -thr)
    ]
    features.sort(key=lambda f: f.start)
    return features


def group_features_1d(
    features: Sequence[CurvatureFeature], tip_radius: float
) -> list[tuple[CurvatureFeature, ...]]:
    """Group curvature features whose gap is at most ``r_f`` (Definition 2, §3.2.2).

    Args:
        features: curvature features along one path (any order).
        tip_radius: fingertip radius ``r_f`` [units of ``s``].

    Returns:
        Groups in order of ``start``; each group's members are in order of ``start`` and the
        gap ``next.start - previous.end`` between consecutive members is ``<= r_f``.
    """
    r = checks.positive("tip_radius", tip_radius, "m")
    ordered = sorted(features, key=lambda f: f.start)
    groups: list[list[CurvatureFeature]] = []
    for f in ordered:
        if groups and f.start - max(m.end for m in groups[-1]) <= r:
            groups[-1].append(f)
        else:
            groups.append([f])
    return [tuple(g) for g in groups]


def classify_pattern(
    signs: Sequence[int], inner_k2: float | None = None, tip_radius: float = 1.0
) -> str:
    """Macro-feature kind of a sequence of curvature-feature signs (Table 3.1, §3.2.2).

    Args:
        signs: signs (+1/-1) of the grouped features of ``k1`` in path order.
        inner_k2: second principal curvature at the peak of the inner feature of a
            three-feature pattern [1/m], or ``None`` when unknown (then ``-+-`` is a bump and
            ``+-+`` a pit, the reading of §3.2.3).
        tip_radius: fingertip radius ``r_f`` [m], the threshold for ``inner_k2``.

    Returns:
        One of :data:`MACRO_KINDS`; the rules are in the module docstring.
    """
    thr = 1.0 / checks.positive("tip_radius", tip_radius, "m")
    pattern = sign_text(signs)
    if len(pattern) == 1:
        return "cusp"
    if pattern in ("-+", "+-"):
        return "step"
    if pattern == "-+-":
        return (
            "bump"
            if inner_k2 is None or inner_k2 > thr
            else ("ridge" if abs(inner_k2) <= thr else "unknown")
        )
    if pattern == "+-+":
        return (
            "pit"
            if inner_k2 is None or inner_k2 < -thr
            else ("ravine" if abs(inner_k2) <= thr else "unknown")
        )
    return "unknown"


def macro_features_1d(
    features: Sequence[CurvatureFeature],
    tip_radius: float,
    *,
    s: np.ndarray | None = None,
    k2: np.ndarray | None = None,
    flat_crests: bool = False,
) -> list[MacroFeature]:
    """Group 1-D curvature features into macro features and classify them (Table 3.1).

    Features whose gap is at most ``r_f`` are grouped (Definition 2); each group is classified
    by the signs of its members in path order (rules in the module docstring): one feature is
    a ``cusp``; ``-+`` or ``+-`` a ``step``; ``-+-`` a ``bump`` (``ridge`` when the second
    principal curvature at the inner peak satisfies ``|k2| <= 1/r_f``); ``+-+`` a ``pit``
    (``ravine`` likewise); anything else ``unknown``.

    Args:
        features: curvature features of ``k1`` along one path, e.g. from
            :func:`curvature_features_1d`.
        tip_radius: fingertip radius ``r_f`` [units of ``s``].
        s: (N,) the path samples, only needed with ``k2``.
        k2: (N,) second principal curvature along the path [1/m]; lets ``-+-`` be told apart
            as bump/ridge and ``+-+`` as pit/ravine. Without it, bump and pit are returned.
        flat_crests: the 1-D extension of a fingertip path (:data:`FLAT_CRESTS`): a flat
            crest between two convex edges, ``-++-``, is a ridge and a flat floor between
            two concave edges, ``+--+``, a ravine (a rectangular ridge/ravine crossed at
            right angles).

    Returns:
        Macro features in order of ``start``; ``position`` is the mean of the member
        positions when they all have one.

    Raises:
        InvalidParameter: ``tip_radius <= 0``, or ``k2`` given without a matching ``s``.
    """
    r = checks.positive("tip_radius", tip_radius, "m")
    if (s is None) != (k2 is None):
        raise InvalidParameter(
            "pass both s and k2 (the path samples and the second principal"
            " curvature along them) or neither"
        )
    if s is not None:
        s, k2 = _check_signal(s, k2)
    out: list[MacroFeature] = []
    for group in group_features_1d(features, r):
        signs = [f.sign for f in group]
        pattern = sign_text(signs)
        inner = None
        if k2 is not None and len(group) == 3:
            inner = float(np.interp(group[1].peak, s, k2))
        kind = classify_pattern(signs, inner, r)
        if flat_crests and pattern in FLAT_CRESTS:
            kind = FLAT_CRESTS[pattern]
        pos = None
        if all(f.position is not None for f in group):
            pos = np.mean([np.asarray(f.position, dtype=float) for f in group], axis=0)
        out.append(
            MacroFeature(
                kind=kind,
                start=float(group[0].start),
                end=float(max(f.end for f in group)),
                signs=pattern,
                features=group,
                position=pos,
            )
        )
    return out


__all__ = [
    "MACRO_KINDS",
    "CurvatureRegion",
    "FeatureMap",
    "MacroRegion",
    "curvature_feature_map",
    "multiscale_feature_maps",
    "FLAT_CRESTS",
    "CurvatureFeature",
    "CurvatureFeature1D",
    "MacroFeature",
    "MacroFeature1D",
    "classify_pattern",
    "curvature_features_1d",
    "group_features_1d",
    "macro_features_1d",
    "sign_text",
    "threshold_runs",
]
