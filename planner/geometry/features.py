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

from planner.errors import InvalidParameter
from planner.geometry.feature_maps import (  # 2-D maps, re-exported
    CurvatureRegion,
    FeatureMap,
    MacroRegion,
    curvature_feature_map,
    multiscale_feature_maps,
)

MACRO_KINDS = ("bump", "pit", "ridge", "ravine", "step", "cusp", "unknown")


@dataclass(frozen=True)
class CurvatureFeature1D:
    """A curvature feature along a path (Definition 1 of §3.2.2).

    Attributes:
        sign: +1 for a convex feature (``k > 1/r_f``), -1 for a concave one (``k < -1/r_f``).
        start: where the curvature crosses the threshold entering the feature, linearly
            interpolated between samples [units of ``s``]; ``s[0]`` if the signal starts inside.
        end: where it crosses the threshold leaving the feature [units of ``s``]; ``s[-1]`` if
            the signal ends inside.
        peak: the sample of ``s`` where ``|k|`` is largest inside the feature [units of ``s``].
        peak_curvature: the curvature at ``peak`` (signed) [1/units of ``s``].
        open_start: the feature begins at the first sample (its true start is unknown).
        open_end: the feature ends at the last sample (its true end is unknown).
    """

    sign: int
    start: float
    end: float
    peak: float
    peak_curvature: float
    open_start: bool = False
    open_end: bool = False

    @property
    def width(self) -> float:
        """Length of the feature, ``end - start`` [units of ``s``]."""
        return self.end - self.start


@dataclass(frozen=True)
class MacroFeature1D:
    """A macro feature along a path (Definition 2 and Table 3.1 of §3.2.2).

    Attributes:
        kind: one of ``"bump", "pit", "ridge", "ravine", "step", "cusp", "unknown"``.
        members: the grouped curvature features, in order of ``start``.
        start: start of the first member [units of ``s``].
        end: end of the last member [units of ``s``].
        pattern: the signs of the members as text, e.g. ``"-+-"``.
    """

    kind: str
    members: tuple[CurvatureFeature1D, ...]
    start: float
    end: float
    pattern: str


def _check_radius(tip_radius: float) -> float:
    try:
        r = float(tip_radius)
    except (TypeError, ValueError):
        raise InvalidParameter(
            f"tip_radius must be a positive number [m], got {tip_radius!r}"
        ) from None
    if not np.isfinite(r) or r <= 0.0:
        raise InvalidParameter(f"tip_radius must be a finite number > 0 [m], got {tip_radius!r}")
    return r


def _check_signal(s: np.ndarray, k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    s = np.asarray(s, dtype=float)
    k = np.asarray(k, dtype=float)
    if s.ndim != 1 or k.ndim != 1:
        raise InvalidParameter(f"s and k must be 1-D arrays, got shapes {s.shape} and {k.shape}")
    if s.shape != k.shape:
        raise InvalidParameter(f"s and k must have the same length, got {s.size} and {k.size}")
    if s.size < 2:
        raise InvalidParameter(f"need at least 2 samples, got {s.size}")
    if not (np.all(np.isfinite(s)) and np.all(np.isfinite(k))):
        raise InvalidParameter("s and k must be finite (no NaN or inf)")
    if np.any(np.diff(s) <= 0.0):
        bad = int(np.argmax(np.diff(s) <= 0.0))
        raise InvalidParameter(
            f"s must be strictly increasing; s[{bad}]={s[bad]!r} >= s[{bad + 1}]={s[bad + 1]!r}"
        )
    return s, k


def _crossing(s: np.ndarray, k: np.ndarray, i: int, level: float) -> float:
    """Linear interpolation of where ``k`` equals ``level`` between samples ``i`` and ``i+1``."""
    k0, k1 = k[i], k[i + 1]
    t = (level - k0) / (k1 - k0)
    return float(s[i] + t * (s[i + 1] - s[i]))


def curvature_features_1d(
    s: np.ndarray, k: np.ndarray, tip_radius: float
) -> list[CurvatureFeature1D]:
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
    r = _check_radius(tip_radius)
    s, k = _check_signal(s, k)
    thr = 1.0 / r
    features: list[CurvatureFeature1D] = []
    for sign in (1, -1):
        inside = sign * k > thr
        if not inside.any():
            continue
        edges = np.diff(inside.astype(np.int8))
        starts = list(np.flatnonzero(edges == 1) + 1)
        ends = list(np.flatnonzero(edges == -1))
        if inside[0]:
            starts.insert(0, 0)
        if inside[-1]:
            ends.append(s.size - 1)
        for i0, i1 in zip(starts, ends, strict=True):
            seg = slice(i0, i1 + 1)
            ip = i0 + int(np.argmax(sign * k[seg]))
            features.append(
                CurvatureFeature1D(
                    sign=sign,
                    start=float(s[0]) if i0 == 0 else _crossing(s, k, i0 - 1, sign * thr),
                    end=float(s[-1]) if i1 == s.size - 1 else _crossing(s, k, i1, sign * thr),
                    peak=float(s[ip]),
                    peak_curvature=float(k[ip]),
                    open_start=bool(i0 == 0),
                    open_end=bool(i1 == s.size - 1),
                )
            )
    features.sort(key=lambda f: f.start)
    return features


def group_features_1d(
    features: Sequence[CurvatureFeature1D], tip_radius: float
) -> list[tuple[CurvatureFeature1D, ...]]:
    """Group curvature features whose gap is at most ``r_f`` (Definition 2, §3.2.2).

    Args:
        features: curvature features along one path (any order).
        tip_radius: fingertip radius ``r_f`` [units of ``s``].

    Returns:
        Groups in order of ``start``; each group's members are in order of ``start`` and the
        gap ``next.start - previous.end`` between consecutive members is ``<= r_f``.
    """
    r = _check_radius(tip_radius)
    ordered = sorted(features, key=lambda f: f.start)
    groups: list[list[CurvatureFeature1D]] = []
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
    thr = 1.0 / _check_radius(tip_radius)
    pattern = "".join("+" if x > 0 else "-" for x in signs)
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
    features: Sequence[CurvatureFeature1D],
    tip_radius: float,
    *,
    s: np.ndarray | None = None,
    k2: np.ndarray | None = None,
) -> list[MacroFeature1D]:
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

    Returns:
        Macro features in order of ``start``.

    Raises:
        InvalidParameter: ``tip_radius <= 0``, or ``k2`` given without a matching ``s``.
    """
    r = _check_radius(tip_radius)
    if (s is None) != (k2 is None):
        raise InvalidParameter(
            "pass both s and k2 (the path samples and the second principal"
            " curvature along them) or neither"
        )
    if s is not None:
        s, k2 = _check_signal(s, k2)
    out: list[MacroFeature1D] = []
    for group in group_features_1d(features, r):
        signs = [f.sign for f in group]
        inner = None
        if k2 is not None and len(group) == 3:
            inner = float(np.interp(group[1].peak, s, k2))
        out.append(
            MacroFeature1D(
                kind=classify_pattern(signs, inner, r),
                members=group,
                start=group[0].start,
                end=max(f.end for f in group),
                pattern="".join("+" if x > 0 else "-" for x in signs),
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
    "CurvatureFeature1D",
    "MacroFeature1D",
    "classify_pattern",
    "curvature_features_1d",
    "group_features_1d",
    "macro_features_1d",
]
