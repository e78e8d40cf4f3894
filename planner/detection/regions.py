"""Threshold a curvature signal into feature regions (App. B.2 steps 6-7): Definition 1
(:func:`planner.geometry.features.threshold_runs`) plus the merging of noise dips."""

from __future__ import annotations

import numpy as np

from planner.geometry.features import threshold_runs


def threshold_regions(
    signal: np.ndarray, s: np.ndarray, upper: float, lower: float, merge_gap: float = 0.0
) -> list[tuple[int, int, int, int]]:
    """Regions where ``signal > upper`` (sign +1) or ``signal < lower`` (sign -1).

    Runs of the same sign separated by less than ``merge_gap`` of arclength (noise dips
    inside one feature) are merged.

    Args:
        signal: (M,) curvature signal [1/m] (non-finite values never count as features).
        s: (M,) arclength of each sample [m], non-decreasing.
        upper: convex threshold [1/m].
        lower: concave threshold [1/m].
        merge_gap: largest gap between same-sign runs that are merged [m].

    Returns:
        ``[(sign, first, last, peak), ...]`` sample indices, sorted by ``first``.
    """
    sig = np.where(np.isfinite(signal), signal, 0.0)
    out: list[tuple[int, int, int, int]] = []
    for sign in (1, -1):
        merged: list[list[int]] = []
        for _, a, b, _ in (r for r in threshold_runs(sig, upper, lower) if r[0] == sign):
            if merged and s[a] - s[merged[-1][1]] < merge_gap:
                merged[-1][1] = b
            else:
                merged.append([a, b])
        for a, b in merged:
            out.append((sign, a, b, a + int(np.argmax(sign * sig[a : b + 1]))))
    out.sort(key=lambda r: r[1])
    return out


__all__ = ["threshold_regions"]
