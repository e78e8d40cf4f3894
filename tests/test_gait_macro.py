"""Macro features of the sensed outline (planar.macro): isolation, suspect passes, locality."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from planner.exploration.planar import macro
from planner.exploration.planar.macro import (
    MACRO_HEIGHT,
    MACRO_MERGE,
    NOISE_SIGMAS,
    PAD_PASS,
    SUSPECT_WEIGHT,
    height_threshold,
    isolated,
    macro_regions,
    pass_regions,
    suspect_passes,
)

A = np.linspace(0.2, 1.8, 640)  # one pass's polar angles [rad], 0.15 deg apart


def bumps(centres, height=3e-3, half_width=0.04, noise=1e-4, seed=0):
    """Heights over A [m]: 3 mm plateaus at ``centres`` [rad] plus white noise."""
    h = np.zeros(A.size)
    for c in centres:
        h[np.abs(A - c) < half_width] = height
    return h + np.random.default_rng(seed).normal(0.0, noise, A.size)


def test_isolated_drops_same_sign_neighbours_only():
    near = math.radians(8.0)
    regions = [(1.0, 1), (1.0 + near, 1), (1.0 + near / 2, -1), (2.5, 1)]
    # the two ridges 8 deg apart go; the groove between them and the far ridge stay
    assert isolated(regions) == [(1.0 + near / 2, -1), (2.5, 1)]
    apart = [(0.5, 1), (0.5 + MACRO_MERGE * 1.01, 1)]
    assert isolated(apart) == apart
    # across +-pi
    assert isolated([(math.pi - 0.01, -1), (-math.pi + 0.01, -1)]) == []


def test_a_wandering_pass_adds_no_feature():
    # pass 0: three grooves 6 deg apart (the estimate wandering); pass 1: one groove at 1.0
    wander = bumps([0.9, 1.0, 1.1], height=-2e-3, half_width=0.02)
    one = bumps([1.0], height=-2e-3)
    a, h = np.r_[A, A], np.r_[wander, one]
    p = np.r_[np.zeros(A.size), np.ones(A.size)].astype(int)
    assert [q for _, _, q in pass_regions(a, h, p)] == [1]
    assert macro_regions(a, h, p) == []  # one pass only: no feature
    # two clean passes: the groove, at its place
    found = macro_regions(np.r_[A, A], np.r_[one, bumps([1.0], -2e-3, seed=1)], p)
    assert len(found) == 1 and found[0][1] == -1 and abs(found[0][0] - 1.0) < math.radians(0.5)


def test_a_pad_pass_lifted_as_a_whole_is_no_feature():
    # the estimate 3 mm off over the whole pass (a ridge under the palm or the holder)
    lifted = np.full(A.size, 3e-3)
    p = np.r_[np.zeros(A.size), np.ones(A.size)].astype(int)
    assert macro_regions(np.r_[A, A], np.r_[lifted, lifted], p + PAD_PASS) == []
    # the round tip's passes are exempt (riding over a ridge lifts most of a short pass)
    assert len(macro_regions(np.r_[A, A], np.r_[lifted, lifted], p)) == 1


def test_suspect_passes_are_the_neighbours_of_excluded_rows():
    # passes: 0 kind 1, 1 kind 2 (tip), 2 excluded, 3 kind 3 (pad), 4 kind 1, 5 kind 3,
    # 6 excluded (the last)
    kind = np.array([1, 1, 2, 2, 0, 0, 3, 3, 1, 3, 3, 0])
    assert suspect_passes({"kind": kind}) == {1, 3 + PAD_PASS, 5 + PAD_PASS}
    assert suspect_passes({"kind": np.array([1, 2, 3, 1])}) == frozenset()
    assert suspect_passes({"kind": np.array([])}) == frozenset()


def test_suspect_passes_weigh_half():
    a = np.r_[A, A, A]
    h = np.r_[bumps([1.0], seed=0), bumps([1.0], seed=1), bumps([1.1], seed=2)]
    p = np.repeat([0, 1, 2], A.size)
    both = {0, 1}
    assert SUSPECT_WEIGHT * 2 < 2  # two suspect passes are not enough on their own
    assert macro_regions(a[: 2 * A.size], h[: 2 * A.size], p[: 2 * A.size], both) == []
    # with a sound third pass (weight 1 + 0.5 + 0.5): found, pulled to the sound one's 1.1
    # by the weighted median (the suspect ones' 1.0 weigh half)
    found = macro_regions(a, h, p, both)
    assert len(found) == 1 and abs(found[0][0] - 1.05) < math.radians(0.5)
    plain = macro_regions(a, h, p)
    assert len(plain) == 1 and abs(plain[0][0] - 1.0) < math.radians(0.5)


@given(st.floats(-math.pi, math.pi), st.integers(2, 4))
def test_one_ridge_seen_by_several_passes_is_found_at_its_angle(centre, n):
    # the same 3 mm ridge in n passes, rotated anywhere on the circle
    a = np.remainder(np.tile(A - 1.0 + centre, n) + math.pi, 2 * math.pi) - math.pi
    h = np.concatenate([bumps([1.0], seed=k) for k in range(n)])
    p = np.repeat(np.arange(n), A.size)
    found = macro_regions(a, h, p)
    assert len(found) == 1 and found[0][1] == 1
    assert abs(math.remainder(found[0][0] - centre, 2 * math.pi)) < math.radians(0.5)


@given(st.floats(0.2e-3, 2e-3), st.integers(0, 2**16))
def test_height_threshold_is_three_sigmas_of_gaussian_scatter(sigma, seed):
    # N(0, sigma) heights: the robust scatter estimate is sigma (MAD x 1.4826) within a few
    # per cent at 20 000 samples; a 3 mm ridge on 5 % of them does not move it much
    h = np.random.default_rng(seed).normal(0.0, sigma, 20_000)
    expected = max(MACRO_HEIGHT, NOISE_SIGMAS * sigma)
    assert height_threshold(h) == pytest.approx(expected, rel=0.05)
    h[:1000] += 3e-3
    assert height_threshold(h) == pytest.approx(expected, rel=0.12)


def test_height_threshold_floor():
    assert height_threshold(np.array([])) == MACRO_HEIGHT
    assert height_threshold(np.full(50, 3e-3)) == MACRO_HEIGHT  # no scatter at all
    assert height_threshold(np.random.default_rng(0).normal(0, 1e-4, 500)) == MACRO_HEIGHT


#: sensed heights of two recorded runs (``explore_object``, 60 s, seed 0): the 11 x 10 cm
#: ellipse (``ellipse_gait``'s object, its circle model posed anew each phase) and
#: ``ball_with_ridge`` (seed 0, the ridge at 170 deg): ``{name}_angles`` [rad, float32],
#: ``{name}_heights`` [um, int16], ``{name}_passes`` (:func:`sensed_heights`' numbering)
RECORDED = Path(__file__).parent / "data" / "macro_heights.npz"


def _recorded(name):
    z = np.load(RECORDED)
    a = z[f"{name}_angles"].astype(float)
    return a, z[f"{name}_heights"] * 1e-6, z[f"{name}_passes"].astype(int)


def test_recorded_ellipse_has_no_phantom_and_the_ridge_ball_keeps_its_ridge(monkeypatch):
    a, h, p = _recorded("ellipse")
    pad = p >= PAD_PASS
    # the mis-posed model's scatter sets both fingers' thresholds above the 1 mm floor
    assert height_threshold(h[pad]) > 1.5 * MACRO_HEIGHT
    assert height_threshold(h[~pad]) > 1.5 * MACRO_HEIGHT
    assert macro_regions(a, h, p) == []
    a2, h2, p2 = _recorded("ridge_ball")
    assert height_threshold(h2[p2 >= PAD_PASS]) == MACRO_HEIGHT  # 0.1-0.2 mm scatter
    found = macro_regions(a2, h2, p2)
    assert [sign for _, sign in found] == [1]
    assert abs(math.remainder(found[0][0] - math.radians(170.0), 2 * math.pi)) < math.radians(5)
    # with the fixed 1 mm threshold of before, the ellipse had ridges and grooves
    monkeypatch.setattr(macro, "NOISE_SIGMAS", 0.0)
    assert len(macro_regions(a, h, p)) >= 3


def _trace(kind, cx, cy=None):
    kind = np.asarray(kind, float)
    cy = np.zeros(kind.size) if cy is None else np.asarray(cy, float)
    return {"kind": kind, "cx": np.asarray(cx, float), "cy": cy}


def test_held_still_keeps_the_phases_3_whose_centre_stayed():
    from planner.exploration.planar.metrics import held_still

    # phase 1 | phase 3 moving 3 mm | phase 2 | phase 3 moving 5 mm (the last row back home)
    kind = [1, 1, 3, 3, 3, 2, 2, 3, 3, 3]
    cx = [0, 0.01, 0.0, 0.003, 0.001, 0.0, 0.0, 0.0, 0.005, 0.0]
    first, second = [False] * 2 + [True] * 3 + [False] * 2, [True] * 3
    assert held_still(_trace(kind, cx), 0.004).tolist() == first + [False] * 3
    assert held_still(_trace(kind, cx), 0.006).tolist() == first + second
    # the motion is the distance in the plane, not along x alone
    assert not held_still(_trace([3, 3], [0, 0.003], [0, 0.003]), 0.004).any()
    assert held_still(_trace([], []), 0.004).size == 0


def test_macro_features_survive_a_run_without_a_sliding_pass():
    # only the round tip explores (two phase-2 passes over a 3 mm ridge at 1.0 rad, a phase 1
    # between them), the pad never slides: the curvature detector has nothing to look at,
    # and the ridge must still be reported
    from planner.exploration.planar.metrics import detect_pad_features
    from planner.geometry import shapes

    R, r, k = 0.05, 0.025, A.size
    ang = np.tile(A, 3)
    height = np.r_[bumps([1.0], noise=0.0), np.zeros(k), bumps([1.0], noise=0.0)]
    kind = np.repeat([2.0, 1.0, 2.0], k)
    out = np.column_stack([np.cos(ang), np.sin(ang)])  # outward normal of the ball
    tip_centre = (R + r + height)[:, None] * out
    m, zero = 3 * k, np.zeros(3 * k)
    trace = {
        "t": np.arange(m) * 0.002, "kind": kind, "theta": zero, "cx": zero, "cy": zero,
        "pRx": tip_centre[:, 0] - r * out[:, 0], "pRy": tip_centre[:, 1] - r * out[:, 1],
        "nRx": -out[:, 0], "nRy": -out[:, 1], "fnR": np.full(m, 0.3), "fnL": zero,
        "pad_touch": zero, "pLx": zero, "pLy": zero, "nLx": zero, "nLy": zero, "u": zero,
    }  # fmt: skip
    found = detect_pad_features(trace, shapes.circle(R), None, R, 0.3, r)
    assert [f.kind for f in found] == ["ridge"]
    assert abs(found[0].angle - 1.0) < math.radians(1.0)
