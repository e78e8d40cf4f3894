"""Feature detection with the four algorithms of thesis Fig. 3.8 (§3.3.1-3.3.2): the
curvature signal of one algorithm (:mod:`planner.detection.signals`) thresholded into
curvature features (Definition 1, App. B.2 steps 6-7)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from planner import checks
from planner.detection import path as P
from planner.detection import signals as S
from planner.detection.regions import threshold_regions
from planner.detection.settings import DetectionSettings
from planner.detection.types import CurvatureSignal
from planner.errors import InvalidParameter
from planner.geometry.features import CurvatureFeature

ALGORITHMS = (1, 2, 3, 4)
#: fewest fingertip-centre samples per tip radius of path (the smoothing needs several)
MIN_SAMPLES_PER_RADIUS = 5
#: largest plausible extent of a fingertip path [m]: larger than any object a fingertip
#: explores (a 60 mm trace passed in millimetres spans 60 "m"; shorter ones in millimetres
#: fail the samples-per-tip-radius check)
MAX_PATH_EXTENT_M = 10.0
MIN_SAMPLES = 8


def check_sampling(centers: np.ndarray, tip_radius: float) -> None:
    """Reject fingertip paths that cannot be what they claim: millimetres passed as metres,
    or samples too sparse for the tip radius (fewer than :data:`MIN_SAMPLES_PER_RADIUS` per
    r_f of travel).

    Args:
        centers: (N, D) checked fingertip centres [m].
        tip_radius: r_f [m].

    Raises:
        InvalidParameter: saying what looks wrong.
    """
    sub = centers[:: max(1, len(centers) // 100_000)]  # plenty for a plausibility check
    extent = float(np.max(sub.max(axis=0) - sub.min(axis=0)))
    h = P.median_spacing(centers)
    if extent > MAX_PATH_EXTENT_M:
        raise InvalidParameter(
            f"centers: expected a fingertip path in metres, got one spanning {extent:.4g} m "
            f"(looks like millimetres: divide by 1000)"
        )
    if h > tip_radius / MIN_SAMPLES_PER_RADIUS:
        per = tip_radius / h if h > 0 else float("inf")
        raise InvalidParameter(
            f"centers: expected at least {MIN_SAMPLES_PER_RADIUS} samples per tip radius "
            f"({tip_radius:g} m), got samples {h:.3g} m apart ({per:.2g} per tip radius); "
            f"sample faster, or check that centers and tip_radius are both in metres"
        )


#: algorithm -> its signal function (:mod:`planner.detection.signals`)
_SIGNALS = {
    1: lambda prep, c, nrm, con, r, cfg: S.contact_signal(prep, c, con, r),
    2: lambda prep, c, nrm, con, r, cfg: S.normal_signal(prep, nrm, con, r, cfg.normal_arclength),
    3: lambda prep, c, nrm, con, r, cfg: S.traced_signal(prep, r),
    4: lambda prep, c, nrm, con, r, cfg: S.estimated_signal(prep, r),
}


def _inputs(centers, tip_radius, algorithm, normals, contacts):
    """Checked ``(r, centers, normals, contacts)``; normals from contacts by eq. (3.19)."""
    r = checks.positive("tip_radius", tip_radius, "m")
    checks.choice("algorithm", algorithm, ALGORITHMS)
    c = checks.points("centers", centers, min_count=MIN_SAMPLES)
    n_pts, d = c.shape
    nrm = None if normals is None else checks.points("normals", normals, n=n_pts, dims=(d,))
    con = None if contacts is None else checks.points("contacts", contacts, n=n_pts, dims=(d,))
    if algorithm == 1 and con is None:
        raise InvalidParameter(
            "contacts: algorithm 1 needs (N, D) tactile contact points [m], got None"
        )
    if algorithm == 2 and nrm is None and con is None:
        raise InvalidParameter(
            "normals: algorithm 2 needs normals (N, D) or contacts (N, D) to compute them "
            "with eq. (3.19), got neither"
        )
    check_sampling(c, r)
    if nrm is not None:
        lens = np.linalg.norm(nrm, axis=1)
        if np.any(lens < 1e-9):
            i = int(np.argmax(lens < 1e-9))
            raise InvalidParameter(
                f"normals: expected unit outward normals, got row {i} of zero length"
            )
        nrm = nrm / lens[:, None]
    elif con is not None:
        diff = c - con
        nrm = diff / np.maximum(np.linalg.norm(diff, axis=1), 1e-300)[:, None]  # eq. (3.19)
    return r, c, nrm, con


def curvature_signal(
    centers,
    tip_radius: float,
    algorithm: int = 3,
    normals=None,
    contacts=None,
    settings: DetectionSettings | None = None,
    **overrides,
) -> CurvatureSignal:
    """The curvature signal one algorithm of Fig. 3.8 thresholds
    (:mod:`planner.detection.signals`).

    Args and settings: as :func:`detect_features`.

    Returns:
        A :class:`CurvatureSignal` with its thresholds.
    """
    cfg = DetectionSettings.of(settings, **overrides)
    r, c, nrm, con = _inputs(centers, tip_radius, algorithm, normals, contacts)
    scale = cfg.smoothing_scale
    scale = S.default_scale(c, r, algorithm, nrm, con) if scale is None else scale
    hint = None if nrm is None else nrm.mean(axis=0)
    prep = S.prepare_path(c, r, scale, cfg.material_side, hint, nrm)
    sig = _SIGNALS[algorithm](prep, c, nrm, con, r, cfg)
    upper = sig.upper if cfg.upper is None else float(cfg.upper)
    lower = sig.lower if cfg.lower is None else float(cfg.lower)
    return replace(sig, upper=upper, lower=lower, scale=float(scale))


def _concave_position(sig: CurvatureSignal, p: int, tip_radius: float, ds: float) -> np.ndarray:
    """Where a concave feature found at an interference point (a corner of the traced curve)
    most likely is: the true corner lies in the unobservable region between the two contacts
    ``a`` (before) and ``b`` (after), ``a = c - r_f n_a`` (eq. 3.11) just outside the smoothed
    corner. If both sides are flat, the corner is where their tangent lines meet (exact for a
    V-groove); if both are convex (a bridged pit), the fillet point under the interference
    point (eq. 3.11), the deepest point reached; otherwise the contact on the more convex
    side (a wire, the top edge of a step) is projected onto the tangent line of the flatter
    side (exact for a step)."""
    m = max(2, int(np.ceil(3 * sig.scale / max(ds, 1e-300))))
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
    ds = float(np.median(np.diff(sig.s))) if sig.s.size > 1 else 0.0  # once, not per feature
    out = []
    for sign, a, b, p in regions:
        pos = sig.surface[p].copy()
        if sign < 0 and tip_radius is not None and sig.algorithm in (2, 3):
            pos = _concave_position(sig, p, tip_radius, ds)
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
    centers,
    tip_radius: float,
    algorithm: int = 3,
    normals=None,
    contacts=None,
    settings: DetectionSettings | None = None,
    **overrides,
) -> list[CurvatureFeature]:
    """Detect curvature features (Definition 1) in fingertip data with one algorithm of
    thesis Fig. 3.8.

    The fingertip-centre path is decimated by block means, smoothed with a Gaussian of
    standard deviation ``smoothing_scale`` (in arclength) and differentiated (Gaussian
    derivatives); curvature is eq. (B.5); regions beyond the thresholds are features.
    The defaults work on data at the thesis' noise level (centre noise ~0.1-0.2 mm, contact
    noise ~0.25-0.5 mm) without tuning. The material side is read from the normals or
    contacts when given, else from the path itself, so a trace recorded in either direction
    gives the same features (arclengths mirrored).

    Args:
        centers: (N, 2) or (N, 3) fingertip-centre positions in time order [m]; at least
            :data:`MIN_SAMPLES_PER_RADIUS` samples per tip radius of travel.
        tip_radius: fingertip radius r_f [m].
        algorithm: 1, 2, 3 or 4 (thesis Fig. 3.8; :mod:`planner.detection.signals`).
        normals: (N, D) measured outward contact normals (unit), or ``None``.
        contacts: (N, D) measured contact points [m], or ``None``.
        settings: a :class:`DetectionSettings` (default: all defaults).
        **overrides: fields of :class:`DetectionSettings` to change, e.g.
            ``smoothing_scale=1e-3``, ``material_side="left"``.

    Returns:
        Curvature features in path order, each with ``.sign``, ``.start``, ``.end``,
        ``.peak`` (arclength along the centre path from its first sample [m]) and
        ``.position`` (point on the estimated surface, same dimension as ``centers`` [m]).

    Raises:
        InvalidParameter: bad shapes, non-finite values, an unknown algorithm or setting, a
            missing input the algorithm needs, millimetres passed as metres, or samples too
            sparse for the tip radius.
    """
    cfg = DetectionSettings.of(settings, **overrides)
    sig = curvature_signal(centers, tip_radius, algorithm, normals, contacts, cfg)
    gap = sig.scale if cfg.merge_gap is None else float(cfg.merge_gap)
    return features_from_signal(sig, gap, float(tip_radius))


__all__ = [
    "ALGORITHMS",
    "MIN_SAMPLES_PER_RADIUS",
    "check_sampling",
    "curvature_signal",
    "detect_features",
    "features_from_signal",
]
