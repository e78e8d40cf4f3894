"""Settings of the detection algorithms of thesis Fig. 3.8, as one frozen, self-checking
dataclass."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

from planner import checks
from planner.errors import InvalidParameter

MATERIAL_SIDES = ("auto", "right", "left")
NORMAL_ARCLENGTHS = ("center", "contact")


@dataclass(frozen=True)
class DetectionSettings:
    """Settings of :func:`planner.detection.detect_features` (all optional).

    Attributes:
        smoothing_scale: Gaussian smoothing scale along the path [m]; ``None``: chosen from
            the noise estimated in the data (:func:`planner.detection.signals.default_scale`,
            about ``tip_radius/10`` at the thesis' noise level).
        material_side: side of the direction of travel where the object lies:
            ``"auto"`` (default: from the measured normals/contacts when given, else
            inferred from the path itself — on a traced curve the curvature toward the
            material never exceeds 1/r_f while interference kinks bend away from it — and,
            when the path cannot tell, on the right of travel, as for an open profile
            traced in +x with material below), ``"right"`` or ``"left"``.
        merge_gap: same-sign regions closer than this are merged [m] (``None``: the
            smoothing scale; noise dips inside one feature).
        upper: convex threshold of the signal [1/m] (``None``: the algorithm's own, > 0).
        lower: concave threshold of the signal [1/m] (``None``: the algorithm's own, < 0).
        normal_arclength: algorithm 2: differentiate the normal with respect to the
            arclength of the fingertip-centre path (``"center"``, the experiment of §3.4.2)
            or of the contact path (``"contact"``, the literal reading of §3.3.1).
    """

    smoothing_scale: float | None = None
    material_side: str = "auto"
    merge_gap: float | None = None
    upper: float | None = None
    lower: float | None = None
    normal_arclength: str = "center"

    def __post_init__(self) -> None:
        if self.smoothing_scale is not None:
            checks.positive("smoothing_scale", self.smoothing_scale, "m")
        checks.choice("material_side", self.material_side, MATERIAL_SIDES)
        if self.merge_gap is not None:
            checks.nonnegative("merge_gap", self.merge_gap, "m")
        if self.upper is not None:
            checks.positive("upper", self.upper, "1/m")
        if self.lower is not None:
            checks.in_range("lower", self.lower, -math.inf, 0.0, "1/m", closed=(False, False))
        checks.choice("normal_arclength", self.normal_arclength, NORMAL_ARCLENGTHS)

    @classmethod
    def of(
        cls, settings: DetectionSettings | None = None, **overrides: object
    ) -> DetectionSettings:
        """``settings`` (default: all defaults) with the keyword ``overrides`` applied.

        Raises:
            InvalidParameter: an unknown setting or a bad value.
        """
        base = cls() if settings is None else settings
        if not isinstance(base, cls):
            raise InvalidParameter(
                f"settings: expected a DetectionSettings, got {type(base).__name__}"
            )
        known = [f.name for f in fields(cls)]
        unknown = sorted(set(overrides) - set(known))
        if unknown:
            raise InvalidParameter(
                f"settings: unknown setting(s) {unknown}; expected any of {known}"
            )
        return replace(base, **overrides) if overrides else base


__all__ = ["MATERIAL_SIDES", "DetectionSettings"]
