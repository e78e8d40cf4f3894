"""Map-space reach from the resting pose (planar/start_reach.py): a circle turns a full
turn, the batch's ellipses stop where the module docstring says, and the reported reasons
agree with the friction-cone geometry."""

from __future__ import annotations

import math
import re

import pytest
from conftest import benchmark_module
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.exploration.planar.start_reach import start_reach
from planner.geometry import shapes


@pytest.fixture(scope="module")
def hand():
    from robots.planar_hand import PlanarHand, gait_hand_params

    return PlanarHand(gait_hand_params())


@pytest.mark.parametrize("radius", [0.02, 0.05])
def test_a_circle_turns_a_full_turn_from_rest(hand, radius):
    sr = start_reach(shapes.circle(radius), hand, 1.0)
    assert sr.full_turn and sr.rotation == pytest.approx(2 * math.pi)
    assert sr.blocking == "" and sr.start_grasps > 0


def test_a_1_5_to_1_ellipse_turns_a_full_turn_and_a_margin_never_helps(hand):
    """Every grasp with epsilon > 0.05 is also a force-closure grasp: the reachable set
    can only shrink (measured: a full turn without the margin, 95 deg with it)."""
    prof = shapes.ellipse(0.05, 0.05 / 1.5)
    free = start_reach(prof, hand, 1.0)
    robust = start_reach(prof, hand, 1.0, min_epsilon=0.05)
    assert free.full_turn
    assert not robust.full_turn and 0 < robust.rotation < free.rotation
    assert robust.start_grasps <= free.start_grasps


@pytest.mark.parametrize("a", [0.05, 0.07])
def test_the_start_grasp_is_in_force_closure_on_the_resting_outline(hand, a):
    """The reported start grasp, put on the true outline resting on the palm
    (hold_geometry.resting_contact), has its contact line inside both mu = 1 cones."""
    from planner.exploration.planar.hold_geometry import contact_line_angles, resting_contact

    prof = shapes.ellipse(a, a / 1.5)
    sr = start_reach(prof, hand, 1.0)
    (pl, nl, _), (pr, nr, _) = (resting_contact(prof, 0.0, b) for b in sr.start)
    assert max(contact_line_angles(pl, nl, pr, nr)) < math.atan(1.0)
    assert math.pi / 2 < sr.start[0] <= math.pi and -math.pi / 2 < sr.start[1] < math.pi / 2


def test_a_2_to_1_ellipse_stops_at_the_left_reach(hand):
    sr = start_reach(shapes.ellipse(0.05, 0.025), hand, 1.0)
    assert not sr.full_turn and sr.start_grasps > 0
    assert 0 < math.degrees(sr.rotation) <= 15.0
    assert "left finger's reach" in sr.blocking
    assert "neither finger holds the object on the palm" in sr.blocking


@pytest.mark.parametrize("a", [0.05, 0.07])
def test_a_4_to_1_ellipse_has_no_force_closure_grasp_at_rest(hand, a):
    """Two contacts are in force closure iff their line lies inside both cones: with none
    the best line must be at least atan(mu) = 45 deg off a normal."""
    sr = start_reach(shapes.ellipse(a, a / 4), hand, 1.0)
    assert (sr.rotation, sr.full_turn, sr.start_grasps, sr.states) == (0.0, False, 0, 0)
    m = re.search(r"contact line (\d+) deg off a normal", sr.blocking)
    assert m and sr.blocking.startswith("force closure within reach")
    assert int(m.group(1)) >= 45


def test_the_state_cap_stops_the_search_and_says_so(hand):
    sr = start_reach(shapes.circle(0.05), hand, 1.0, max_states=5)
    assert not sr.full_turn and sr.states >= 5
    assert f"search stopped: {sr.states} entries, cap 5" in sr.blocking


@pytest.mark.parametrize(
    "kwargs", [{"mu": 0.0}, {"mu": -1.0}, {"max_states": 0}, {"min_epsilon": 1.0}]
)
def test_bad_arguments_raise(hand, kwargs):
    args = {"mu": 1.0, **kwargs}
    with pytest.raises(InvalidParameter):
        start_reach(shapes.circle(0.05), hand, args.pop("mu"), **args)


