"""The curvature signals the four detection algorithms of thesis Fig. 3.8 threshold
(§3.3.1-3.3.2), one function per algorithm.

All four use the outward convention (convex > 0) and map each sample to the estimated
surface, eq. (3.11) ``s_e = s_t - r_f z_t``:

1. curvature of the estimated surface built from the tactile **contact points**,
   thresholds ``±1/r_f`` (Definition 1). The sensor measures the contact relative to the
   fingertip, so that relative vector is what is smoothed (in time) before the fingertip
   pose is added back; across an interference point the smoothed contact then sweeps the
   r_f fillet, and concave features are missed, as §3.4.2 reports;
2. derivative of the **contact normal** angle with respect to arclength, thresholds
   ``±1/r_f``. §3.3.1 says "arclength of the contact path", but the findings of §3.4.2
   (spikes at concave features, convex ones missed "because the normal direction does not
   change as quickly at those points") only hold for the arclength of the fingertip's own
   travel (time at constant speed): against the contact path the normal turns fastest over
   convex features, where the contact point dwells. ``normal_arclength="center"`` (default)
   follows the experiment; ``"contact"`` is the literal reading;
3. curvature ``k_t`` of the **traced curve** (fingertip-centre path). Under the fingertip the
   object curvature is ``k_obj = k_t / (1 - r_f k_t)``, so a convex feature
   ``k_obj > 1/r_f`` shows as ``k_t > 1/(2 r_f)``; a concave feature never shows as a smooth
   ``k_obj < -1/r_f`` but as an interference point, a corner of the traced curve whose
   smoothed curvature is strongly negative: thresholds ``±1/(2 r_f)``;
4. estimated surface from the traced curve first (eq. 3.11, with the curvature limitation of
   §3.3.3: traced points with ``k_t >= 1/r_f`` are deleted), then its numeric curvature,
   thresholds ``±1/r_f``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.detection import path as P
from planner.detection.types import CurvatureSignal
from planner.errors import InvalidParameter

#: default Gaussian smoothing scale as a fraction of the fingertip radius, per algorithm
SCALE_FRACTION = {1: 1 / 6, 2: 1 / 10, 3: 1 / 10, 4: 1 / 10}
_SAMPLES_PER_SCALE = 4.0
#: turning [rad] beyond 1/r_f that counts as evidence of the material side of a path
SIDE_EVIDENCE = 0.003
#: the material side is the one with this many times less excess turning than the other
SIDE_RATIO = 3.0


@dataclass(frozen=True, eq=False)
class PreparedPath:
    """A fingertip-centre path decimated, smoothed and differentiated in its plane.

    Attributes:
        frame: the plane of the analysis.
        centers: (M, 2) smoothed, decimated, in-plane centres [m].
        dc: (M, 2) derivative with respect to the decimated index [m].
        ddc: (M, 2) second derivative [m].
        block: input samples per decimated sample.
        sigma: Gaussian sigma [decimated samples].
        index: (M,) fractional input index of each sample.
        s: (M,) arclength along the centre path [m].
        orientation: +1 material on the right of travel, -1 on the left.
        outward: (M, 2) outward unit normal of the traced curve.
        spacing: arclength between decimated samples [m].
    """

    frame: P.PlanarFrame
    centers: np.ndarray
    dc: np.ndarray
    ddc: np.ndarray
    block: int
    sigma: float
    index: np.ndarray
    s: np.ndarray
    orientation: int
    outward: np.ndarray
    spacing: float

    def traced_curvature(self) -> np.ndarray:
        """(M,) curvature of the smoothed traced curve, outward convention [1/m]."""
        return -self.orientation * P.signed_curvature(self.dc, self.ddc)


def default_scale(
    centers: np.ndarray,
    tip_radius: float,
    algorithm: int,
    normals: np.ndarray | None = None,
    contacts: np.ndarray | None = None,
) -> float:
    """Default smoothing scale [m] of an algorithm for these data.

    The noise of the input each algorithm differentiates (centres for 3-4, contacts for 1,
    the normal angle for 2) is estimated from the data (:func:`path.noise_sigma`) and the
    scale chosen so that the noise of the curvature signal stays a factor
    :data:`path.NOISE_MARGIN` below the threshold (:func:`path.auto_scale`), within
    ``[r_f/25, r_f/4]`` (``[r_f/10, r_f/4]`` for the tactile algorithms 1-2, whose data
    carry sensor artefacts that white noise does not model). At the thesis' noise (0.1 mm)
    and sampling this is about ``SCALE_FRACTION[algorithm] * r_f``.
    """
    r = tip_radius
    frame = P.planar_frame(centers, None if normals is None else normals.mean(axis=0))
    uv = frame.to_plane(centers)
    h = P.median_spacing(uv)
    lo, hi = (r / 10 if algorithm in (1, 2) else r / 25), r / 4
    if algorithm == 1 and contacts is not None:
        sig = P.noise_sigma(frame.to_plane(contacts))
        return P.auto_scale(sig, h, 1.0 / r, 2, lo, hi)
    if algorithm == 2 and normals is not None:
        nv = frame.vectors_to_plane(normals)
        phi = np.unwrap(np.arctan2(nv[:, 1], nv[:, 0]))
        return P.auto_scale(P.noise_sigma(phi), h, 1.0 / r, 1, lo, hi)
    return P.auto_scale(P.noise_sigma(uv), h, 1.0 / (2 * r), 2, lo, hi)


def infer_material_side(dc: np.ndarray, ddc: np.ndarray, tip_radius: float) -> int | None:
    """The side of travel where the object lies, read from a smoothed traced curve.

    A fingertip centre never curves toward the material more than ``1/r_f`` (it rolls on
    the object), while the corners of interference points bend it sharply away from the
    material. The side whose convex-curvature excess ``∫ max(k - 1/r_f, 0) ds`` (its
    turning beyond the fingertip's own, [rad]) is small is the material side.

    Args:
        dc, ddc: (M, 2) first and second derivatives of the path [m].
        tip_radius: r_f [m].

    Returns:
        +1 (material on the right of travel), -1 (left), or ``None`` when the path does not
        tell: less than :data:`SIDE_EVIDENCE` rad of excess on both sides, or excesses
        within a factor :data:`SIDE_RATIO`. At the thesis' noise (0.1 mm) that happens
        for features whose interference kinks are shallow (a wire well under 1 mm, a groove
        the fingertip bridges): pass normals or contacts, or ``material_side``, for those.
    """
    k_ccw = P.signed_curvature(dc, ddc)
    ds = np.hypot(dc[:, 0], dc[:, 1])
    thr = 1.0 / tip_radius
    if_right = float(np.sum(np.maximum(-k_ccw - thr, 0.0) * ds))  # convex if material right
    if_left = float(np.sum(np.maximum(k_ccw - thr, 0.0) * ds))
    if max(if_right, if_left) < SIDE_EVIDENCE:
        return None
    if SIDE_RATIO * min(if_right, if_left) > max(if_right, if_left):
        return None
    return 1 if if_right < if_left else -1


def _orientation(side, left, measured_outward, frame, block, dc, ddc, r, dims) -> int:
    if side == "right":
        return 1
    if side == "left":
        return -1
    if measured_outward is not None:
        m, _ = P.block_means(frame.vectors_to_plane(measured_outward), block)
        return 1 if float(np.sum(left * m)) >= 0 else -1
    inferred = infer_material_side(dc, ddc, r)
    if inferred is not None:
        return inferred
    if dims == 3:
        return 1 if float(left[:, 1].mean()) >= 0 else -1
    return 1


def prepare_path(
    centers: np.ndarray,
    tip_radius: float,
    scale: float,
    side: str,
    hint: np.ndarray | None = None,
    measured_outward: np.ndarray | None = None,
) -> PreparedPath:
    """Decimate (block means), smooth and differentiate the fingertip-centre path.

    Args:
        centers: (N, D) checked fingertip centres [m].
        tip_radius: r_f [m].
        scale: Gaussian smoothing scale along the path [m].
        side: ``"auto"``, ``"right"`` or ``"left"`` (see ``DetectionSettings``).
        hint: (D,) a vector pointing away from the object (3-D data), or ``None``.
        measured_outward: (N, D) measured outward normals, or ``None``.
    """
    frame = P.planar_frame(centers, hint)
    uv = frame.to_plane(centers)
    h = P.median_spacing(uv)
    if h <= 0:
        raise InvalidParameter("centers: expected a moving fingertip, got all samples equal [m]")
    n = uv.shape[0]
    block = int(max(1, min(scale / _SAMPLES_PER_SCALE / h, n // 8)))
    dec, index = P.block_means(uv, block)
    sigma = scale / (h * block)
    cs, dc, ddc = P.gaussian_derivatives(dec, sigma)
    left = P.left_normals(dc)
    o = _orientation(
        side, left, measured_outward, frame, block, dc, ddc, tip_radius, centers.shape[1]
    )
    s = P.arclength(cs, start=h * float(index[0]))  # from the first sample [m]
    return PreparedPath(frame, cs, dc, ddc, block, sigma, index, s, o, o * left, h * block)


def _signal(prep: PreparedPath, alg: int, k, surf, upper: float, valid=None) -> CurvatureSignal:
    sel = slice(None) if valid is None else valid
    return CurvatureSignal(
        algorithm=alg,
        s=prep.s[sel],
        curvature=k,
        upper=upper,
        lower=-upper,
        surface=prep.frame.from_plane(surf),
        traced=prep.frame.from_plane(prep.centers[sel]),
        index=prep.index[sel],
    )


def contact_signal(prep: PreparedPath, centers, contacts, tip_radius: float) -> CurvatureSignal:
    """Algorithm 1: curvature of the surface of the tactile contact points (module
    docstring); ``centers``, ``contacts`` (N, D) [m]."""
    fr, block = prep.frame, prep.block
    rel, _ = P.block_means(fr.to_plane(contacts) - fr.to_plane(centers), block)
    rs, _, _ = P.gaussian_derivatives(rel, prep.sigma)
    mag, _, _ = P.gaussian_derivatives(np.linalg.norm(rel, axis=1)[:, None], prep.sigma)
    rs *= (mag[:, 0] / np.maximum(np.linalg.norm(rs, axis=1), 1e-300))[:, None]
    surf = prep.centers + rs
    k = -prep.orientation * P.curvature_by_arclength(surf, prep.spacing)
    return _signal(prep, 1, k, surf, 1.0 / tip_radius)


def normal_signal(
    prep: PreparedPath, normals, contacts, tip_radius: float, along: str = "center"
) -> CurvatureSignal:
    """Algorithm 2: turning rate of the contact normal (module docstring); ``normals``
    (N, D) unit, ``contacts`` (N, D) [m] or ``None``."""
    fr, block = prep.frame, prep.block
    nv, _ = P.block_means(fr.vectors_to_plane(normals), block)
    ns, _, _ = P.gaussian_derivatives(nv, prep.sigma)
    ns /= np.maximum(np.linalg.norm(ns, axis=1), 1e-300)[:, None]
    phi = np.unwrap(np.arctan2(ns[:, 1], ns[:, 0]))
    if contacts is not None:
        cp, _ = P.block_means(fr.to_plane(contacts), block)
        surf, dcp, _ = P.gaussian_derivatives(cp, prep.sigma)
    else:
        surf = prep.centers - tip_radius * ns
        dcp = np.gradient(surf, axis=0)
    dsurf = prep.dc if along == "center" else dcp
    ds = np.linalg.norm(dsurf, axis=1)
    ds = np.maximum(ds, 1e-3 * max(float(np.median(ds)), 1e-300))
    k = -prep.orientation * np.gradient(phi) / ds
    return _signal(prep, 2, k, surf, 1.0 / tip_radius)


def traced_signal(prep: PreparedPath, tip_radius: float) -> CurvatureSignal:
    """Algorithm 3: curvature of the traced curve, thresholds ±1/(2 r_f) (module
    docstring)."""
    surf = prep.centers - tip_radius * prep.outward  # eq. (3.11)
    return _signal(prep, 3, prep.traced_curvature(), surf, 1.0 / (2 * tip_radius))


def estimated_signal(prep: PreparedPath, tip_radius: float) -> CurvatureSignal:
    """Algorithm 4: curvature of the estimated surface after the curvature limitation of
    §3.3.3 (module docstring)."""
    valid = prep.traced_curvature() < 1.0 / tip_radius
    surf = (prep.centers - tip_radius * prep.outward)[valid]  # eq. (3.11)
    if surf.shape[0] < 3:
        raise InvalidParameter(
            "smoothing_scale: algorithm 4 keeps fewer than 3 traced points after the "
            "curvature limitation k_t < 1/r_f; expected less noisy data or a larger scale"
        )
    k = -prep.orientation * P.curvature_by_arclength(surf, prep.spacing)
    return _signal(prep, 4, k, surf, 1.0 / tip_radius, valid)


__all__ = [
    "SCALE_FRACTION",
    "PreparedPath",
    "contact_signal",
    "default_scale",
    "estimated_signal",
    "infer_material_side",
    "normal_signal",
    "prepare_path",
    "traced_signal",
]
