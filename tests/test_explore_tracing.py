"""Boundary tracing helpers (thesis §4.4.2): the level servo's distance, loop closure and
coverage, the plate level next to a feature - on a stand-in explorer, no simulator."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from planner.exploration.surface.runtime import PHASE
from planner.exploration.surface.tracing import (
    HOLE,
    MIN_SLOPE,
    SETTLED_LATERAL,
    SMOOTH,
    Outline,
    _closing,
    _covered,
    _fill_holes,
    level_distance,
    plate_level,
)


def _ex(centres, phases, normal=(0.0, 0.0, 1.0)):
    centres = np.asarray(centres, float)
    rec = SimpleNamespace(centre=centres, phase=np.asarray(phases, np.int8), n=len(centres))
    est = SimpleNamespace(
        centre=centres[-1], normal=np.asarray(normal, float), uv=centres[-1, :2].copy()
    )
    return SimpleNamespace(rec=rec, est=est)


@pytest.mark.parametrize("slope", [0.1, 0.35, 1.0])
def test_level_distance_is_the_height_error_over_the_flank_slope(slope):
    """First order: a flank of slope tan(a) under the contact, a height error e -> e / tan(a)."""
    a = math.atan(slope)
    n = (-math.sin(a), 0.0, math.cos(a))  # outward normal of a flank rising along +u
    ex = _ex([[0.0, 0.0, 0.0081]], [PHASE["trace"]], n)
    out = Outline(level=0.0082, sigma=1.0, inward=np.array([1.0, 0.0]), rise=2.5e-4)
    err, dist = level_distance(ex, out)
    assert err == pytest.approx(1e-4)
    assert dist == pytest.approx(1e-4 / slope)
    sunken = Outline(level=0.0080, sigma=-1.0, inward=np.array([1.0, 0.0]), rise=2.5e-4)
    assert level_distance(ex, sunken)[1] == pytest.approx(1e-4 / slope)  # deeper: inwards
    flat = _ex([[0.0, 0.0, 0.0081]], [PHASE["trace"]])
    assert level_distance(flat, out)[1] == pytest.approx(1e-4 / MIN_SLOPE)


def test_loop_closes_past_the_closest_approach_to_the_first_sample():
    home = np.array([0.0, 0.0])
    near = None
    states = []
    for x in np.linspace(-2e-3, 2e-3, 81):  # passing home 0.1 mm to its side
        near = _closing(x, 1e-4, home, 8e-4, near)
        states.append(near)
        if near is not None and near < 0:
            break
    assert states[0] is None  # outside the zone
    assert states[-1] == -1.0
    assert np.hypot(x, 1e-4) > 1e-4 + 2e-4 - 1e-12  # closed only once past it (overlap)


def test_coverage_of_the_traced_path_by_kept_samples():
    t = np.linspace(0, 2 * np.pi, 2000)
    path = np.column_stack([5e-3 * np.cos(t), 5e-3 * np.sin(t), np.full_like(t, 8e-3)])
    ex = _ex(path, np.full(len(t), PHASE["trace"]))
    all_kept = list(range(len(t)))
    assert _covered(ex, all_kept, 0)
    hole = [k for k in all_kept if not 400 <= k <= 700]  # a quarter of the cap unsettled
    assert not _covered(ex, hole, 0)


def test_plate_level_from_the_far_end_of_the_across_crossing():
    """On a bump's tail the local height is off the plate; the across crossing's end on the
    finger's side reads the plate, the other end (a step's other level) is never used."""
    u = np.linspace(-0.02, 0.02, 400)
    w = 0.008 + 0.002 / (1 + (u / 0.004) ** 2)  # centre heights of a crossing over a bump
    across = np.column_stack([u, np.zeros_like(u), w])
    here = np.array([[0.01, 0.0, 0.008 + 0.002 / (1 + 2.5**2)]])
    ex = _ex(np.vstack([across, here]), [PHASE["across"]] * 400 + [PHASE["reapproach"]])
    local = float(here[0, 2])
    got = plate_level(ex, local, rise=5e-4)
    assert abs(got - 0.008) < abs(local - 0.008) / 2  # 0.09 mm instead of 0.28 mm off
    assert plate_level(ex, local, rise=5e-5) == local  # farther than rise: kept local
    no_across = _ex(here, [PHASE["reapproach"]])
    assert plate_level(no_across, local, rise=5e-4) == local


def test_plate_level_on_the_far_side_of_a_raised_or_sunken_feature():
    """The across crossing's end is still on a wide ridge's flank (higher than where the
    approach starts): for a raised feature the lower height is the plate, for a sunken one
    the higher; without a side (a step) the old rule keeps the end within ``rise``."""
    u = np.linspace(-0.02, 0.02, 400)
    w = 0.008 + 0.003 * np.exp(-(u**2) / (2 * 0.006**2))  # the end at 20 mm still 1.2 um up
    across = np.column_stack([u, np.zeros_like(u), w + 4e-4 * (np.abs(u) > 0.015)])
    here = np.array([[0.015, 0.0, 0.008 + 1e-5]])
    ex = _ex(np.vstack([across, here]), [PHASE["across"]] * 400 + [PHASE["reapproach"]])
    local = float(here[0, 2])
    assert plate_level(ex, local, rise=1e-3, sense=1) == local
    assert plate_level(ex, local, rise=1e-3, sense=0) > local + 3e-4
    assert plate_level(ex, local, rise=1e-3, sense=-1) > local + 3e-4


def test_holes_of_a_closed_outline_are_filled_with_runs_of_loose_samples():
    t = np.linspace(0, 2 * np.pi, 3000, endpoint=False)
    path = np.column_stack([5e-3 * np.cos(t), 5e-3 * np.sin(t), np.full_like(t, 8e-3)])
    ex = _ex(path, np.full(len(t), PHASE["trace"]))
    gap = set(range(1000, 1400))  # 4.2 mm of the outline not settled
    kept = [k for k in range(len(t)) if k not in gap]
    loose = sorted(gap)
    got = _fill_holes(ex, kept, loose)
    assert set(got) >= set(kept)
    assert _covered(ex, list(got), 0)
    # only the samples farther than HOLE + SETTLED_LATERAL from the kept ones are added
    added = np.setdiff1d(got, kept)
    d = np.min(np.hypot(*(path[added, None, :2] - path[None, kept, :2]).transpose(2, 0, 1)), 1)
    assert np.all(d > HOLE + SETTLED_LATERAL)
    # a stray sample (shorter than SMOOTH steps) is not a stretch of outline
    stray = list(range(1200, 1200 + SMOOTH // 2))
    assert np.array_equal(_fill_holes(ex, kept, stray), np.array(kept))
