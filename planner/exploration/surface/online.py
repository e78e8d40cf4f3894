"""Online feature detection: algorithm 3 over a sliding window of the streamed path (§4.2).

While the finger searches, :class:`OnlineDetector` re-runs the detector of
:mod:`planner.exploration.surface.detection_adapter` on the last ``window`` metres of the
fingertip-centre path, subsampled to about ``r_f/100`` along the path
(:func:`window_samples`). A macro feature (curvature features within ``r_f`` of each other,
Definition 2) is reported once the finger is more than
``1.25 r_f`` past its last curvature feature, i.e. when the whole pattern has been crossed;
the **latency** is the time from crossing the peak of that last feature to the report.
Features inside the known area of already explored features are ignored, and so are
features whose peak lies within :data:`EDGE` ``r_f`` (two smoothing scales of the detector)
of either end of the analysed path: there the Gaussian smoothing runs off the data and the
finger accelerates from rest over steps of the quantized encoders, which reads as curvature.

§4.4.1: "the finger can actually travel over a feature without detecting it. Thus, it may be
desired to perform type detection even if it is uncertain whether the curvature is sharp
enough". A crest crossed obliquely shows only ``cos^2`` of its curvature along the path
(Euler), below ``1/r_f``; so when the window holds no curvature feature but the path *turns*
by more than :data:`TURN` over half a fingertip radius on each side of a point the finger
has left by ``1.25 r_f``, that point is reported as an uncertain feature (pattern ``"+"`` or
``"-"``) and identified like any other.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.exploration.surface.detection_adapter import analyse_path, collapse_pattern

__all__ = [
    "EDGE",
    "SPACING",
    "STRIDE",
    "TURN",
    "Detection",
    "OnlineDetector",
    "uncertain_turn",
    "window_samples",
]

#: margin at the ends of the analysed path where curvature features are not trusted [r_f]
EDGE = 0.2
#: the window is analysed again once the finger has moved this far [r_f] (1 mm: a report
#: comes at most ~30 ms later at the search speed; algorithm 3 over the window is ~1.5 ms)
STRIDE = 0.125
#: turn [rad] of the centre path over ``r_f / 2`` on each side of a point that asks for type
#: identification without a curvature feature: a surface at the Definition 1 threshold
#: (curvature ``1/r_f``) crossed at 60 deg from its principal direction has a normal
#: curvature of ``cos^2(60 deg)/r_f = 1/(4 r_f)``, its offset by ``r_f`` ``1/(5 r_f)``, which
#: turns the path by 0.1 rad over ``r_f / 2``
TURN = 0.1
#: spacing of the samples handed to algorithm 3 along the path [r_f]
SPACING = 0.01


@dataclass(frozen=True)
class Detection:
    """A macro feature met by the search.

    Attributes:
        points: (K, 2) its curvature-feature points in the plate frame [m].
        signs: (K,) their signs; pattern: collapsed sign pattern.
        k_first, k_last: recorder indices of its first and last curvature-feature peaks.
        k_start, k_end: recorder range of the analysed window.
        t: time of the report [s]; latency: report time minus last peak time [s].
    """

    points: np.ndarray
    signs: np.ndarray
    pattern: str
    k_first: int
    k_last: int
    k_start: int
    k_end: int
    t: float
    latency: float

    @property
    def centre(self) -> np.ndarray:
        """(2,) middle of its curvature features [m]."""
        return 0.5 * (self.points.min(axis=0) + self.points.max(axis=0))


class OnlineDetector:
    """Sliding-window detection over the explorer's recorder (see the module doc).

    Args:
        ex: the :class:`~planner.exploration.surface.runtime.ExplorerController`.
        tip_radius: r_f [m]; window: window length along the path [m].
        known: callable ``known(point (2,)) -> bool`` (already explored area).
    """

    def __init__(self, ex, tip_radius: float, window: float, known) -> None:
        self.ex, self.r, self.window, self.known = ex, tip_radius, window, known
        self.latencies: list[float] = []
        self.calls = 0
        self._last = None  # (2,) where the last analysis ended

    def __call__(self, k0: int, k1: int, flush: bool = False) -> Detection | None:
        """Detection in the recorder range ``k0:k1`` (``flush``: the sweep ended, report
        features the finger has not yet left by ``1.25 r_f``)."""
        rec = self.ex.rec
        if k1 - k0 < 30:
            return None
        here = rec.centre[k1 - 1, :2]
        if (
            not flush
            and self._last is not None
            and float(np.hypot(*(here - self._last))) < (STRIDE * self.r)
        ):
            return None  # less than STRIDE r_f of new path since the last analysis
        self._last = here.copy()
        self.calls += 1
        idx = window_samples(rec.centre[k0:k1, :2], self.window, SPACING * self.r) + k0
        i0 = int(idx[0])
        a = analyse_path(rec.centre[idx], self.r)
        if not a.features:
            return self._uncertain(a, idx, k1, i0, flush)
        s_now = a.s[-1]
        edge = EDGE * self.r
        feats = [f for f in a.features if edge <= f.s <= s_now - edge]
        if not feats:
            return None
        groups, cur = [], [feats[0]]
        for f in feats[1:]:
            if f.start - cur[-1].end <= self.r:
                cur.append(f)
            else:
                groups.append(cur)
                cur = [f]
        groups.append(cur)
        for g in groups:
            if g[-1].end > s_now - (0.0 if flush else 1.25 * self.r):
                continue  # the finger is still on it
            pts = _with_relief_extreme(np.array([f.point for f in g]), g, a, self.r)
            if pts is None and not flush:
                continue  # a lone foot and the finger still climbing (descending) the flank
            if pts is None:
                pts = np.array([f.point for f in g])
            mid = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
            if self.known(mid):
                continue
            first = int(idx[int(round(g[0].index))])
            last = int(idx[int(round(g[-1].index))])
            lat = float(rec.t[k1 - 1] - rec.t[last])
            self.latencies.append(lat)
            signs = np.array([f.sign for f in g])
            return Detection(
                pts, signs, collapse_pattern(signs), first, last, i0, k1, rec.t[k1 - 1], lat
            )
        return None

    def _uncertain(self, a, idx: np.ndarray, k1: int, i0: int, flush: bool) -> Detection | None:
        """A point of the window where the path turns by more than :data:`TURN` (no
        curvature feature in the window), once the finger has left it by ``1.25 r_f``."""
        j, turn = uncertain_turn(a.s, a.w, 0.5 * self.r, 0.0 if flush else 1.25 * self.r)
        if j < 0 or abs(turn) < TURN:
            return None
        sign = 1 if turn > 0 else -1
        # a concave turn is the foot of a raised feature (a convex one the lip of a sunken
        # one): span the feature to its crest like a lone curvature feature does
        lone = _Turn(sign, float(j))
        pts = _with_relief_extreme(a.point_at(j)[None].copy(), [lone], a, self.r)
        if pts is None and not flush:
            return None  # still on the flank
        if pts is None:
            pts = a.point_at(j)[None].copy()
        mid = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
        if self.known(mid):
            return None
        rec = self.ex.rec
        k = int(idx[j])
        lat = float(rec.t[k1 - 1] - rec.t[k])
        self.latencies.append(lat)
        pattern = "+" if sign > 0 else "-"
        return Detection(pts, np.array([sign]), pattern, k, k, i0, k1, rec.t[k1 - 1], lat)


def window_samples(uv: np.ndarray, window: float, spacing: float) -> np.ndarray:
    """Indices into ``uv`` (N, 2) [m] of the samples of its last ``window`` [m] of path,
    about ``spacing`` [m] apart along the path (the last sample always kept).

    The window and the subsampling are measured along the path's arclength, not in samples:
    the quantized encoders repeat a centre for several 1 kHz steps at a low speed (44 % of
    the steps at 0.02 m/s), so a spacing estimated per step - the median step was 0 there -
    collapsed the window to a few samples.
    """
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(uv, axis=0).T))])
    lo = int(np.searchsorted(s, s[-1] - window, side="left"))
    marks = np.arange(s[-1], s[lo] - 0.5 * spacing, -spacing)[::-1]
    idx = np.searchsorted(s, marks, side="left")
    idx[-1] = len(s) - 1
    return np.unique(idx)


@dataclass(frozen=True)
class _Turn:
    """A turn of the path standing in for a lone curvature feature (sign, sample index)."""

    sign: int
    index: float


def uncertain_turn(s: np.ndarray, w: np.ndarray, r: float, past: float) -> tuple[int, float]:
    """``(j, turn)``: the sample of a path (horizontal arclength ``s`` (N,), centre heights
    ``w`` (N,) [m]) where the path turns most over ``r`` [m] on each side, at least ``r``
    from its start and ``past`` [m] before its end, and that turn [rad] (positive convex:
    the slope behind minus the slope ahead); ``(-1, 0.0)`` when the path is too short.
    Heights are averaged over ``r/4`` at each end of the two chords (encoder quantization:
    0.05 mm steps)."""
    s, w = np.asarray(s, float), np.asarray(w, float)
    if len(s) < 10 or s[-1] - s[0] < 2 * r + past:
        return -1, 0.0
    h = r / 4
    cs = np.concatenate([[0.0], np.cumsum(w)])

    def mean_at(x: np.ndarray) -> np.ndarray:
        lo = np.searchsorted(s, x - h / 2)
        hi = np.maximum(np.searchsorted(s, x + h / 2), lo + 1)
        hi = np.minimum(hi, len(w))
        lo = np.minimum(lo, hi - 1)
        return (cs[hi] - cs[lo]) / (hi - lo)

    cand = np.flatnonzero((s >= s[0] + r) & (s <= s[-1] - max(past, r)))
    if cand.size == 0:
        return -1, 0.0
    x = s[cand]
    mid = mean_at(x)
    behind = (mid - mean_at(x - r)) / r
    ahead = (mean_at(x + r) - mid) / r
    turn = np.arctan(behind) - np.arctan(ahead)
    i = int(np.argmax(np.abs(turn)))
    return int(cand[i]), float(turn[i])


def _with_relief_extreme(pts: np.ndarray, group, analysis, r: float, least: float = 3e-4):
    """The group's points plus, for a lone curvature feature (one sign: the foot of a wide
    ridge seen by a ball whose crest reads flatter than ``1/r_f``, a step's edge), the point
    of the path after it that departs most from its height (the crest), when that departs by
    more than ``least`` [m]: the detection then spans the feature instead of sitting on its
    foot. None while that point is the end of the window (the finger is still on the flank:
    wait)."""
    if len({f.sign for f in group}) > 1:
        return pts
    s, w = analysis.s, analysis.w
    i0 = int(round(group[0].index))
    if i0 >= len(w) - 2:
        return pts
    dev = np.abs(w[i0:] - w[i0])
    j = i0 + int(np.argmax(dev))
    if dev[j - i0] < least:
        return pts
    if s[-1] - s[j] < 0.25 * r:
        return None
    return np.vstack([pts, analysis.point_at(j)])
