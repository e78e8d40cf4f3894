"""Tests of what the gait executor uses from the sensed trace: the macro feature a phase-3
pass crossed, the phase-1 rotation cap that keeps it off the palm, the back-stroke segment
and the NLP's rotation bound."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.exploration.planar.controller import TRACE_NAMES
from planner.exploration.planar.segments import EDGE_MARGIN, explore_segment
from planner.exploration.planar.sensed_features import (
    FEATURE_HEIGHT,
    MIN_CAPPED,
    PALM_ANGLE,
    PALM_CLEAR,
    rotation_cap,
    sensed_bump,
)
from planner.exploration.planar.settings import GaitSettings
from robots.planar_hand import PlanarHand

R = 0.05
COL = {k: i for i, k in enumerate(TRACE_NAMES)}


def _pass(b0, b1, bump_at=None, height=0.003, width=0.04, lift=0.0, n=400):
    """Trace rows of a phase-3 pass of the pad from ``b0`` to ``b1`` [rad] over a circle of
    radius R about (0, R) with a bump of ``height`` [m] and half-width ``width`` [rad]."""
    rows = np.zeros((n, len(TRACE_NAMES)))
    b = np.linspace(b0, b1, n)
    r = np.full(n, R + lift)
    if bump_at is not None:
        r += height * (np.abs(b - bump_at) < width)
    rows[:, COL["t"]] = np.linspace(0.0, 1.0, n)
    rows[:, COL["kind"]] = 3
    rows[:, COL["pad_touch"]] = 1
    rows[:, COL["cy"]] = R
    rows[:, COL["pLx"]] = r * np.cos(b)
    rows[:, COL["pLy"]] = R + r * np.sin(b)
    return rows


@pytest.mark.parametrize("direction", [1, -1])
def test_a_crossed_bump_is_found_at_its_middle(direction):
    b0, b1 = 2.0, 2.7
    if direction < 0:
        b0, b1 = b1, b0
    angle, crossed = sensed_bump(_pass(b0, b1, bump_at=2.3))
    assert angle == pytest.approx(2.3, abs=math.radians(0.5))
    assert crossed


def test_a_pass_ending_on_the_bump_sees_its_near_half():
    angle, crossed = sensed_bump(_pass(2.0, 2.3, bump_at=2.3))
    assert not crossed
    assert angle == pytest.approx(2.3 - 0.5 * 0.04, abs=math.radians(0.5))


def test_no_bump_without_one_within_the_pass():
    assert sensed_bump(_pass(2.0, 2.7)) is None  # no bump
    assert sensed_bump(_pass(2.0, 2.7, lift=0.003)) is None  # a whole pass lifted
    low = 0.8 * FEATURE_HEIGHT
    assert sensed_bump(_pass(2.0, 2.7, bump_at=2.3, height=low)) is None  # too low
    assert sensed_bump(_pass(2.0, 2.7, bump_at=2.02)) is None  # the pass starts on it
    assert sensed_bump(np.zeros((5, len(TRACE_NAMES)))) is None  # too short


def test_rotation_cap_closed_form():
    # a feature 40 deg above the palm (world -50 deg): rotate at most 40 - 15 deg
    f = math.radians(-50.0)
    assert rotation_cap([f], 0.0) == pytest.approx(math.radians(40.0) - PALM_CLEAR)
    # the same feature seen from an object turned by -10 deg: 10 deg less
    assert rotation_cap([f + 0.1745], -0.1745) == pytest.approx(rotation_cap([f], 0.0))
    # already past the palm, or too close to cap usefully: no cap
    assert rotation_cap([math.radians(-120.0)], 0.0) == math.inf
    close = PALM_ANGLE + PALM_CLEAR + 0.5 * MIN_CAPPED
    assert rotation_cap([close], 0.0) == math.inf
    assert rotation_cap([], 0.3) == math.inf


@given(st.floats(-math.pi, math.pi), st.floats(-10.0, 10.0))
@settings(max_examples=100, deadline=None, derandomize=True)
def test_a_capped_rotation_stops_the_feature_off_the_palm(f, theta):
    cap = rotation_cap([f], theta)
    if math.isfinite(cap):
        end = math.remainder(f + theta - cap - PALM_ANGLE, 2 * math.pi)
        assert end == pytest.approx(PALM_CLEAR, abs=1e-9)
        assert cap >= MIN_CAPPED


def _est(beta_left: float):
    c = np.array([0.0, R])
    n = np.array([math.cos(beta_left), math.sin(beta_left)])
    p = np.vstack([c + R * n, c + R * np.array([1.0, 0.0])])
    return SimpleNamespace(p=p, centre=c, beta=np.array([beta_left, 0.0]), u=0.0,
                           normal_force=np.array([0.3, 2.0]))  # fmt: skip


def test_backstroke_goes_to_via_and_back_with_the_pad_trailing():
    hand = PlanarHand()
    s = GaitSettings()
    b0, via = 2.6, 2.3
    q = np.zeros(6)
    seg = explore_segment(3, _est(b0), q, b0, 0.0, s, hand, via=via)
    T = seg.duration - 0.02
    c = np.array([0.0, R])
    # at the turn (the first quintic piece ends at rest on via) the pad centre sits on the
    # tangent at via, a pad half-width less EDGE_MARGIN on b0's side: the pad trails
    t_turn = s.startup_time + abs(via - b0) * R / s.explore_speed
    p, v, phi = seg.explore(t_turn)
    trail = hand.params.left.pad_half_width - EDGE_MARGIN
    t_via = np.array([-math.sin(via), math.cos(via)])
    foot = c + R * np.array([math.cos(via), math.sin(via)])
    assert np.asarray(p) - foot == pytest.approx(trail * t_via, abs=1e-9)
    assert np.asarray(v) == pytest.approx(0.0, abs=1e-9)
    # the pad lies tangent to the object at its contact
    assert math.remainder(phi - (via + math.pi / 2), 2 * math.pi) == pytest.approx(0, abs=1e-9)
    # it ends where it started, the pad centred on its contact again
    p_end, _, _ = seg.explore(T)
    assert np.asarray(p_end) == pytest.approx(c + R * np.array([math.cos(b0), math.sin(b0)]),
                                              abs=1e-6)  # fmt: skip


def test_nlp_rotation_cap():
    from planner.trajectory import RollingNLP
    from tests.test_trajectory import _start, r

    nlp = RollingNLP(PlanarHand(), knots=6)
    q0, c, beta = _start()
    free = nlp.solve(q0, c, R, r, 0.8, beta, 0.0, warm=False)
    cap = 0.5 * abs(free.rotation)
    capped = nlp.solve(q0, c, R, r, 0.8, beta, 0.0, warm=False, max_rotation=cap)
    assert free.success and capped.success
    assert capped.rotation == pytest.approx(-cap, abs=1e-5)


def test_a_stall_fails_the_gait_unless_the_full_turn_is_done():
    from planner.exploration.planar.machine import stall_outcome

    status, reason = stall_outcome(-math.radians(146.7))
    assert status == "failed" and reason.startswith("no progress")
    status, reason = stall_outcome(-math.radians(373.1))
    assert status == "ok" and "373.1 deg (a full turn)" in reason
    # a failure names what blocked phase 1; a full turn does not
    status, reason = stall_outcome(-math.radians(20.0), "blocking: workspace (x)")
    assert status == "failed" and reason.endswith("deg (blocking: workspace (x))")
    status, reason = stall_outcome(-math.radians(373.1), "blocking: workspace (x)")
    assert status == "ok" and "blocking" not in reason


@pytest.mark.parametrize(("kind", "expected"), [(2, 0.7), (3, 1.9)])
def test_each_holder_ramps_to_its_own_force(kind, expected):
    """Phase 2: the left pad holds with ``left_hold_force``; phase 3: the right finger
    with ``hold_force`` (both ramped from the sensed force over the startup)."""
    s = GaitSettings(hold_force=1.9, left_hold_force=0.7)
    seg = explore_segment(kind, _est(2.6), np.zeros(6), 2.4, 0.0, s, PlanarHand())
    assert seg.hold_force(s.startup_time) == pytest.approx(expected)
    holder = 0 if kind == 2 else 1
    assert seg.hold_force(0.0) == pytest.approx(_est(2.6).normal_force[holder])


def test_left_hold_force_is_validated():
    from planner.errors import InvalidParameter

    with pytest.raises(InvalidParameter, match="left_hold_force"):
        GaitSettings(left_hold_force=0.0)


def test_a_stalled_gait_names_the_constraints_its_phases_1_ended_on():
    """``_Runner._blocking_now``: the phase-1 end events of the stalled cycles name the
    constraint (grasp stability lost: force closure, with the smallest sensed epsilon;
    workspace limit: workspace); phases 2/3 and older cycles do not count."""
    from types import SimpleNamespace

    from planner.exploration.planar.machine import STALL_CYCLES, _Runner
    from planner.exploration.planar.result import PhaseRecord
    from planner.exploration.planar.settings import GaitSettings

    def rec(kind, event, eps=float("nan")):
        return PhaseRecord(
            kind=kind,
            skip=False,
            start=0.0,
            end=1.0,
            rotation=0.0,
            planned_rotation=0.0,
            event=event,
            epsilon=eps,
            nlp_time_s=0.0,
        )

    old = [rec(1, "workspace limit"), rec(2, "path finished")]  # before the window
    window = []
    for k in range(STALL_CYCLES + 1):
        window += [rec(1, "grasp stability lost", 0.004 + 0.001 * k), rec(2, "workspace limit")]
    window[2] = rec(1, "workspace limit")
    r = SimpleNamespace(records=old + window, s=GaitSettings())
    why = _Runner._blocking_now(r)
    assert why == (
        "blocking: force closure (phase 1 ended by grasp stability lost x3, epsilon "
        "down to 0.004 < 0.01), workspace (phase 1 ended by workspace limit x1)"
    )


def test_planning_mu_is_mu_less_its_friction_margin():
    from planner.exploration.planar.settings import GaitSettings

    assert GaitSettings().planning_mu == pytest.approx(0.8)
    assert GaitSettings(mu=0.5, friction_margin=0.1).planning_mu == pytest.approx(0.45)


def test_a_phase_cut_by_the_duration_is_not_judged():
    """A run that runs out of time ends "duration reached", whatever its last phase 1 (cut
    short by the time limit) did. The 6 cm sharp hexagon (seed 1) stalls: its gait fails
    "no progress" when the phase 1 that ends it is judged (at 11 s on one machine, 7.2 s on
    another: the stall's time depends on the CPU's rounding, so the cut is placed from the
    longer run). Cut inside that phase 1, the same run ends "duration reached" with it
    ended by the time limit (before, the run judged its cut phase 1 and failed: a longer
    run disagreed with the shorter one about the state at the cut)."""
    from planner.exploration import explore_object
    from planner.geometry import shapes

    ang = -0.5 * np.pi + np.pi / 6 - 2 * np.pi * np.arange(6) / 6
    hexagon = shapes.polygon(0.06 * np.column_stack([np.cos(ang), np.sin(ang)]))
    longer = explore_object(hexagon, seed=1, duration=20.0)
    assert longer.status == "failed" and longer.reason.startswith("no progress")
    last = longer.phases[-1]
    assert last.phase == 1 and last.event != "time limit" and last.end - last.start > 0.05
    cut = round(0.5 * (last.start + last.end), 3)
    short = explore_object(hexagon, seed=1, duration=cut)
    assert (short.status, short.reason) == ("ok", f"duration {cut:g} s reached")
    assert short.phases[-1].phase == 1 and short.phases[-1].event == "time limit"
    assert short.phases[-1].start == pytest.approx(last.start)
    assert len(short.phases) == len(longer.phases)


def test_a_symptom_ending_names_what_last_blocked_the_gait():
    """A gait ending on a lost contact (or a dropped object, a simulator fault) says what
    its planners last found blocking: the latest ``no_plan`` event naming a constraint;
    nothing from an event whose check found none, or from other events."""
    from types import SimpleNamespace

    from planner.exploration.planar.machine import _Runner

    def ended(*events):
        return _Runner._last_blocked(SimpleNamespace(events=list(events)))

    fc = "blocking: force closure (contact line 5 deg outside x)"
    old = {"t": 0.5, "kind": "no_plan", "phase": 1, "blocking": "blocking: workspace"}
    new = {"t": 1.086, "kind": "no_plan", "phase": 1, "blocking": fc}
    end = {"t": 2.0, "kind": "phase_end", "phase": 1, "blocking": "blocking: reach (z)"}
    assert ended(old, new, end) == f" (last blocked at 1.09 s: {fc})"
    assert ended(old, end) == " (last blocked at 0.50 s: blocking: workspace)"
    none = dict(new, blocking="")
    assert ended(none, end) == "" and ended() == ""


def test_the_blocking_phrase_of_every_planner_reason():
    """``phase_planning.blocking_phrase`` finds the phrase in each planner's reason: bare
    after the NLP's stop (with its own parentheses), in parentheses after the posed-outline
    planner's, none in a reason without one or with only ``NOT_BLOCKED``."""
    from planner.exploration.planar import phase_planning as pp

    fc = "blocking: force closure (contact line 5 deg outside the friction cones)"
    assert pp.blocking_phrase(f"phase-1 NLP: solver failed; {fc}") == fc
    assert pp.blocking_phrase("pivot about the palm corner: x (blocking: workspace)") == (
        "blocking: workspace"
    )
    ws = "blocking: workspace (the right finger's joint 1 0.1 deg from its lower limit)"
    assert pp.blocking_phrase(f"no pivot ({ws})") == ws
    assert pp.blocking_phrase(f"phase-1 NLP: solver failed; {pp.NOT_BLOCKED}") == ""
    assert pp.blocking_phrase("phase 1 rotated 0.2 deg") == ""
