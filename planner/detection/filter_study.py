"""The filter comparison of App. B.4: rate noise-type smoothing filters by the false positives
plus false negatives of the App. B.2 detection scheme on data with known features."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.detection.scheme_b2 import b2_scheme
from planner.detection.scoring import score_features
from planner.detection.smoothing import FILTERS, smooth
from planner.errors import InvalidParameter


@dataclass(frozen=True)
class FilterSetting:
    """One filter configuration.

    Attributes:
        method: one of :data:`planner.detection.smoothing.FILTERS`.
        window: window [samples] (corner-cutting iterations for ``dual_point``).
        sigma: Gaussian standard deviation [samples] (``gaussian`` only, else ``None``).
    """

    method: str
    window: int
    sigma: float | None = None


@dataclass(frozen=True)
class StudyTrace:
    """One noisy trace with the times of its true features.

    Attributes:
        t: (N,) time stamps [s] (constant rate).
        centers: (N, 2) measured positions [m].
        truth_signs: (K,) +1/-1 of the true features.
        truth_times: (K,) when the fingertip passes each of them [s].
    """

    t: np.ndarray
    centers: np.ndarray
    truth_signs: tuple[int, ...]
    truth_times: tuple[float, ...]


@dataclass(frozen=True)
class FilterScore:
    """Mean detection errors of one setting over the study's traces.

    Attributes:
        setting: the filter.
        fp, fn: mean false positives / false negatives per trace.
        errors: ``fp + fn`` (the thesis' rating).
    """

    setting: FilterSetting
    fp: float
    fn: float

    @property
    def errors(self) -> float:
        return self.fp + self.fn


@dataclass(frozen=True)
class _Truth:
    sign: int
    peak: float


def grid(
    filters: Sequence[str],
    windows: Sequence[int],
    sigmas: Sequence[float],
    dual_point_iterations: Sequence[int] = (1, 2, 3, 4),
) -> list[FilterSetting]:
    """All settings of a filters x windows (x sigmas for Gaussian) grid."""
    out: list[FilterSetting] = []
    for m in filters:
        if m not in FILTERS:
            raise InvalidParameter(f"filters: got {m!r}; expected one of {list(FILTERS)}")
        if m == "none":
            out.append(FilterSetting("none", 1))
        elif m == "dual_point":
            out += [FilterSetting(m, int(k)) for k in dual_point_iterations]
        elif m == "gaussian":
            out += [FilterSetting(m, int(w), float(s)) for w in windows for s in sigmas]
        else:
            out += [FilterSetting(m, int(w)) for w in windows]
    return out


def rate_filters(
    traces: Sequence[StudyTrace],
    settings: Sequence[FilterSetting],
    tip_radius: float,
    tolerance: float,
    *,
    decimate: int = 1,
    curvature_sigma: float = 2.0,
) -> list[FilterScore]:
    """Filter each trace with each setting, run the App. B.2 scheme, count FP and FN.

    Args:
        traces: noisy traces with known feature times.
        settings: filter settings to rate.
        tip_radius: r_f [m] (thresholds of the scheme: +-1/(2 r_f)).
        tolerance: largest time difference of a match [s].
        decimate: App. B.2 step 2.
        curvature_sigma: App. B.2 step 5 [kept samples].

    Returns:
        One :class:`FilterScore` per setting, in the order given.
    """
    r = checks.positive("tip_radius", tip_radius, "m")
    tol = checks.positive("tolerance", tolerance, "s")
    out = []
    for st in settings:
        fps, fns = [], []
        for tr in traces:
            xy = smooth(tr.centers, st.method, st.window, st.sigma)
            res = b2_scheme(xy[:, 0], xy[:, 1], r, t=tr.t, decimate=decimate, sigma=curvature_sigma)
            truth = [_Truth(s, t) for s, t in zip(tr.truth_signs, tr.truth_times, strict=True)]
            sc = score_features(res.features, truth, tol, key="peak")
            fps.append(sc.fp)
            fns.append(sc.fn)
        out.append(FilterScore(st, float(np.mean(fps)), float(np.mean(fns))))
    return out


__all__ = ["FilterScore", "FilterSetting", "StudyTrace", "grid", "rate_filters"]
