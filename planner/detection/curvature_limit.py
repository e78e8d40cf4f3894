"""Smoothing using curvature limitations (thesis §3.3.3, §3.4.1, Fig. 3.9).

A fingertip of radius r_f cannot trace a path curving more than ``1/r_f`` (it rounds convex
corners), and the surface it estimates cannot curve below ``-1/r_f`` (it fillets concave
ones). So: delete traced points with ``k_t > 1/r_f``, smooth, estimate the surface as the
envelope of r_f circles (eq. 3.11 along the smoothed normals), delete estimated points with
``k_e < -1/r_f``, smooth.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.detection import path as P
from planner.detection.algorithms import check_sampling
from planner.detection.signals import default_scale, prepare_path


@dataclass(frozen=True, eq=False)
class CurvatureLimited:
    """Result of :func:`curvature_limit_smoothing`.

    Attributes:
        traced: (M, D) smoothed traced curve (fingertip centres) after deleting points with
            ``k_t > 1/r_f`` [m].
        traced_curvature: (M,) its curvature, outward convention [1/m].
        estimated: (K, D) smoothed estimated surface after deleting points with
            ``k_e < -1/r_f`` [m].
        estimated_curvature: (K,) its curvature [1/m].
        removed_traced: number of traced samples deleted by the first limitation.
        removed_estimated: number of estimated samples deleted by the second limitation.
    """

    traced: np.ndarray
    traced_curvature: np.ndarray
    estimated: np.ndarray
    estimated_curvature: np.ndarray
    removed_traced: int
    removed_estimated: int


def curvature_limit_smoothing(
    centers, tip_radius: float, *, smoothing_scale: float | None = None, material_side: str = "auto"
) -> CurvatureLimited:
    """Curvature-limit smoothing of a fingertip-centre path (§3.3.3).

    Args:
        centers: (N, 2) or (N, 3) fingertip-centre positions in time order [m].
        tip_radius: r_f [m].
        smoothing_scale: Gaussian smoothing scale along the path [m] (default: from the
            noise of the data, as ``detect_features``).
        material_side: ``"auto"``, ``"right"`` or ``"left"`` (see ``detect_features``).

    Returns:
        A :class:`CurvatureLimited`.
    """
    r = checks.positive("tip_radius", tip_radius, "m")
    c = checks.points("centers", centers, min_count=8)
    check_sampling(c, r)
    checks.choice("material_side", material_side, ("auto", "right", "left"))
    scale = checks.positive("smoothing_scale", smoothing_scale or default_scale(c, r, 3), "m")
    prep = prepare_path(c, r, scale, material_side)
    o = prep.orientation
    raw, _ = P.block_means(prep.frame.to_plane(c), prep.block)
    kt = -o * P.signed_curvature(prep.dc, prep.ddc)
    keep = kt <= 1.0 / r  # the fingertip centre cannot curve more than 1/r_f
    cs, dc, ddc = P.gaussian_derivatives(raw[keep], prep.sigma)
    kt2 = -o * P.signed_curvature(dc, ddc)
    nrm = o * P.left_normals(dc)
    est = cs - r * nrm  # eq. (3.11)
    ke = -o * P.curvature_by_arclength(est, prep.spacing)
    keep_e = ke >= -1.0 / r  # the estimated surface cannot curve below -1/r_f
    es, de2, dde2 = P.gaussian_derivatives(est[keep_e], 1.0)
    ke2 = -o * P.curvature_by_arclength(es, prep.spacing)
    return CurvatureLimited(
        traced=prep.frame.from_plane(cs),
        traced_curvature=kt2,
        estimated=prep.frame.from_plane(es),
        estimated_curvature=ke2,
        removed_traced=int((~keep).sum()),
        removed_estimated=int((~keep_e).sum()),
    )


__all__ = ["CurvatureLimited", "curvature_limit_smoothing"]
