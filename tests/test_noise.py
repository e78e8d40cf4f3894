"""planner.detection.noise_analysis: App. B.1 chi-squared normality test."""

import numpy as np
import pytest
from scipy import stats

from planner.detection import noise_analysis
from planner.errors import InvalidParameter


def test_table_b1_style_result_on_gaussian_noise():
    rng = np.random.default_rng(0)
    t = np.arange(3000) * 2e-4
    x = 0.02 + 0.03 * t - 0.4 * t**2 + rng.normal(0, 9e-5, t.size)  # curved path, Fig. B.3
    res = noise_analysis(t, x)
    assert abs(res.mean) < 1e-12  # least-squares residual of a fit with a constant term
    assert res.sigma == pytest.approx(9e-5, rel=0.05)
    assert 4 <= res.bins <= 8 and res.dof == res.bins - 3  # outer bins merged if E < 5
    assert res.critical == pytest.approx(stats.chi2.ppf(0.95, res.dof))
    assert stats.chi2.ppf(0.95, 8 - 3) == pytest.approx(11.0705, abs=1e-3)  # App. B.1
    assert res.normal
    assert res.residual.shape == t.shape
    assert res.observed.sum() == t.size
    assert res.expected.sum() == pytest.approx(t.size)


def test_false_alarm_rate_near_the_confidence_level():
    rng = np.random.default_rng(1)
    t = np.linspace(0, 1, 1000)
    normal = [noise_analysis(t, rng.normal(0, 1e-4, t.size)).normal for _ in range(200)]
    assert 0.88 <= np.mean(normal) <= 0.995


def test_non_gaussian_noise_is_rejected():
    rng = np.random.default_rng(2)
    t = np.linspace(0, 1, 2000)
    assert not noise_analysis(t, rng.uniform(-1e-4, 1e-4, t.size)).normal
    assert not noise_analysis(t, rng.laplace(0, 1e-4, t.size)).normal


def test_statistic_matches_scipy_chisquare():
    rng = np.random.default_rng(3)
    t = np.linspace(0, 1, 500)
    res = noise_analysis(t, rng.normal(0, 1, t.size), bins=6)
    ref = stats.chisquare(res.observed, res.expected, ddof=2)
    assert res.chi2 == pytest.approx(ref.statistic)


def test_bad_inputs():
    t = np.linspace(0, 1, 100)
    with pytest.raises(InvalidParameter, match="strictly increasing"):
        noise_analysis(t[::-1], t)
    with pytest.raises(InvalidParameter, match="at least 20"):
        noise_analysis(t[:5], t[:5])
    with pytest.raises(InvalidParameter, match="100 samples"):
        noise_analysis(t, t[:50])
    with pytest.raises(InvalidParameter, match="constant"):
        noise_analysis(t, 3 * t**2 + 1)
    with pytest.raises(InvalidParameter, match="bins"):
        noise_analysis(t, np.sin(50 * t), bins=2)
    with pytest.raises(InvalidParameter, match="not finite"):
        noise_analysis(t, np.where(t > 0.5, np.nan, t))
