"""Multiscale detection (thesis §3.2.2, end): after exploring with a fingertip of radius
r_f, simulate fingertips of radius r_i >= r_f rolling over the *estimated* surface and detect
the features they would see. r_i < r_f is impossible: the unobservable regions of the real
exploration hold no information."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from planner import checks
from planner.detection import path as P
from planner.detection.algorithms import check_sampling, detect_features
from planner.detection.signals import default_scale, prepare_path
from planner.errors import InvalidParameter
from planner.geometry.envelope import offset_envelope
from planner.geometry.features import CurvatureFeature


def detect_multiscale(
    centers,
    tip_radius: float,
    radii: Sequence[float],
    *,
    smoothing_scale: float | None = None,
    material_side: str = "auto",
) -> dict[float, list[CurvatureFeature]]:
    """Re-detect curvature features for virtual fingertips of radius r_i >= r_f.

    The estimated surface (eq. 3.11 from the smoothed traced curve, with traced points of
    ``k_t > 1/r_f`` deleted, §3.3.3) is traced again by a circle of radius r_i (envelope of
    circles, :func:`planner.geometry.envelope.offset_envelope`), and algorithm 3 runs on that
    virtual traced curve with ``tip_radius = r_i``. Same-sign regions closer than ``r_i/2``
    are one feature at that scale (the end of the r_f fillet of an interference point can
    otherwise show as a weak extra convex region).

    Args:
        centers: (N, 2) or (N, 3) fingertip-centre positions [m].
        tip_radius: radius r_f of the real fingertip [m].
        radii: virtual radii r_i [m], each >= ``tip_radius``.
        smoothing_scale: smoothing of the real data [m] (default: 1.5 times the
            ``detect_features`` default: re-tracing the estimated surface amplifies noise).
        material_side: ``"auto"``, ``"right"`` or ``"left"``.

    Returns:
        ``{r_i: features}``; arclengths refer to the real fingertip-centre path [m] and
        positions to points of the estimated surface.

    Raises:
        InvalidParameter: a radius below ``tip_radius`` or not positive.
    """
    r = checks.positive("tip_radius", tip_radius, "m")
    c = checks.points("centers", centers, min_count=8)
    check_sampling(c, r)
    checks.choice("material_side", material_side, ("auto", "right", "left"))
    rs = [checks.positive("radii", ri, "m") for ri in radii]
    for ri in rs:
        if ri < r * (1 - 1e-12):
            raise InvalidParameter(
                f"radii: {ri!r} is smaller than tip_radius {r!r}; "
                f"only r_i >= r_f can be simulated (§3.2.2)"
            )
    scale = checks.positive("smoothing_scale", smoothing_scale or 1.5 * default_scale(c, r, 3), "m")
    prep = prepare_path(c, r, scale, material_side)
    o = prep.orientation
    kt = -o * P.signed_curvature(prep.dc, prep.ddc)
    keep = kt < 1.0 / r
    est = (prep.centers - r * prep.outward)[keep]
    nrm = prep.outward[keep]
    s_real = prep.s[keep]
    if o < 0:  # offset_envelope expects the material on the right of travel
        est, nrm, s_real = est[::-1], nrm[::-1], s_real[::-1]
    return {ri: _redetect(prep, est, nrm, s_real, ri, scale) for ri in rs}


def _redetect(prep, est, nrm, s_real, ri: float, scale: float) -> list[CurvatureFeature]:
    """Features a virtual fingertip of radius ``ri`` [m] sees on the estimated surface
    ``est`` (M, 2) [m] with outward normals ``nrm`` (M, 2), material on the right of travel;
    ``s_real`` (M,) their arclength on the real centre path [m]."""
    o = prep.orientation
    env = offset_envelope(est, nrm, ri, closed=False)
    pts = env.points[::-1] if o < 0 else env.points
    src = env.source[::-1] if o < 0 else env.source
    if pts.shape[0] < 8:
        return []
    ok = src >= 0
    s_path = P.arclength(pts)
    s_map = np.interp(np.arange(src.size), np.flatnonzero(ok), s_real[src[ok]])
    feats = detect_features(
        pts,
        ri,
        3,
        material_side="right" if o > 0 else "left",
        smoothing_scale=max(scale, default_scale(pts, ri, 3)),
        merge_gap=ri / 2,
    )
    res = []
    for f in feats:
        st, en, pk = np.interp([f.start, f.end, f.peak], s_path, s_map)
        res.append(
            CurvatureFeature(
                sign=f.sign,
                start=float(min(st, en)),
                end=float(max(st, en)),
                peak=float(pk),
                position=prep.frame.from_plane(np.asarray(f.position)[None, :2])[0],
                peak_curvature=f.peak_curvature,
                algorithm=3,
            )
        )
    return res


__all__ = ["detect_multiscale"]
