"""Tests of the 1-D curvature and macro features (thesis §3.2.2-3.2.3, Fig. 3.7)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from planner.errors import InvalidParameter
from planner.geometry.features import (
    classify_pattern,
    curvature_features_1d,
    group_features_1d,
    macro_features_1d,
)


def bump_k1(u, a):
    """Eq. 3.17, K11: principal curvature of the bump profile (convex positive)."""
    d = 1 + a * u**2
    c = np.sqrt(1 + 4 * a**2 * u**2 / d**4)
    return 2 * a * d * (1 - 3 * a * u**2) / (c * (d**4 + 4 * a**2 * u**2))


def profile_curvature(u, a):
    """Curvature of the graph z = 1/(1+a u^2) from its derivatives: -h''/(1+h'^2)^1.5."""
    d = 1 + a * u**2
    h1 = -2 * a * u / d**2
    h2 = 2 * a * (3 * a * u**2 - 1) / d**3
    return -h2 / (1 + h1**2) ** 1.5


def test_eq_3_17_matches_profile_curvature():
    u = np.linspace(-1, 1, 101)
    np.testing.assert_allclose(bump_k1(u, 15.0), profile_curvature(u, 15.0), rtol=1e-12)


def test_fig_3_7_three_features_with_analytic_boundaries():
    a, rf = 15.0, 1.0
    u = np.linspace(-0.99, 0.99, 1001)
    feats = curvature_features_1d(u, bump_k1(u, a), rf)
    assert [f.sign for f in feats] == [-1, 1, -1]
    # analytic boundaries: roots of k1 = +-1/rf
    pos = brentq(lambda x: bump_k1(x, a) - 1 / rf, 0.0, 0.2)
    neg_in = brentq(lambda x: bump_k1(x, a) + 1 / rf, 0.2, 0.4)
    neg_out = brentq(lambda x: bump_k1(x, a) + 1 / rf, 0.5, 0.9)
    tol = 2e-4
    assert feats[1].start == pytest.approx(-pos, abs=tol)
    assert feats[1].end == pytest.approx(pos, abs=tol)
    assert feats[2].start == pytest.approx(neg_in, abs=tol)
    assert feats[2].end == pytest.approx(neg_out, abs=tol)
    assert feats[0].start == pytest.approx(-neg_out, abs=tol)
    assert feats[1].peak == pytest.approx(0.0, abs=2e-3)
    assert feats[1].peak_curvature == pytest.approx(2 * a, rel=1e-6)
    macros = macro_features_1d(feats, rf)
    assert len(macros) == 1
    assert macros[0].kind == "bump" and macros[0].pattern == "-+-"
    assert macros[0].start == feats[0].start and macros[0].end == feats[2].end


def test_bump_vs_ridge_with_k2():
    a, rf = 15.0, 1.0
    u = np.linspace(-0.99, 0.99, 801)
    feats = curvature_features_1d(u, bump_k1(u, a), rf)
    d = 1 + a * u**2
    k2_bump = 2 * a / (np.sqrt(1 + 4 * a**2 * u**2 / d**4) * d**2)  # eq. 3.17, K22
    assert macro_features_1d(feats, rf, s=u, k2=k2_bump)[0].kind == "bump"
    assert macro_features_1d(feats, rf, s=u, k2=np.zeros_like(u))[0].kind == "ridge"
    neg = curvature_features_1d(u, -bump_k1(u, a), rf)
    assert macro_features_1d(neg, rf)[0].kind == "pit"
    assert macro_features_1d(neg, rf, s=u, k2=-k2_bump)[0].kind == "pit"
    assert macro_features_1d(neg, rf, s=u, k2=0 * u)[0].kind == "ravine"


@pytest.mark.parametrize(
    ("signs", "kind"),
    [
        ((1,), "cusp"),
        ((-1,), "cusp"),
        ((-1, 1), "step"),
        ((1, -1), "step"),
        ((-1, 1, -1), "bump"),
        ((1, -1, 1), "pit"),
        ((1, 1), "unknown"),
        ((-1, 1, -1, 1), "unknown"),
    ],
)
def test_classify_pattern(signs, kind):
    assert classify_pattern(signs) == kind


def test_grouping_uses_tip_radius():
    s = np.linspace(0, 10, 2001)
    k = np.zeros_like(s)
    k[(s > 2) & (s < 2.5)] = 5.0
    k[(s > 3.0) & (s < 3.5)] = -5.0  # gap 0.5 after the first
    k[(s > 6.0) & (s < 6.5)] = 5.0  # gap 2.5
    feats = curvature_features_1d(s, k, 0.6)
    assert [len(g) for g in group_features_1d(feats, 0.6)] == [2, 1]
    assert [m.kind for m in macro_features_1d(feats, 0.6)] == ["step", "cusp"]
    assert [len(g) for g in group_features_1d(feats, 0.4)] == [1, 1, 1]


def test_open_features_at_the_ends_and_threshold_is_strict():
    s = np.linspace(0, 1, 11)
    k = np.where(s < 0.35, 3.0, 0.0)
    (f,) = curvature_features_1d(s, k, 0.5)
    assert f.open_start and not f.open_end and f.start == 0.0
    assert curvature_features_1d(s, np.full_like(s, 2.0), 0.5) == []


@settings(max_examples=40, deadline=None)
@given(
    c=st.floats(0.1, 0.9),
    w=st.floats(0.02, 0.08),
    amp=st.floats(2.0, 50.0),
    sign=st.sampled_from([-1, 1]),
)
def test_linear_crossings_are_exact_for_a_tent(c, w, amp, sign):
    # a tent-shaped curvature signal is piecewise linear: interpolated crossings are exact
    s = np.unique(np.concatenate([np.linspace(0, 1, 157), [c]]))
    k = sign * amp * np.clip(1 - np.abs(s - c) / w, 0, None)
    rf = 2.0 / amp  # threshold at half height
    (f,) = curvature_features_1d(s, k, rf)
    assert f.sign == sign
    assert f.start == pytest.approx(c - w / 2, abs=1e-9)
    assert f.end == pytest.approx(c + w / 2, abs=1e-9)
    assert f.peak == pytest.approx(c)
    assert f.peak_curvature == pytest.approx(sign * amp)


@pytest.mark.parametrize(
    ("args", "match"),
    [
        ((np.arange(3.0), np.zeros(4), 1.0), "k: expected 3 samples"),
        ((np.zeros((2, 2)), np.zeros((2, 2)), 1.0), "1-D"),
        ((np.array([0.0, 1.0, 1.0]), np.zeros(3), 1.0), "strictly increasing"),
        ((np.arange(3.0), np.array([0, np.nan, 0]), 1.0), "finite"),
        ((np.arange(3.0), np.zeros(3), 0.0), "tip_radius"),
        ((np.arange(3.0), np.zeros(3), -1.0), "tip_radius"),
        ((np.arange(1.0), np.zeros(1), 1.0), "at least 2"),
    ],
)
def test_bad_input(args, match):
    with pytest.raises(InvalidParameter, match=match):
        curvature_features_1d(*args)


def test_macro_k2_needs_s():
    with pytest.raises(InvalidParameter, match="both s and k2"):
        macro_features_1d([], 1.0, k2=np.zeros(3))
