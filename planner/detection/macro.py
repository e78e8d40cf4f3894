"""Macro features from detected curvature features (thesis §3.2.2, Definition 2, Table 3.1).

Grouping (gap at most ``r_f``) and the Table 3.1 sign rules come from
:mod:`planner.geometry.features`. Gaps are measured along the fingertip-centre path, the
arclength the features carry. On a 1-D path the second principal curvature is unknown, so
``-+-`` reads as a bump (a wire lying on a plane, §3.4.2) and ``+-+`` as a pit, as in
§3.2.3. One 1-D extension: a flat crest between two convex edges, ``-++-``, is a ridge and a
flat floor between two concave edges, ``+--+``, a ravine (a rectangular ridge/ravine crossed
at right angles).
"""

from __future__ import annotations

from collections.abc import Sequence

from planner import checks
from planner.errors import InvalidParameter
from planner.geometry.features import (
    FLAT_CRESTS,
    CurvatureFeature,
    MacroFeature,
    classify_pattern,
    macro_features_1d,
    sign_text,
)


def classify_signs(signs: Sequence[int], tip_radius: float) -> str:
    """Macro-feature kind of a sign pattern along a path (Table 3.1 + the 1-D extension).

    Args:
        signs: +1/-1 signs of grouped curvature features in path order.
        tip_radius: fingertip radius r_f [m].

    Returns:
        One of ``"bump", "pit", "ridge", "ravine", "step", "cusp", "unknown"``.
    """
    return FLAT_CRESTS.get(sign_text(signs)) or classify_pattern(list(signs), None, tip_radius)


def macro_features(features: Sequence[CurvatureFeature], tip_radius: float) -> list[MacroFeature]:
    """Group curvature features within ``tip_radius`` of each other and classify each group.

    Args:
        features: curvature features of one path (any order), e.g. from
            :func:`planner.detection.detect_features`; each needs ``sign``, ``start``,
            ``end`` and ``position``.
        tip_radius: fingertip radius r_f [m].

    Returns:
        Macro features in path order; ``.kind`` is one of
        ``"bump", "pit", "ridge", "ravine", "step", "cusp", "unknown"`` and ``.position``
        is the mean of the member positions [m].

    Raises:
        InvalidParameter: ``tip_radius <= 0`` or a feature without the needed attributes.
    """
    r = checks.positive("tip_radius", tip_radius, "m")
    feats = list(features)
    for i, f in enumerate(feats):
        if not all(hasattr(f, a) for a in ("sign", "start", "end", "position")):
            raise InvalidParameter(
                f"features[{i}]: expected a curvature feature with "
                f"sign, start, end and position, got {type(f).__name__}"
            )
        if f.sign not in (1, -1):
            raise InvalidParameter(f"features[{i}].sign: expected +1 or -1, got {f.sign!r}")
    return macro_features_1d(feats, r, flat_crests=True)


__all__ = ["classify_signs", "macro_features"]
