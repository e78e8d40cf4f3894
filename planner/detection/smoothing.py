"""Noise-type smoothing filters of thesis §3.3.3 and App. B.3.

Every filter works on samples taken at constant time intervals and filters each coordinate
against time (App. B.1: "the convolution ... can be done separately along the x and y
directions with respect to t"). Ends are handled by point-reflection padding, which keeps
linear trends, so a filtered straight path stays straight up to its ends.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage, signal

from planner import checks
from planner.errors import InvalidParameter

FILTERS = ("none", "average", "median", "dual_point", "gaussian", "wiener")


def _check_window(window, method: str) -> int:
    """``window`` [samples] of the ``method`` filter as an int >= 1."""
    if isinstance(window, float) or not checks.integer("window", window, minimum=1):
        raise InvalidParameter(
            f"window: expected an integer >= 1 [samples] for the {method!r} filter, got {window!r}"
        )
    return int(window)


def _pad(x: np.ndarray, pad: int) -> tuple[np.ndarray, int]:
    pad = int(min(pad, x.shape[0] - 1))
    if pad <= 0:
        return x, 0
    head = 2 * x[:1] - x[pad:0:-1]
    tail = 2 * x[-1:] - x[-2 : -pad - 2 : -1]
    return np.concatenate([head, x, tail], axis=0), pad


def gaussian_kernel(window: int, sigma: float) -> np.ndarray:
    """Normalised Gaussian weights of ``window`` taps and standard deviation ``sigma``
    [samples] (App. B.3, "Gaussian filter")."""
    window = _check_window(window, "gaussian")
    sigma = checks.positive("sigma", sigma, "samples")
    u = np.arange(window) - (window - 1) / 2.0
    w = np.exp(-0.5 * (u / sigma) ** 2)
    return w / w.sum()


def _even_gaussian(window: int, sigma: float) -> np.ndarray:
    """A centred (window + 1)-tap Gaussian whose end taps are halved (an even window)."""
    sigma = checks.positive("sigma", sigma, "samples")
    u = np.arange(window + 1) - window / 2.0
    w = np.exp(-0.5 * (u / sigma) ** 2)
    w[0] *= 0.5
    w[-1] *= 0.5
    return w / w.sum()


def dual_point(points: np.ndarray, iterations: int = 1) -> np.ndarray:
    """Dual-point (corner-cutting) smoothing of a polyline (App. B.3).

    Each iteration replaces every segment by its 1/4 and 3/4 points (the end points are
    kept), so the vertex count roughly doubles.

    Args:
        points: (N, D) polyline vertices.
        iterations: number of passes k (>= 1); the cost is O(2^k N).

    Returns:
        (2^k N, D) array of smoothed vertices (each pass maps n to 2(n - 1) + 2).
    """
    iterations = _check_window(iterations, "dual_point")
    p = np.asarray(points, dtype=float)
    if p.ndim == 1:
        p = p[:, None]
    for _ in range(iterations):
        q = 0.75 * p[:-1] + 0.25 * p[1:]
        r = 0.25 * p[:-1] + 0.75 * p[1:]
        mid = np.empty((2 * q.shape[0], p.shape[1]))
        mid[0::2], mid[1::2] = q, r
        p = np.vstack([p[:1], mid, p[-1:]])
    return p


def smooth(x, method: str = "gaussian", window: int = 25, sigma: float | None = None) -> np.ndarray:
    """Filter a time series (each column against time).

    Args:
        x: (N,) or (N, D) samples taken at constant time intervals.
        method: one of ``"none"``, ``"average"`` (eq. B.6, uniform weights), ``"median"``,
            ``"dual_point"`` (``window`` = number of corner-cutting iterations, the result
            resampled back to N samples by index), ``"gaussian"`` (``window`` taps,
            standard deviation ``sigma``), ``"wiener"`` (``scipy.signal.wiener`` on the linearly
            detrended signal, noise power estimated from the data).
        window: filter length [samples]. Even windows are centred by using window + 1
            taps (the two end taps at half weight for average and Gaussian; median and
            Wiener round up to the next odd length).
        sigma: Gaussian standard deviation [samples]; default ``window / 4``.

    Returns:
        Array of the shape of ``x``.

    Raises:
        InvalidParameter: unknown method, bad window/sigma, or a non-finite input.
    """
    checks.choice("method", method, FILTERS)
    arr = np.asarray(x, dtype=float)
    if arr.ndim not in (1, 2) or arr.shape[0] < 2:
        raise InvalidParameter(
            f"x: expected (N,) or (N, D) samples with N >= 2, got shape {arr.shape}"
        )
    if not np.isfinite(arr).all():
        raise InvalidParameter("x: expected finite samples [m], got NaN or infinite values")
    if method == "none":
        return arr.copy()
    window = _check_window(window, method)
    one_d = arr.ndim == 1
    a = arr[:, None] if one_d else arr
    n = a.shape[0]
    if method == "dual_point":
        out = dual_point(a, window)
        idx = np.linspace(0, out.shape[0] - 1, n)
        res = np.column_stack(
            [np.interp(idx, np.arange(out.shape[0]), out[:, j]) for j in range(a.shape[1])]
        )
        return res[:, 0] if one_d else res
    ap, pad = _pad(a, window)
    odd = window + 1 - window % 2  # even windows get one more tap so they stay centred
    if method == "average":
        k = np.ones(odd)
        if odd != window:
            k[0] = k[-1] = 0.5
        res = ndimage.correlate1d(ap, k / k.sum(), axis=0, mode="nearest")
    elif method == "median":
        res = ndimage.median_filter(ap, size=(odd, 1), mode="nearest")
    elif method == "gaussian":
        sg = window / 4.0 if sigma is None else float(sigma)
        k = gaussian_kernel(window, sg) if odd == window else _even_gaussian(window, sg)
        res = ndimage.correlate1d(ap, k, axis=0, mode="nearest")
    else:  # wiener
        res = np.column_stack([_wiener(ap[:, j], odd) for j in range(ap.shape[1])])
    res = res[pad : pad + n]
    return res[:, 0] if one_d else res


def _wiener(x: np.ndarray, window: int) -> np.ndarray:
    """scipy's Wiener filter on a linearly detrended copy: it pads with zeros and estimates
    the noise power as the mean local variance, which a trend (a path along an inclined
    plane) would inflate until nothing is filtered."""
    if np.ptp(x) == 0:
        return x.copy()
    u = np.arange(x.size, dtype=float)
    coef = np.polyfit(u, x, 1)
    trend = np.polyval(coef, u)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = signal.wiener(x - trend, mysize=window)
    out = np.where(np.isfinite(out), out, x - trend)
    return out + trend


__all__ = ["FILTERS", "dual_point", "gaussian_kernel", "smooth"]
