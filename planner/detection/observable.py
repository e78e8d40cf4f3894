"""Ground truth as a fingertip can know it: the *observable* curvature features of a
simulated trace, and the sample at which the fingertip passes each one.

A fingertip cannot tell apart two same-sign features inside one unobservable region (a gap
of the contact locus, between the two contacts of an interference point, thesis §3.2.1), nor
two it passes within r_f/4 of path length: those count as one, at their mean position.
Shared by the simulators of :mod:`planner.detection.synthetic` (feature-on-a-plane shapes)
and :mod:`planner.detection.profile_trace` (the geometry package's exact profiles).

Both describe where a true feature lies, and where the contact point is, by one coordinate
that increases along the profile: the abscissa along the plane for a shape, the arclength of
the profile for a :class:`~planner.geometry.profiles.Profile`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from planner.detection.types import CurvatureFeature


def _merged(prev: CurvatureFeature, f: CurvatureFeature) -> CurvatureFeature:
    """One feature standing for ``prev`` and ``f`` (same sign), at their mean position."""
    return CurvatureFeature(
        sign=f.sign,
        start=prev.start,
        end=f.end,
        peak=0.5 * (prev.peak + f.peak),
        position=0.5 * (np.asarray(prev.position) + np.asarray(f.position)),
    )


def _merge_in_gaps(
    truth: Sequence[CurvatureFeature], coords: Sequence[float], contact_u: np.ndarray, gap: float
) -> tuple[list[CurvatureFeature], list[float]]:
    """Merge same-sign true features lying in the same gap of the contact locus.

    Args:
        truth: true features in path order.
        coords: (K,) coordinate of each feature's peak along the profile [m].
        contact_u: (M,) coordinate of the contact point along a dense noise-free trace [m],
            non-decreasing.
        gap: smallest jump of ``contact_u`` that is a gap (an unobservable region) [m].

    Returns:
        The merged features and their coordinates (the mean of the merged ones) [m].
    """
    jumps = np.flatnonzero(np.diff(contact_u) > gap)
    gaps = [(contact_u[j], contact_u[j + 1]) for j in jumps]

    def gap_of(u: float) -> int:
        for i, (a, b) in enumerate(gaps):
            if a < u < b:
                return i
        return -1

    out: list[CurvatureFeature] = []
    out_u: list[float] = []
    last_gap = -2
    for f, u in zip(truth, coords, strict=True):
        g = gap_of(u)
        if out and g >= 0 and g == last_gap and out[-1].sign == f.sign:
            f = _merged(out.pop(), f)
            u = 0.5 * (out_u.pop() + u)
        out.append(f)
        out_u.append(float(u))
        last_gap = g
    return out, out_u


def _merge_passed_together(
    feats: Sequence[CurvatureFeature], idx: np.ndarray, s: np.ndarray, gap: float
) -> tuple[tuple[CurvatureFeature, ...], np.ndarray]:
    """Same-sign features the fingertip passes within ``gap`` of path length [m] count once
    (e.g. the two bottom corners of a groove it only just touches)."""
    out: list[CurvatureFeature] = []
    out_idx: list[int] = []
    for f, i in zip(feats, idx, strict=True):
        if out and out[-1].sign == f.sign and s[i] - s[out_idx[-1]] < gap:
            f = _merged(out.pop(), f)
            i = (i + out_idx.pop()) // 2
        out.append(f)
        out_idx.append(int(i))
    return tuple(out), np.array(out_idx, dtype=int)


def observable_truth(
    truth: Sequence[CurvatureFeature],
    coords: Sequence[float],
    contact_u: np.ndarray,
    sample_u: np.ndarray,
    s: np.ndarray,
    tip_radius: float,
    *,
    gap: float,
    tie: float = 0.0,
) -> tuple[tuple[CurvatureFeature, ...], np.ndarray]:
    """The observable ground truth of a simulated trace and where the fingertip passes it.

    Args:
        truth: exact curvature features (Definition 1) in path order.
        coords: (K,) coordinate of each true feature's peak along the profile [m].
        contact_u: (M,) coordinate of the true contact point along a dense noise-free trace,
            non-decreasing [m]; its jumps larger than ``gap`` are the unobservable regions.
        sample_u: (N,) the same coordinate for the contact point of each trace sample,
            non-decreasing [m].
        s: (N,) arclength of the fingertip-centre path at each sample [m].
        tip_radius: fingertip radius r_f [m].
        gap: smallest jump of ``contact_u`` that counts as an unobservable region [m].
        tie: coordinates within ``tie`` of a feature count as on it [m] (the resolution of
            ``sample_u``; 0 when it is exact).

    Returns:
        ``(observable, index)``: the observable features, and (K',) the sample index at which
        the contact point passes each one (the middle of the samples on it, e.g. while the
        fingertip rolls over a sharp convex corner; the first sample past it when it lies in
        an unobservable region).
    """
    feats, u = _merge_in_gaps(truth, coords, contact_u, gap)
    u = np.asarray(u, dtype=float)
    i0 = np.searchsorted(sample_u, u - tie, side="left")
    i1 = np.searchsorted(sample_u, u + tie, side="right")
    idx = np.clip((i0 + np.maximum(i1 - 1, i0)) // 2, 0, len(sample_u) - 1)
    return _merge_passed_together(feats, idx, s, tip_radius / 4)


__all__ = ["observable_truth"]
