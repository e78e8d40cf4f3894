"""Search strategies of the explorer (thesis §4.2, §4.5.1): the random walk's legs."""

from __future__ import annotations

import itertools
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from planner.exploration.surface.strategies import MIN_LEG, random_walk

R = 0.008
DEFAULT = ((-0.02, 0.02), (-0.02, 0.02))
TINY = ((-0.005, 0.005), (-0.005, 0.005))  # usable box 2 mm x 2 mm
STRIP = ((-0.0045, 0.0045), (-0.02, 0.02))  # usable box 1 mm x 32 mm
NO_ROOM = ((-0.004, 0.004), (-0.004, 0.004))  # usable box collapses to a point


@pytest.mark.parametrize("region", [DEFAULT, TINY, STRIP, ((-0.03, 0.03), (-0.03, 0.03))])
def test_random_walk_legs_stay_in_box_and_are_never_short(region):
    """Legs of 1-2 x 4 r_f in a 32 mm box (the default region) used to end in an endless
    stream of zero-length legs; every leg is now inside the box and at least
    max(1 mm, min(step, box) / 4) long."""
    reg = np.array(region)
    margin, step = 0.5 * R, 4.0 * R
    lo, hi = reg[:, 0] + margin, reg[:, 1] - margin
    lo, hi = np.minimum(lo, reg.mean(axis=1)), np.maximum(hi, reg.mean(axis=1))
    room = float(np.max(hi - lo))
    shortest = max(MIN_LEG, 0.25 * min(step, room))
    walk = random_walk(reg, reg.mean(axis=1), np.random.default_rng(3), step, margin)
    legs = list(itertools.islice(walk, 3000))
    assert len(legs) == 3000
    for a, b in legs:
        assert np.all(b >= lo - 1e-12) and np.all(b <= hi + 1e-12)
        assert np.linalg.norm(b - a) >= shortest - 1e-12
        assert np.linalg.norm(b - a) <= 2.0 * step + 1e-12
    # consecutive legs join
    assert all(np.array_equal(p[1], q[0]) for p, q in zip(legs[:-1], legs[1:], strict=True))


def test_random_walk_without_room_yields_no_leg():
    reg = np.array(NO_ROOM)
    assert list(random_walk(reg, (0.0, 0.0), np.random.default_rng(0), 4 * R, 0.5 * R)) == []


def _run(code: str, timeout: float):
    try:
        return subprocess.run(
            [sys.executable, "-c", textwrap.dedent(code)],
            capture_output=True,
            text=True,
            timeout=timeout,
        )
    except subprocess.TimeoutExpired:
        return None


@pytest.mark.parametrize(
    ("region", "reason"),
    [(None, "duration reached"), (TINY, "duration reached"), (NO_ROOM, "exploration complete")],
)
def test_random_walk_run_terminates(region, reason):
    """explore_surface(strategy="random_walk") ends (in a subprocess: a hang fails, not hangs)."""
    proc = _run(
        f"""
        from planner.exploration import explore_surface
        from planner.sim.spatial.plate import Plate
        r = explore_surface(Plate(()), strategy="random_walk", region={region!r},
                            duration=0.5, seed=1)
        print(r.status, r.reason, sep="|")
        """,
        timeout=120,
    )
    assert proc is not None, "explore_surface(strategy='random_walk') hung"
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip().splitlines()[-1] == f"ok|{reason}"


def test_bug2_reaches_a_goal_inside_the_traced_features_known_area():
    """The goal lies 15 mm past a bump, inside its known area (the traced hull grown by
    1.5 r_f): Bug-2 leaves just past the traced outline and ends at the goal (it used to stop
    next to the bump and report 'exploration complete')."""
    from planner.exploration import explore_surface
    from planner.exploration.surface.program import GOAL_TOLERANCE
    from planner.sim.spatial.plate import Plate, PlateFeature

    plate = Plate((PlateFeature("bump", 0.002, 0.003, (0.0, 0.0015)),))
    goal = (0.015, -0.002)
    reg = ((-0.02, 0.02), (-0.012, 0.012))
    res = explore_surface(plate, region=reg, strategy="bug2", goal=goal, duration=40, speed=0.03)
    assert (res.status, res.reason) == ("ok", "exploration complete")
    assert [(f.kind, f.closed) for f in res.features] == [("bump", True)]
    assert np.linalg.norm(res.path[-1, :2] - goal) < GOAL_TOLERANCE
    assert not [e for e in res.events if e.kind == "goal_not_reached"]


class _Stopped:
    """The parts of ExplorerController that the goal check reads and writes."""

    def __init__(self, uv):
        self.est = type("Est", (), {"uv": np.asarray(uv, float)})()
        self.events, self.failed = [], None

    def event(self, kind, message, **data):
        self.events.append((kind, message, data))


@pytest.mark.parametrize(("uv", "failed"), [((0.0105, 0.0), True), ((0.0095, 0.0), False)])
def test_bug2_goal_check_fails_a_run_that_stops_short(uv, failed):
    from planner.exploration.surface.program import GOAL_TOLERANCE, _check_goal

    assert GOAL_TOLERANCE == 1e-3
    ex = _Stopped(uv)
    _check_goal(ex, (0.009, 0.0))
    if failed:  # 1.5 mm from the goal
        assert ex.failed == (
            "goal not reached: the fingertip stopped 1.5 mm from the goal [9.0, 0.0] mm "
            "(tolerance 1 mm)"
        )
        assert [e[0] for e in ex.events] == ["goal_not_reached"]
        assert ex.events[0][2]["gap"] == pytest.approx(1.5e-3)
    else:  # 0.5 mm from the goal
        assert ex.failed is None and ex.events == []
