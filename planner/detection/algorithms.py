"""The four feature-detection algorithms of thesis Fig. 3.8 (§3.3.1-3.3.2).

All four threshold a curvature signal (outward convention, convex > 0) and map each region to
the estimated surface, eq. (3.11) ``s_e = s_t - r_f z_t``:

1. curvature of the estimated surface built from the tactile **contact points**,
   thresholds ``+-1/r_f`` (Definition 1). The sensor measures the contact relative to the
   fingertip, so that relative vector is what is smoothed (in time) before the fingertip
   pose is added back; across an interference point the smoothed contact then sweeps the
   r_f fillet, and concave features are missed, as §3.4.2 reports;
2. derivative of the **contact normal** angle with respect to arclength, thresholds
   ``+-1/r_f``. §3.3.1 says "arclength of the contact path", but the findings of §3.4.2
   (spikes at concave features, convex ones missed "because the normal direction does not
   change as quickly at those points") only hold for the arclength of the fingertip's own
   travel (time at constant speed): against the contact path the normal turns fastest over
   convex features, where the contact point dwells. The default ``normal_arclength="center"``
   follows the experiment; ``"contact"`` is the literal reading;
3. curvature ``k_t`` of the **traced curve** (fingertip-centre path). Under the fingertip the
   object curvature is ``k_obj = k_t / (1 - r_f k_t)``, so a convex feature
   ``k_obj > 1/r_f`` shows as ``k_t > 1/(2 r_f)``; a concave feature never shows as a smooth
   ``k_obj < -1/r_f`` but as an interference point, a corner of the traced curve whose
   smoothed curvature is strongly negative: thresholds ``+-1/(2 r_f)``;
4. estimated surface from the traced curve first (eq. 3.11, with the curvature limitation of
   §3.3.3: traced points with ``k_t >= 1/r_f`` are deleted), then its numeric curvature,
   thresholds ``+-1/r_f``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.detection import path as P
from planner.detection._validate import as_points, choice, positive
from planner.detection.regions import threshold_regions
from planner.detection.types import CurvatureFeature, CurvatureSignal
from planner.errors import InvalidParameter

ALGORITHMS = (1, 2, 3, 4)
SETTINGS = ("smoothing_scale", "material_side", "merge_gap", "upper", "lower", "normal_arclength")
#: default Gaussian smoothing scale as a fraction of the fingertip radius, per algorithm
SCALE_FRACTION = {1: 1 / 6, 2: 1 / 10, 3: 1 / 10, 4: 1 / 10}
_SAMPLES_PER_SCALE = 4.0


@dataclass(frozen=True, eq=False)
class _Prepared:
    frame: P.PlanarFrame
    centers: np.ndarray  # (M, 2) smoothed, decimated, in-plane
    dc: np.ndarray  # (M, 2) derivative w.r.t. decimated index
    ddc: np.ndarray
    block: int
    sigma: float  # Gaussian sigma [decimated samples]
    index: np.ndarray  # (M,) fractional input index of each sample
    s: np.ndarray  # (M,) arclength along the centre path [m]
    orientation: int  # +1: material on the right of travel; -1: on the left
    outward: np.ndarray  # (M, 2) outward unit normal of the traced curve
    spacing: float  # arclength between decimated samples [m]


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


def _check_settings(settings: dict) -> None:
    unknown = sorted(set(settings) - set(SETTINGS))
    if unknown:
        raise InvalidParameter(f"unknown setting(s) {unknown}; valid settings are {list(SETTINGS)}")


def _prepare(
    centers: np.ndarray,
    tip_radius: float,
    scale: float,
    side: str,
    hint: np.ndarray | None,
    measured_outward: np.ndarray | None,
) -> _Prepared:
    """Decimate (block means), smooth and differentiate the fingertip-centre path."""
    frame = P.planar_frame(centers, hint)
    uv = frame.to_plane(centers)
    h = P.median_spacing(uv)
    if h <= 0:
        raise InvalidParameter("centers: the fingertip does not move (all samples equal)")
    n = uv.shape[0]
    block = int(max(1, min(scale / _SAMPLES_PER_SCALE / h, n // 8)))
    dec, index = P.block_means(uv, block)
    sigma = scale / (h * block)
    cs, dc, ddc = P.gaussian_derivatives(dec, sigma)
    left = P.left_normals(dc)
    if side == "right":
        o = 1
    elif side == "left":
        o = -1
    elif measured_outward is not None:
        m, _ = P.block_means(frame.vectors_to_plane(measured_outward), block)
        o = 1 if float(np.sum(left * m)) >= 0 else -1
    elif centers.shape[1] == 3:
        o = 1 if float(left[:, 1].mean()) >= 0 else -1
    else:
        o = 1
    s = P.arclength(cs, start=h * (block - 1) / 2.0)
    return _Prepared(frame, cs, dc, ddc, block, sigma, index, s, o, o * left, h * block)


def curvature_signal(
    centers, tip_radius: float, algorithm: int = 3, normals=None, contacts=None, **settings
) -> CurvatureSignal:
    """The curvature signal one algorithm of Fig. 3.8 thresholds (see the module docstring).

    Args and settings: as :func:`detect_features`.

    Returns:
        A :class:`CurvatureSignal` with its thresholds.
    """
    _check_settings(settings)
    r = positive("tip_radius", tip_radius)
    choice("algorithm", algorithm, ALGORITHMS)
    c = as_points("centers", centers)
    n_pts, d = c.shape
    nrm = None if normals is None else as_points("normals", normals, n=n_pts, dims=(d,))
    con = None if contacts is None else as_points("contacts", contacts, n=n_pts, dims=(d,))
    if algorithm == 1 and con is None:
        raise InvalidParameter("algorithm 1 needs contacts: (N, D) tactile contact points [m]")
    if algorithm == 2 and nrm is None and con is None:
        raise InvalidParameter(
            "algorithm 2 needs normals (N, D) or contacts (N, D) to compute them with eq. (3.19)"
        )
    if nrm is not None:
        lens = np.linalg.norm(nrm, axis=1)
        if np.any(lens < 1e-9):
            raise InvalidParameter(
                f"normals: row {int(np.argmax(lens < 1e-9))} has zero "
                f"length; expected unit outward normals"
            )
        nrm = nrm / lens[:, None]
    elif con is not None:
        diff = c - con
        lens = np.linalg.norm(diff, axis=1)
        nrm = diff / np.maximum(lens, 1e-300)[:, None]  # eq. (3.19)
    scale = settings.get("smoothing_scale")
    scale = default_scale(c, r, algorithm, nrm, con) if scale is None else scale
    scale = positive("smoothing_scale", scale)
    side = choice("material_side", settings.get("material_side", "auto"), ("auto", "right", "left"))
    hint = None if nrm is None else nrm.mean(axis=0)
    prep = _prepare(c, r, scale, side, hint, nrm)
    o = prep.orientation
    if algorithm == 3:
        k = -o * P.signed_curvature(prep.dc, prep.ddc)
        surf = prep.centers - r * prep.outward  # eq. (3.11)
        upper, lower = 1.0 / (2 * r), -1.0 / (2 * r)
        s, idx, traced = prep.s, prep.index, prep.centers
    elif algorithm == 4:
        kt = -o * P.signed_curvature(prep.dc, prep.ddc)
        valid = kt < 1.0 / r  # curvature limitation, §3.3.3
        surf = (prep.centers - r * prep.outward)[valid]  # eq. (3.11)
        if surf.shape[0] < 3:
            raise InvalidParameter(
                "algorithm 4: fewer than 3 traced points survive the "
                "curvature limitation k_t < 1/r_f; the data are too noisy "
                "for this smoothing_scale"
            )
        k = -o * P.curvature_by_arclength(surf, prep.spacing)
        upper, lower = 1.0 / r, -1.0 / r
        s, idx, traced = prep.s[valid], prep.index[valid], prep.centers[valid]
    else:
        block = prep.block
        if con is not None:
            cp, _ = P.block_means(prep.frame.to_plane(con), block)
            cps, dcp, ddcp = P.gaussian_derivatives(cp, prep.sigma)
        nv, _ = P.block_means(prep.frame.vectors_to_plane(nrm), block)
        ns, _, _ = P.gaussian_derivatives(nv, prep.sigma)
        ns /= np.maximum(np.linalg.norm(ns, axis=1), 1e-300)[:, None]
        if algorithm == 1:
            # the tactile sensor measures the contact relative to the fingertip: smooth that
            # (the contact location on the sensor), then add the smoothed fingertip pose
            rel, _ = P.block_means(prep.frame.to_plane(con) - prep.frame.to_plane(c), block)
            rs, _, _ = P.gaussian_derivatives(rel, prep.sigma)
            mag, _, _ = P.gaussian_derivatives(np.linalg.norm(rel, axis=1)[:, None], prep.sigma)
            rs *= (mag[:, 0] / np.maximum(np.linalg.norm(rs, axis=1), 1e-300))[:, None]
            surf = prep.centers + rs
            k = -o * P.curvature_by_arclength(surf, prep.spacing)
        else:
            phi = np.unwrap(np.arctan2(ns[:, 1], ns[:, 0]))
            dphi = np.gradient(phi)
            along = choice(
                "normal_arclength",
                settings.get("normal_arclength", "center"),
                ("center", "contact"),
            )
            surf = cps if con is not None else prep.centers - r * ns
            if along == "center":
                dsurf = prep.dc
            elif con is not None:
                dsurf = dcp
            else:
                dsurf = np.gradient(surf, axis=0)
            ds = np.linalg.norm(dsurf, axis=1)
            ds = np.maximum(ds, 1e-3 * max(float(np.median(ds)), 1e-300))
            k = -o * dphi / ds
        upper, lower = 1.0 / r, -1.0 / r
        s, idx, traced = prep.s, prep.index, prep.centers
    if settings.get("upper") is not None:
        upper = float(settings["upper"])
    if settings.get("lower") is not None:
        lower = float(settings["lower"])
    if not upper > 0 or not lower < 0:
        raise InvalidParameter(
            f"thresholds: expected upper > 0 > lower [1/m], got upper={upper!r}, lower={lower!r}"
        )
    return CurvatureSignal(
        algorithm=algorithm,
        s=s,
        curvature=k,
        upper=upper,
        lower=lower,
        surface=prep.frame.from_plane(surf),
        traced=prep.frame.from_plane(traced),
        index=idx,
        scale=scale,
    )


def _concave_position(sig: CurvatureSignal, p: int, tip_radius: float) -> np.ndarray:
    """Where a concave feature found at an interference point (a corner of the traced curve)
    most likely is: the true corner lies in the unobservable region between the two contacts
    ``a`` (before) and ``b`` (after), ``a = c - r_f n_a`` (eq. 3.11) just outside the smoothed
    corner. If both sides are flat, the corner is where their tangent lines meet (exact for a
    V-groove); if both are convex (a bridged pit), the fillet point under the interference
    point (eq. 3.11), the deepest point reached; otherwise the contact on the more convex
    side (a wire, the top edge of a step) is projected onto the tangent line of the flatter
    side (exact for a step)."""
    m = max(2, int(np.ceil(3 * sig.scale / max(np.median(np.diff(sig.s)), 1e-300))))
    n = sig.s.size
    i, j = max(p - m, 0), min(p + m, n - 1)
    if i == p or j == p:
        return sig.surface[p].copy()
    a3, b3 = sig.surface[i], sig.surface[j]
    na3 = sig.traced[i] - a3
    # a 2-D basis of the plane of the two contacts and the normal (identity for 2-D data)
    e1 = b3 - a3
    if np.linalg.norm(e1) < 1e-12 * tip_radius:
        return sig.surface[p].copy()
    e1 = e1 / np.linalg.norm(e1)
    e2 = na3 - (na3 @ e1) * e1
    if np.linalg.norm(e2) < 1e-9 * tip_radius:
        return sig.surface[p].copy()
    e2 = e2 / np.linalg.norm(e2)
    basis = np.vstack([e1, e2])
    a, b = np.zeros(2), basis @ (b3 - a3)
    na = basis @ (sig.traced[i] - a3) / tip_radius
    nb = basis @ (sig.traced[j] - b3) / tip_radius
    ka, kb = sig.curvature[i], sig.curvature[j]
    if min(ka, kb) >= 1.0 / (4 * tip_radius):
        # convex on both sides (the fingertip bridges a pit or a narrow groove): nothing of
        # the inside was touched; the deepest point the fingertip reached is the best bound
        return sig.surface[p].copy()
    if max(ka, kb) < 1.0 / (4 * tip_radius):
        mat = np.array([na, nb])
        if abs(np.linalg.det(mat)) < 1e-6:
            x = 0.5 * (a + b)
        else:
            x = np.linalg.solve(mat, np.array([na @ a, nb @ b]))
    elif kb > ka:
        x = b - ((b - a) @ na) * na
    else:
        x = a - ((a - b) @ nb) * nb
    return a3 + x @ basis


def features_from_signal(
    sig: CurvatureSignal, merge_gap: float = 0.0, tip_radius: float | None = None
) -> list[CurvatureFeature]:
    """Threshold a :class:`CurvatureSignal` into curvature features (App. B.2 steps 6-7).

    With ``tip_radius`` and an algorithm-2 or -3 signal, concave features are placed
    in the unobservable region of their interference point (see ``_concave_position``)
    instead of on the fillet of the estimated surface.
    """
    regions = threshold_regions(sig.curvature, sig.s, sig.upper, sig.lower, merge_gap)
    out = []
    for sign, a, b, p in regions:
        pos = sig.surface[p].copy()
        if sign < 0 and tip_radius is not None and sig.algorithm in (2, 3):
            pos = _concave_position(sig, p, tip_radius)
        out.append(
            CurvatureFeature(
                sign=sign,
                start=float(sig.s[a]),
                end=float(sig.s[b]),
                peak=float(sig.s[p]),
                position=pos,
                peak_curvature=float(sig.curvature[p]),
                algorithm=sig.algorithm,
            )
        )
    return out


def detect_features(
    centers, tip_radius: float, algorithm: int = 3, normals=None, contacts=None, **settings
) -> list[CurvatureFeature]:
    """Detect curvature features (Definition 1) in fingertip data with one algorithm of
    thesis Fig. 3.8.

    The fingertip-centre path is decimated by block means, smoothed with a Gaussian of
    standard deviation ``smoothing_scale`` (in arclength) and differentiated (Gaussian
    derivatives); curvature is eq. (B.5); regions beyond the thresholds are features.
    The defaults work on data at the thesis' noise level (centre noise ~0.1-0.2 mm, contact
    noise ~0.25-0.5 mm) without tuning.

    Args:
        centers: (N, 2) or (N, 3) fingertip-centre positions in time order [m].
        tip_radius: fingertip radius r_f [m].
        algorithm: 1, 2, 3 or 4 (thesis Fig. 3.8; see the module docstring). Default 3.
        normals: (N, D) measured outward contact normals (unit), or ``None``.
        contacts: (N, D) measured contact points [m], or ``None``.
        **settings:
            smoothing_scale: Gaussian smoothing scale along the path [m] (default: chosen
                from the noise estimated in the data, :func:`default_scale`; about
                ``tip_radius/10`` at the thesis' noise level).
            material_side: ``"auto"`` (default: from normals/contacts when given; else the
                object is on the right of the direction of travel, as for an open profile
                traced in +x with material below; for 3-D data without normals, below in
                world z), ``"right"`` or ``"left"``.
            merge_gap: same-sign regions closer than this are merged [m]
                (default ``smoothing_scale``: noise dips inside one feature).
            upper, lower: override the convex/concave thresholds of the signal [1/m].
            normal_arclength: algorithm 2 only: differentiate the normal with respect to the
                arclength of the fingertip-centre path (``"center"``, default) or of the
                contact path (``"contact"``).

    Returns:
        Curvature features in path order, each with ``.sign``, ``.start``, ``.end``,
        ``.peak`` (arclength along the centre path from its first sample [m]) and
        ``.position`` (point on the estimated surface, same dimension as ``centers`` [m]).

    Raises:
        InvalidParameter: bad shapes, non-finite values, unknown algorithm or setting, or a
            missing input the algorithm needs.
    """
    sig = curvature_signal(centers, tip_radius, algorithm, normals, contacts, **settings)
    gap = settings.get("merge_gap")
    gap = sig.scale if gap is None else float(gap)
    return features_from_signal(sig, gap, float(tip_radius))


__all__ = ["ALGORITHMS", "curvature_signal", "detect_features", "features_from_signal"]
