"""The map-space prior during an executed gait (planner/exploration/planar/prior_track.py):
pose lookup, world angles of the prior's contacts, and the deviations it reports; the
``prior`` events of a run and the posed outline's regrasp to the prior's handoff."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from planner.exploration.planar.prior_track import (
    ROTATION_TOL,
    SAME_CONTACT,
    PriorTrack,
    infeasible_message,
)

N = 72
STEP = 2 * math.pi / N


def _phase(kind, k0, k1, start, end, transition="forward"):
    """A ``GaitPhase``-like record: object-frame contact angles [rad] at poses k0 / k1."""
    return SimpleNamespace(phase=kind, pose_start=k0, pose_end=k1,
                           rotation=-(k1 - k0) * STEP, transition=transition,
                           start={"left": start[0], "right": start[1], "palm": 0.0},
                           end={"left": end[0], "right": end[1], "palm": 0.0})  # fmt: skip


def _gait(phases, feasible=True, reason=""):
    return SimpleNamespace(feasible=feasible, reason=reason, phases=tuple(phases), resolution=N)


def _cycle(k0: int, turn: int, left: float, right: float, skip: bool = False):
    """One 1 -> 2 -> 3 cycle from pose k0 turning ``turn`` cells with the contacts at the
    world angles ``left`` / ``right`` [rad] throughout (object-frame angle = world angle +
    k 2 pi / N at pose k: phase 1 rolls them along the object, phases 2/3 regrasp where
    they are)."""
    a0, a1 = k0 * STEP, (k0 + turn) * STEP
    s0, s1 = (left + a0, right + a0), (left + a1, right + a1)
    return [
        _phase(1, k0, k0 + turn, s0, s1),
        _phase(2, k0 + turn, k0 + turn, s1, s1, "skip" if skip else "forward"),
        _phase(3, k0 + turn, k0 + turn, s1, s1),
    ]


CIRCLE = _gait([p for k in range(0, N, 4) for p in _cycle(k, 4, math.radians(170),
                                                           math.radians(10))])  # fmt: skip


def test_no_prior_or_an_infeasible_one_gives_no_track_and_says_why():
    assert PriorTrack.of(None) is None
    bad = _gait([], feasible=False, reason="force closure lost")
    assert PriorTrack.of(bad) is None
    assert "force closure lost" in infeasible_message(bad)
    assert infeasible_message(CIRCLE) == "" and infeasible_message(None) == ""


def test_world_angles_are_object_angles_turned_by_the_pose():
    """A contact rolling with the object keeps its world angle: the object-frame angle
    grows by the turn while the pose turns the object back by as much."""
    tr = PriorTrack.of(CIRCLE)
    for s in tr.steps:
        assert math.remainder(s.start[0] - math.radians(170), 2 * math.pi) == pytest.approx(0)
        assert math.remainder(s.end[1] - math.radians(10), 2 * math.pi) == pytest.approx(0)


@given(st.floats(-20.0, 20.0))
def test_pose_index_and_nearest_step(theta):
    tr = PriorTrack.of(CIRCLE)
    k = tr.pose_index(theta)
    assert 0 <= k < N
    assert math.remainder(-theta - k * STEP, 2 * math.pi) == pytest.approx(0, abs=STEP / 2 + 1e-9)
    for kind in (1, 2, 3):
        s = tr.step(kind, theta)
        assert s.kind == kind

        def dist(x):
            d = abs(x.pose - k) % N
            return min(d, N - d)

        assert all(dist(s) <= dist(o) for o in tr.steps if o.kind == kind)


def test_the_start_grasp_of_the_prior_is_no_deviation():
    from planner.exploration.planar.setup import prior_world_grasp

    gait = _gait(_cycle(9, 1, 3.75, 1.22))  # starts at pose 9, as on the 8 cm square
    tr = PriorTrack.of(gait)
    beta = prior_world_grasp(gait)
    assert tr.start_deviation(beta) == ""
    msg = tr.start_deviation((beta[0] + SAME_CONTACT + 0.01, beta[1]))
    assert msg.startswith("start grasp at left") and "did not hold" in msg


def test_phase1_deviation_reports_short_turns_and_missing_plans():
    tr = PriorTrack.of(CIRCLE)  # every phase 1 turns 20 deg
    prior = math.radians(-20.0)
    assert tr.phase1_deviation(0.0, prior) == ""
    assert tr.phase1_deviation(0.0, 1.5 * prior) == ""  # turning further is no deviation
    assert tr.phase1_deviation(0.0, 0.55 * prior) == ""  # more than half
    msg = tr.phase1_deviation(0.0, 0.3 * prior)
    assert msg == "phase 1 plans -6.0 deg; the prior's phase 1 at this pose turns -20.0 deg"
    assert "phase 1 plans 3.0 deg" in tr.phase1_deviation(0.0, math.radians(3.0))  # backwards
    assert tr.phase1_deviation(0.0, None).startswith("no phase-1 plan; the prior's")
    # a prior turning less than the grid tolerance: any plan within it is the same
    small = PriorTrack.of(_gait(_cycle(0, 1, 3.0, 0.2)))
    assert small.phase1_deviation(0.0, -0.4 * STEP) == ""
    assert ROTATION_TOL >= STEP - 1e-12


@pytest.mark.parametrize("kind", [2, 3])
def test_regrasp_deviation_beyond_the_contact_tolerance(kind):
    tr = PriorTrack.of(CIRCLE)
    aim = math.radians(10.0 if kind == 2 else 170.0)
    for theta in (0.0, -0.35, -3.0, -6.5):
        assert tr.regrasp_deviation(kind, theta, aim + 2 * math.pi) == ""  # wrapped
        assert tr.regrasp_deviation(kind, theta, aim - 0.9 * SAME_CONTACT) == ""
        msg = tr.regrasp_deviation(kind, theta, aim + 1.2 * SAME_CONTACT)
        who = "right finger's" if kind == 2 else "left pad's"
        assert who in msg and msg.endswith(f"at {round(math.degrees(aim))} deg")
    assert tr.regrasp_deviation(1, 0.0, 5.0) == ""


def test_transition_deviation_both_ways():
    fwd = PriorTrack.of(CIRCLE)
    assert fwd.transition_deviation(0.0, False) == ""
    assert "the prior goes on to phase 3" in fwd.transition_deviation(0.0, True, "x")
    skip = PriorTrack.of(_gait(_cycle(0, 4, 3.0, 0.2, skip=True)))
    assert skip.transition_deviation(0.0, True) == ""
    assert "skips it" in skip.transition_deviation(0.0, False)


def test_a_run_reports_where_it_parts_from_the_prior():
    """The 16 x 10 cm ellipse (long_thin_gait's object): the prior (plan_gait on the
    nominal circle) grasps at 180 / 5 deg, which the planner's friction reserve rejects on
    the ellipse; the run says so at t = 0, and every ``prior`` event names the prior."""
    from planner.exploration import explore_object
    from planner.geometry import shapes

    res = explore_object(shapes.ellipse(0.08, 0.05), duration=1.0)
    ev = [e for e in res.events if e["kind"] == "prior"]
    assert ev and ev[0]["t"] == 0.0 and ev[0]["message"].startswith("start grasp at left")
    assert all("the prior" in e["message"] for e in ev)
    silent = explore_object(shapes.ellipse(0.08, 0.05), duration=1.0, use_prior=False)
    assert not [e for e in silent.events if e["kind"] == "prior"]


def test_a_run_whose_prior_raises_says_so_and_goes_on(monkeypatch):
    """When ``plan_gait`` raises on the planner's model the run has no prior (``result.prior``
    None), its first event says why, and the gait is planned from the sensed estimate."""
    import planner.grasp
    from planner.errors import HapexError
    from planner.exploration import explore_object
    from planner.geometry import shapes

    def broken(*args, **kwargs):
        raise HapexError("grasp tables: out of memory")

    monkeypatch.setattr(planner.grasp, "plan_gait", broken)
    res = explore_object(shapes.circle(0.05), duration=0.3)
    ev = [e for e in res.events if e["kind"] == "prior"]
    assert res.prior is None and len(ev) == 1 and ev[0]["t"] == 0.0
    assert ev[0]["message"] == (
        "the prior (plan_gait on the planner's model) failed: grasp tables: out of memory; "
        "every phase is planned from the sensed estimate alone")  # fmt: skip
    assert res.phases and res.phases[0].phase == 1
    assert infeasible_message(None, "") == ""


def test_posed_outline_regrasps_to_the_prior_handoff(monkeypatch):
    """``shape_planning.plan_explore`` sends the explorer to the prior's handoff at the
    sensed rotation (``follow_prior``), else back to the start grasp's world angle (before
    the move into the planning cones, tested in test_gait.py)."""
    from planner.exploration.planar import shape_planning
    from planner.exploration.planar.settings import GaitSettings

    monkeypatch.setattr(shape_planning, "STABLE_WINDOW", 0.0)

    tr = PriorTrack.of(CIRCLE)
    seen = {}

    def fake_segment(kind, est, q, tracker, target, theta, s, hand, **kw):
        seen["target"] = target
        return "segment"

    for follow, want in ((True, math.radians(170.0)), (False, 2.5)):
        runner = SimpleNamespace(s=GaitSettings(follow_prior=follow), prior=tr, theta=-0.3,
                                 start={"beta": (2.5, 0.3)}, shape=None, hand=None)  # fmt: skip
        est = SimpleNamespace(pad_touch=False)
        import planner.exploration.planar.outline_segments as osg

        old = osg.outline_explore_segment
        osg.outline_explore_segment = fake_segment
        try:
            out = shape_planning.plan_explore(runner, 3, est, np.zeros(6))
        finally:
            osg.outline_explore_segment = old
        assert out == ("segment", 0.0, 0.0, "")
        assert math.remainder(seen["target"] - want, 2 * math.pi) == pytest.approx(0, abs=1e-12)
