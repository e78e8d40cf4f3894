"""Noise analysis of App. B.1: detrend a feature-free stretch, test the residual for
normality with a chi-squared goodness-of-fit test (Table B.1)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter


@dataclass(frozen=True, eq=False)
class NoiseAnalysis:
    """Result of :func:`noise_analysis` (one row of thesis Table B.1).

    Attributes:
        mean: mean of the residual noise [units of x].
        sigma: sample standard deviation of the noise [units of x].
        chi2: chi-squared statistic of the binned residual against a normal distribution.
        critical: critical value of chi2 at the chosen confidence.
        normal: ``chi2 <= critical`` (normality not rejected).
        dof: degrees of freedom (bins after merging - 3: the count, mean and sigma are fitted).
        bins: number of bins used (after merging bins with expected count < 5).
        confidence: confidence level of the test (0.95 in the thesis).
        residual: (N,) the noise: data minus the fitted second-order polynomial in t.
        observed, expected: (bins,) counts per bin.
    """

    mean: float
    sigma: float
    chi2: float
    critical: float
    normal: bool
    dof: int
    bins: int
    confidence: float
    residual: np.ndarray
    observed: np.ndarray
    expected: np.ndarray


def _merge_small(
    obs: np.ndarray, exp: np.ndarray, minimum: float = 5.0
) -> tuple[np.ndarray, np.ndarray]:
    """Merge neighbouring bins, left to right, until every expected count is >= ``minimum``
    (a short remainder at the right end joins the last full bin)."""
    o_out: list[float] = []
    e_out: list[float] = []
    acc_o = acc_e = 0.0
    for o, e in zip(obs.tolist(), exp.tolist(), strict=True):
        acc_o += o
        acc_e += e
        if acc_e >= minimum:
            o_out.append(acc_o)
            e_out.append(acc_e)
            acc_o = acc_e = 0.0
    if acc_e > 0 or acc_o > 0:
        if e_out:
            o_out[-1] += acc_o
            e_out[-1] += acc_e
        else:
            o_out.append(acc_o)
            e_out.append(acc_e)
    return np.array(o_out), np.array(e_out)


def noise_analysis(t, x, bins: int = 8, confidence: float = 0.95, degree: int = 2) -> NoiseAnalysis:
    """Is the noise of a feature-free stretch of fingertip data Gaussian? (App. B.1)

    Fits a polynomial of ``degree`` (2, as the thesis does after a linear fit left a skew,
    Fig. B.3-B.4) to ``x`` against ``t``, takes the residual as the noise, bins it into
    ``bins`` uniform bins between its minimum and maximum, and compares the observed counts
    with those of a normal distribution of the residual's mean and sigma (eq. B.3-B.4, via
    ``scipy.stats.norm.cdf``; the outer bins extend to +-infinity). Bins expected to hold
    fewer than 5 samples are merged with a neighbour. The statistic is compared with the
    ``confidence`` quantile of chi-squared with ``bins - 3`` degrees of freedom (with the
    default 8 bins: 11.07 at 95 %, the value quoted in App. B.1).

    Args:
        t: (N,) time stamps [s], strictly increasing.
        x: (N,) one coordinate of the data [m] (run it once for x and once for y).
        bins: number of histogram bins (>= 4).
        confidence: confidence level in (0, 1).
        degree: degree of the detrending polynomial (>= 0).

    Returns:
        A :class:`NoiseAnalysis`.

    Raises:
        InvalidParameter: bad shapes, fewer than 20 samples, non-finite or non-increasing
            t, constant x, or bad bins/confidence/degree.
    """
    tt = checks.series("t", t, min_count=20, unit="s")
    xx = checks.series("x", x, n=tt.size, min_count=20, unit="m")
    if np.any(np.diff(tt) <= 0):
        i = int(np.argmax(np.diff(tt) <= 0))
        raise InvalidParameter(
            f"t: must be strictly increasing; t[{i}]={tt[i]!r} >= t[{i + 1}]={tt[i + 1]!r}"
        )
    if isinstance(bins, bool) or not isinstance(bins, (int, np.integer)) or bins < 4:
        raise InvalidParameter(f"bins: expected an integer >= 4, got {bins!r}")
    if not 0 < confidence < 1:
        raise InvalidParameter(f"confidence: expected a value in (0, 1), got {confidence!r}")
    if isinstance(degree, bool) or not isinstance(degree, (int, np.integer)) or degree < 0:
        raise InvalidParameter(f"degree: expected an integer >= 0, got {degree!r}")
    u = (tt - tt.mean()) / (np.ptp(tt) / 2)
    coef = np.polynomial.polynomial.polyfit(u, xx, degree)
    res = xx - np.polynomial.polynomial.polyval(u, coef)
    mean, sigma = float(res.mean()), float(res.std(ddof=1))
    if not sigma > 1e-10 * float(np.max(np.abs(xx))):
        raise InvalidParameter(
            "x: the residual after detrending is constant; there is no noise to analyse"
        )
    edges = np.linspace(res.min(), res.max(), bins + 1)
    obs, _ = np.histogram(res, edges)
    from scipy import stats  # heavy: loaded on first use only

    cdf = stats.norm.cdf((edges - mean) / sigma)  # eq. (B.3)-(B.4)
    cdf[0], cdf[-1] = 0.0, 1.0
    exp = res.size * np.diff(cdf)
    obs_m, exp_m = _merge_small(obs, exp)
    dof = max(1, obs_m.size - 3)
    chi2 = float(np.sum((obs_m - exp_m) ** 2 / exp_m))
    critical = float(stats.chi2.ppf(confidence, dof))
    return NoiseAnalysis(
        mean=mean,
        sigma=sigma,
        chi2=chi2,
        critical=critical,
        normal=bool(chi2 <= critical),
        dof=dof,
        bins=int(obs_m.size),
        confidence=float(confidence),
        residual=res,
        observed=obs_m,
        expected=exp_m,
    )


__all__ = ["NoiseAnalysis", "noise_analysis"]
