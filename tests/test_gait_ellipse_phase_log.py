"""Per-phase diagnosis of an executed gait (planar/phase_log.py): on a circle the sensed
rotation and centre agree with the truth, and every contact stays inside its Coulomb cone."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from planner.exploration.planar.phase_log import PAIRS, _cones, _first_rows, phase_rows
from planner.geometry import shapes


@pytest.fixture(scope="module")
def circle_run():
    from planner.exploration.planar.machine import explore_object
    from robots.planar_hand import PlanarHand, gait_hand_params

    hand = PlanarHand(gait_hand_params())
    return explore_object(shapes.circle(0.05), hand=hand, mu=1.0, duration=3.0, seed=0)


def test_one_row_per_phase_with_the_records_values(circle_run):
    rows = phase_rows(circle_run)
    assert len(rows) == len(circle_run.phases) >= 3
    for row, rec in zip(rows, circle_run.phases, strict=True):
        assert (row.kind, row.skip, row.event) == (rec.phase, rec.skip, rec.event)
        assert row.rotation == rec.rotation and row.start == rec.start and row.end == rec.end
        assert rec.event in row.line()
    assert math.isnan(rows[-1].sensed_rotation)


def test_on_a_circle_the_estimate_matches_the_truth(circle_run):
    """The planner's model is exact on a circle: the rolling estimate (eq. 2.4) follows the
    true rotation and the pad-based centre is the true centre."""
    rows = phase_rows(circle_run)
    for row in rows[:-1]:
        assert row.sensed_rotation == pytest.approx(row.rotation, abs=math.radians(1.0))
    assert max(r.centre_error for r in rows) < 1e-3
    assert rows[0].kind == 1 and abs(rows[0].rotation) > math.radians(10.0)


def test_contacts_stay_inside_the_coulomb_cone(circle_run):
    for row in phase_rows(circle_run):
        assert set(row.cone) <= set(PAIRS) and set(row.cone) == set(row.normal)
        for med, top in row.cone.values():
            assert 0.0 <= med <= top <= 1.0 + 1e-9  # mu = 1
        holder = {1: ("left", "right"), 2: ("left",), 3: ("right",)}[row.kind]
        assert all(row.normal[f] > 0.3 for f in holder)


def _log(pairs, t, pair, fn, ft):
    return SimpleNamespace(pairs=pairs, t=np.asarray(t, float), contact_pair=np.asarray(pair),
                           normal_force=np.asarray(fn, float),
                           tangential_force=np.asarray(ft, float))  # fmt: skip


def test_cone_ratios_of_a_hand_made_log():
    """Three steps, two contact slots: the palm slot's ratios 0.5, 0.25 and 0 (median 0.25),
    the right tip's 1.0 once (the other step below MIN_NORMAL), the window [0, 0.3)."""
    log = _log(
        [PAIRS["right"], PAIRS["palm"]],
        [0.0, 0.1, 0.2, 0.3],
        [[1, 0], [1, 0], [1, -1], [1, 0]],
        [[2.0, 0.01], [4.0, 1.0], [9.0, 0.0], [1.0, 1.0]],
        [[1.0, 0.0], [-1.0, 1.0], [0.0, 0.0], [1.0, 1.0]],
    )
    cone, normal = _cones(log, 0.0, 0.3)
    assert cone["palm"] == pytest.approx((0.25, 0.5))
    assert normal["palm"] == pytest.approx(4.0)
    assert cone["right"] == (1.0, 1.0) and normal["right"] == 1.0
    assert "left" not in cone


def test_first_rows_and_empty_results():
    t = np.array([0.0, 0.002, 0.004, 0.006])
    assert _first_rows(t, np.array([0.0, 0.003, 0.006, 1.0])).tolist() == [0, 2, 3, 3]
    empty = SimpleNamespace(phases=(), trace={"t": np.zeros(0)}, log=None)
    assert phase_rows(empty) == []
