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
