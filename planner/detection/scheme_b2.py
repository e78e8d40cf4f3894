"""The feature-detection scheme of App. B.2, used to rate smoothing filters.

Steps (thesis App. B.2): (1) the filtered x and y; (2) keep every n-th point;
(3) central differences ``x' = x(i+1) - x(i-1)``, ``x'' = x'(i+1) - x'(i-1)``;
(4) the *modified curvature* — the numerator of eq. (B.5), without its denominator;
(5) a light Gaussian smoothing of it; (6) thresholds; (7) positive and negative regions,
their ranges and maximum points.

Discrepancy: step 4 is printed ``k = x'y'' + y'x''`` while eq. (B.5) has
``x'y'' - y'x''``. Only the minus sign is a curvature (the plus form is not even invariant
under rotation: it is ``d(x'y')/dt``-like), so the minus sign is implemented.
Since ``x'y'' - y'x'' = k |c'|^3``, a curvature threshold ``k_thr`` [1/m] becomes
``k_thr * median(|c'|)^3`` for the modified curvature (data at constant speed).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import gaussian_filter1d

from planner import checks
from planner.detection.regions import threshold_regions
from planner.errors import InvalidParameter
from planner.geometry.features import CurvatureFeature


@dataclass(frozen=True, eq=False)
class SchemeResult:
    """Output of :func:`b2_scheme`.

    Attributes:
        features: detected regions; ``start/end/peak`` are in units of ``t`` (time [s], or
            sample index when no ``t`` was given); ``position`` is the (x, y) data point at
            the peak [m].
        t: (M,) time of each kept sample.
        modified: (M,) modified curvature (outward convention, convex > 0) [m^2 per
            sample^3 of the kept data].
        upper, lower: thresholds applied to ``modified``.
        curvature: (M,) ``modified / median(|c'|)^3``, an estimate of the curvature [1/m].
    """

    features: list[CurvatureFeature]
    t: np.ndarray
    modified: np.ndarray
    upper: float
    lower: float
    curvature: np.ndarray


def _central(v: np.ndarray) -> np.ndarray:
    d = np.empty_like(v)
    d[1:-1] = v[2:] - v[:-2]
    d[0], d[-1] = d[1], d[-2]
    return d


def b2_scheme(
    x,
    y,
    tip_radius: float,
    *,
    t=None,
    decimate: int = 1,
    sigma: float = 2.0,
    upper: float | None = None,
    lower: float | None = None,
    material_side: str = "right",
) -> SchemeResult:
    """Detect curvature features in filtered (x, y) data with the App. B.2 scheme.

    Args:
        x, y: (N,) filtered coordinates sampled at constant time intervals [m].
        tip_radius: fingertip radius r_f [m]; sets the default thresholds.
        t: (N,) time stamps [s] (default: the sample index).
        decimate: keep every ``decimate``-th sample (step 2).
        sigma: standard deviation of the Gaussian smoothing of the curvature (step 5)
            [kept samples]; 0 disables it.
        upper, lower: curvature thresholds [1/m] (default ``+-1/(2 r_f)``, the traced-curve
            thresholds of algorithm 3: the data of App. B are fingertip positions).
        material_side: side of the object relative to the direction of travel
            (``"right"``: an open profile traced in +x with material below).

    Returns:
        A :class:`SchemeResult`.
    """
    r = checks.positive("tip_radius", tip_radius, "m")
    xx = checks.series("x", x, min_count=8, unit="m")
    yy = checks.series("y", y, n=xx.size, unit="m")
    tt = (
        np.arange(xx.size, dtype=float) if t is None else checks.series("t", t, n=xx.size, unit="s")
    )
    decimate = checks.integer("decimate", decimate, minimum=1)
    sigma = checks.nonnegative("sigma", sigma, "samples")
    o = 1 if checks.choice("material_side", material_side, ("right", "left")) == "right" else -1
    xs, ys, ts = xx[::decimate], yy[::decimate], tt[::decimate]
    if xs.size < 5:
        raise InvalidParameter(f"decimate: only {xs.size} samples are left; expected >= 5")
    dx, dy = _central(xs), _central(ys)
    ddx, ddy = _central(dx), _central(dy)
    mod = -o * (dx * ddy - dy * ddx)
    if sigma > 0:
        mod = gaussian_filter1d(mod, sigma, mode="nearest")
    speed3 = float(np.median(np.hypot(dx, dy))) ** 3
    if speed3 <= 0:
        raise InvalidParameter("x, y: the path does not move")
    up = 1.0 / (2 * r) if upper is None else float(upper)
    lo = -1.0 / (2 * r) if lower is None else float(lower)
    if not up > 0 or not lo < 0:
        raise InvalidParameter(f"thresholds: expected upper > 0 > lower [1/m], got {up}, {lo}")
    regions = threshold_regions(mod, ts, up * speed3, lo * speed3)
    pts = np.column_stack([xs, ys])
    feats = [
        CurvatureFeature(
            sign=sg,
            start=float(ts[a]),
            end=float(ts[b]),
            peak=float(ts[p]),
            position=pts[p].copy(),
            peak_curvature=float(mod[p] / speed3),
            algorithm=0,
        )
        for sg, a, b, p in regions
    ]
    return SchemeResult(feats, ts, mod, up * speed3, lo * speed3, mod / speed3)


__all__ = ["SchemeResult", "b2_scheme"]
