"""Online feature detection: algorithm 3 over a sliding window of the streamed path (§4.2).

While the finger searches, :class:`OnlineDetector` re-runs the detector of
:mod:`planner.exploration.surface.detection_adapter` on the last ``window`` metres of the
fingertip-centre path (subsampled to about ``r_f/100``). A macro feature (curvature features
within ``r_f`` of each other, Definition 2) is reported once the finger is more than
``1.25 r_f`` past its last curvature feature, i.e. when the whole pattern has been crossed;
the **latency** is the time from crossing the peak of that last feature to the report.
Features inside the known area of already explored features are ignored, and so are
features whose peak lies within :data:`EDGE` ``r_f`` (two smoothing scales of the detector)
of either end of the analysed path: there the Gaussian smoothing runs off the data and the
finger accelerates from rest over steps of the quantized encoders, which reads as curvature.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.exploration.surface.detection_adapter import analyse_path, collapse_pattern

__all__ = ["EDGE", "STRIDE", "Detection", "OnlineDetector"]

#: margin at the ends of the analysed path where curvature features are not trusted [r_f]
EDGE = 0.2
#: the window is analysed again once the finger has moved this far [r_f] (1 mm: a report
#: comes at most ~30 ms later at the search speed; algorithm 3 over the window is ~1.5 ms)
STRIDE = 0.125


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
        C = rec.centre[k0:k1]
        step = np.hypot(*np.diff(C[-60:, :2], axis=0).T)
        ds = max(float(np.median(step)), 1e-7)
        n_win = min(k1 - k0, int(self.window / ds))
        stride = max(1, int(round(self.r / 100 / ds)))
        i0 = k1 - n_win
        idx = np.arange(i0, k1, stride)
        a = analyse_path(rec.centre[idx], self.r)
        if not a.features:
            return None
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
