"""Online detection's uncertain-curvature trigger and the DVMA's sample thinning."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.exploration.surface.modelling import THIN, feature_model, thin_samples
from planner.exploration.surface.online import TURN, uncertain_turn, window_samples
from planner.exploration.surface.program import OUTLINE_SHARE_OTHER, outline_rise

R = 0.008


@pytest.mark.parametrize("step_um", [10.0, 20.0, 30.0, 80.0])
def test_window_spans_its_length_of_path_when_quantized_samples_repeat(step_um):
    """A straight path at ``step_um`` per 1 kHz step, its positions quantized to 50 um (the
    encoders): below 50 um per step most samples repeat and the median step is 0 - the
    window must still hold ``window`` metres of path, sampled ``spacing`` apart."""
    u = np.round(np.arange(5000) * step_um * 1e-6 / 5e-5) * 5e-5
    uv = np.column_stack([u, np.zeros_like(u)])
    if step_um < 25:
        assert np.median(np.diff(u)) == 0.0  # what the old per-step estimate saw
    window, spacing = 6 * R, R / 100
    idx = window_samples(uv, window, spacing)
    assert idx[-1] == len(u) - 1
    assert np.all(np.diff(idx) > 0)
    # the positions only take quantized values: each mark of the path moves by up to one
    # quantum q to the next sample
    q = 5e-5
    span = u[-1] - u[idx[0]]
    assert abs(span - window) <= spacing + q + 1e-12
    gaps = np.diff(u[idx])
    assert gaps.min() > 0
    assert gaps.max() <= spacing + q + 1e-12
    assert len(idx) >= window / (spacing + q)  # (the per-step median gave ~3 samples)


def test_window_of_a_path_shorter_than_the_window_is_the_whole_path():
    uv = np.column_stack([np.linspace(0, 0.01, 501), np.zeros(501)])
    idx = window_samples(uv, 6 * R, R / 100)
    assert idx[0] == 0 and idx[-1] == 500
    assert np.diff(uv[idx, 0]).max() <= R / 100 + 1e-12


@pytest.mark.parametrize("slope", [0.1, 0.2, 0.35])
def test_turn_of_a_tent_is_twice_its_flank_angle(slope):
    s = np.linspace(0.0, 0.04, 4001)
    w = -slope * np.abs(s - 0.02)
    j, turn = uncertain_turn(s, w, 0.5 * R, 0.0)
    assert abs(s[j] - 0.02) < 0.25 * R
    # the heights are averaged over r/4 = R/8: at the apex that lowers the middle height by
    # slope R/32, i.e. both chords' slopes by 1/16
    assert turn == pytest.approx(2 * math.atan(slope * 15 / 16), rel=0.01)


def test_turn_threshold_from_the_definition_1_curvature_crossed_at_60_degrees():
    """A circle of curvature 1/(5 r_f) - the offset of the Definition 1 threshold seen at 60
    deg - turns the path by TURN over r_f/2 on each side; a flat plate with encoder steps
    by (almost) nothing; a pit's sign is negative."""
    s = np.linspace(0.012, 0.028, 1601)  # +-8 mm: the circle's slope stays below 0.2
    rho = 5 * R
    w = np.sqrt(rho**2 - (s - 0.02) ** 2)
    _, turn = uncertain_turn(s, w, 0.5 * R, 0.0)
    assert turn == pytest.approx(TURN, rel=0.05)
    s = np.linspace(0.0, 0.04, 4001)
    flat = np.round(np.random.default_rng(0).normal(0, 1e-5, s.size) / 5e-5) * 5e-5
    assert abs(uncertain_turn(s, flat, 0.5 * R, 0.0)[1]) < TURN / 4
    assert uncertain_turn(s, 0.3 * np.abs(s - 0.02), 0.5 * R, 0.0)[1] < -TURN  # a V: concave


def test_turn_waits_until_the_finger_has_left_the_point():
    s = np.linspace(0.0, 0.03, 3001)
    w = -0.3 * np.abs(s - 0.025)  # the crest 5 mm before the end of the path
    j, turn = uncertain_turn(s, w, 0.5 * R, 1.25 * R)
    assert s[j] <= s[-1] - 1.25 * R + 1e-9
    assert abs(turn) < 2 * math.atan(0.3) * 0.99
    assert uncertain_turn(s[:50], w[:50], 0.5 * R, 0.0) == (-1, 0.0)


def test_thinning_keeps_order_and_a_minimum_spacing():
    t = np.linspace(0, 4 * np.pi, 4000)  # two laps 20 um apart
    r = np.where(t < 2 * np.pi, 3e-3, 3.02e-3)
    P = np.column_stack([r * np.cos(t), r * np.sin(t)])
    Q = thin_samples(P)
    d = np.hypot(*(Q[:, None] - Q[None]).transpose(2, 0, 1))
    np.fill_diagonal(d, np.inf)
    assert d.min() > THIN
    assert len(Q) < 2 * math.pi * 3e-3 / THIN + 2
    idx = [int(np.flatnonzero((P == q).all(axis=1))[0]) for q in Q]
    assert idx == sorted(idx)


def test_two_overlapping_laps_of_a_stadium_keep_the_whole_axis():
    """Without thinning the interleaved laps break the DVMA into pieces."""
    t = np.linspace(0, 2 * np.pi, 1500, endpoint=False)
    a, b = 6e-3, 2.5e-3  # a stadium: half-length of the axis, radius

    def stadium(r):
        pts = []
        for x in np.linspace(-a, a, 600):
            pts.append((x, -r))
        for th in np.linspace(-np.pi / 2, np.pi / 2, 300):
            pts.append((a + r * np.cos(th), r * np.sin(th)))
        for x in np.linspace(a, -a, 600):
            pts.append((x, r))
        for th in np.linspace(np.pi / 2, 3 * np.pi / 2, 300):
            pts.append((-a + r * np.cos(th), r * np.sin(th)))
        return np.array(pts)

    del t
    laps = np.vstack([stadium(b), stadium(b + 3e-5)])
    sk = feature_model("ridge", [laps], True)
    assert sk is not None
    xs = sk.points[:, 0]
    assert xs.min() < -a + 1e-3 and xs.max() > a - 1e-3
    assert np.abs(sk.points[:, 1]).max() < 3e-4


def test_outline_level_share_by_kind():
    assert outline_rise("bump", 4e-3, 2.5e-4) == pytest.approx(2e-3)
    assert outline_rise("pit", -4e-3, 2.5e-4) == pytest.approx(OUTLINE_SHARE_OTHER * 4e-3)
    assert outline_rise("step", 1e-4, 2.5e-4) == 2.5e-4


def test_closed_skeleton_is_tried_at_several_thinnings():
    from planner.exploration.surface.modelling import THIN, THINNINGS

    assert min(THINNINGS) < THIN < max(THINNINGS)
    t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    rng = np.random.default_rng(3)
    circle = np.column_stack([3e-3 * np.cos(t), 3e-3 * np.sin(t)]) + rng.normal(0, 2e-5, (2000, 2))
    sk = feature_model("bump", [circle], True)
    assert np.hypot(*sk.points.mean(axis=0)) < 2e-4  # a bump's skeleton: its centre