def test_the_scenario_descriptions_numbers(hand):
    """The 12 x 10 cm ellipse (ellipse_gait until 2026-11-24) turns a full turn from rest even
    with the executor's friction reserve; long_thin_gait (16 x 10 cm) does not, and less with it."""
    eg = start_reach(shapes.ellipse(0.06, 0.05), hand, 0.8, min_epsilon=0.02)
    assert eg.full_turn
    assert [round(math.degrees(b)) for b in eg.start] == [135, 5]
    thin = shapes.ellipse(0.08, 0.05)
    full_cone, reserve = start_reach(thin, hand, 1.0), start_reach(thin, hand, 0.8)
    assert not full_cone.full_turn and round(math.degrees(full_cone.rotation)) == 175
    assert round(math.degrees(reserve.rotation)) == 10
    assert "left finger's reach" in full_cone.blocking


def test_the_batch_table_columns(hand):
    """bench_gait's rest_* columns: the executor's planning (mu 0.8, epsilon >= 0.01) never
    turns further than mu = 1 with force closure alone, and the agree column names the full
    turn plan_gait's search misses."""
    bench = benchmark_module("bench_gait")
    circle = bench.rest_reach(shapes.circle(0.05), hand, 1.0)
    assert circle == {"rest_turn_deg": 360, "rest_turn_reserve_deg": 360, "rest_blocking": ""}
    row = bench.rest_reach(shapes.ellipse(0.05, 0.05 / 1.5), hand, 1.0)
    assert row["rest_turn_deg"] == 360 and row["rest_turn_reserve_deg"] < 360
    assert row["rest_blocking"].startswith("with mu 0.8 and epsilon >= 0.01: ")
    row.update(verdict="failed", plan_gait="no gait")
    assert bench.explain(row).startswith("agree; but map space from rest has a full turn")
    row.update(rest_turn_deg=10)
    assert bench.explain(row) == "agree"


@pytest.mark.parametrize(
    "profile",
    [shapes.ellipse(0.05, 0.05 / 1.5), shapes.rounded_rectangle(0.12, 0.12, 0.024)],
    ids=["ellipse", "rounded square"],
)
def test_phase1_extent_and_handoffs_follow_plan_gaits_rules(hand, profile):
    """start_reach's phase 1 and handoffs are plan_gait's (planner.grasp.gait._Search with
    no successor limit) on 200 random phase-1 entries: the same extent, the same set of
    next entries."""
    import numpy as np

    from planner.exploration.planar import start_reach as sr
    from planner.grasp.gait import _Search, gait_problem

    prob = gait_problem(profile, hand, 1.0, resolution=72)
    srch, horizon, n = _Search(prob), sr._horizon(prob), 72
    kk, ii, jj = np.nonzero(
        prob.fc_lr[None] & prob.reach["left"][:, :, None] & prob.reach["right"][:, None, :]
    )
    rng = np.random.default_rng(0)
    for a in rng.choice(kk.size, 200, replace=False):
        k, i, j = int(kk[a]), int(ii[a]), int(jj[a])
        m, _ = sr._extent(prob, horizon, k, i, j)
        assert m == int(srch.p1_extent(k, i, j)[0][0])
        if m < 1:
            continue
        theirs = {((k + t) % n, g[0], g[1]) for t, _, g, _ in srch.successors(k, i, j, m, 10**6)}
        mine = {
            ((k + t) % n, *g)
            for t in range(m, 0, -1)
            for g in sr._handoffs(prob, horizon, (k + t) % n, (i + t) % n, (j + t) % n)
        }
        assert mine == theirs


@settings(max_examples=6, deadline=None, derandomize=True)
@given(mu=st.floats(0.6, 1.4), extra=st.floats(0.05, 0.5))
def test_more_friction_never_turns_less(mu, extra):
    """Every force-closure grasp (two contacts, or a finger with the palm) stays one with a
    larger mu and the reach tables do not depend on it: the graph only grows."""
    from robots.planar_hand import PlanarHand, gait_hand_params

    h = PlanarHand(gait_hand_params())
    prof = shapes.ellipse(0.05, 0.05 / 1.5)
    low, high = start_reach(prof, h, mu), start_reach(prof, h, mu + extra)
    assert high.rotation >= low.rotation and high.start_grasps >= low.start_grasps
