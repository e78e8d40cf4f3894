"""The phase-1 carry trigger of the round planner (planar/phase_planning.py) and the
squeeze it hands to the phase-1 segment (planar/segments.py)."""

from __future__ import annotations

import dataclasses
import math
from types import SimpleNamespace

import numpy as np
import pytest

from planner.exploration.planar import phase_planning as pp
from planner.exploration.planar.carry_squeeze import phase1_squeeze
from planner.exploration.planar.controller import TRACE_NAMES
from planner.exploration.planar.settings import GaitSettings

R = 0.03
KIND, CX = TRACE_NAMES.index("kind"), TRACE_NAMES.index("cx")


def _plan(x0: float, x1: float, beta=((2.62, 0.37), (2.26, 0.16)), success: bool = True):
    k = len(beta)
    return SimpleNamespace(
        success=success, centre=np.c_[np.linspace(x0, x1, k), np.full(k, R)],
        beta=np.asarray(beta, float), rotation=-0.4, theta=np.linspace(0.0, -0.4, k),
        q=np.zeros((k, 6)), u=np.zeros(k),
    )  # fmt: skip


def _row(kind: int, cx: float) -> list[float]:
    row = [0.0] * len(TRACE_NAMES)
    row[KIND], row[CX] = float(kind), cx
    return row


def _records(last_phase1_event: str = "workspace limit"):
    """Phase records: a phase 1 that ended with ``last_phase1_event``, then phases 2/3."""
    return [SimpleNamespace(kind=1, phase=1, event="path finished"),
            SimpleNamespace(kind=1, phase=1, event=last_phase1_event),
            SimpleNamespace(kind=2, phase=2, event="path finished"),
            SimpleNamespace(kind=3, phase=3, event="workspace limit")]  # fmt: skip


def _runner(last_plan, trace_rows, settings=None, shape=None, event="workspace limit"):
    return SimpleNamespace(
        s=settings or GaitSettings(), shape=shape, _plan1=last_plan,
        ctrl=SimpleNamespace(trace=trace_rows), nlp=SimpleNamespace(travel=0.01),
        events=[], world=SimpleNamespace(time=5.4), records=_records(event),
    )  # fmt: skip


def test_miss_is_the_last_phase1_end_against_its_plan():
    # the plan took the centre from 14 to 4 mm; the object rolled to 26 mm on the palm;
    # phases 2/3 (kinds 2, 3) after it do not count
    rows = [_row(1, 0.014), _row(1, 0.026), _row(2, 0.0255), _row(3, 0.025)]
    r = _runner(_plan(0.014, 0.004), rows)
    assert pp.phase1_miss(r) == pytest.approx(0.022, abs=1e-12)


def test_no_miss_without_an_executed_plan():
    assert pp.phase1_miss(_runner(None, [_row(1, 0.0)])) is None
    assert pp.phase1_miss(_runner(_plan(0.0, 0.0, success=False), [_row(1, 0.02)])) is None
    assert pp.phase1_miss(_runner(_plan(0.0, 0.0), [])) is None
    assert pp.phase1_miss(_runner(_plan(0.0, 0.0), [_row(2, 0.02)])) is None


def test_a_phase1_that_rolled_into_a_workspace_limit_makes_the_next_carry():
    s = GaitSettings()
    r = _runner(None, [])
    plan = _plan(0.025, 0.015)
    f = pp.carry_squeeze(r, plan, 0.022)
    assert f == pytest.approx(phase1_squeeze(plan.beta, s, pp.PHASE1_LIFT))
    assert f > s.internal_force  # 150 / 21 deg on the circle: more than 1 N
    assert [e["kind"] for e in r.events] == ["carry"]
    assert "22.0 mm" in r.events[0]["message"]


@pytest.mark.parametrize(
    "miss, settings, shape, event",
    [
        (None, GaitSettings(), None, "workspace limit"),  # the first phase 1
        (0.009, GaitSettings(), None, "workspace limit"),  # within the NLP's travel
        (0.05, GaitSettings(), None, "path finished"),  # it rolled, but got its turn
        (0.05, dataclasses.replace(GaitSettings(), carry_weight=False), None, "workspace limit"),
        (0.05, GaitSettings(), object(), "workspace limit"),  # a posed outline: its planner
    ],
)
def test_otherwise_the_commanded_squeeze(miss, settings, shape, event):
    r = _runner(None, [], settings, shape, event)
    assert pp.carry_squeeze(r, _plan(0.0, 0.0), miss) is None
    assert r.events == []


@pytest.mark.parametrize("squeeze", [None, 2.3])
def test_the_phase1_segment_ramps_to_the_squeeze(squeeze):
    from planner.exploration.planar.segments import phase1_segment
    from robots.planar_hand import PlanarHand

    s = GaitSettings()
    c = np.array([0.0, R])
    est = SimpleNamespace(centre=c, normal_force=np.array([0.3, 1.1]))
    plan = _plan(0.0, -0.005)
    seg = phase1_segment(plan, est, np.zeros(6), 0.0, s, PlanarHand(), lift=0.0015,
                         squeeze=squeeze)  # fmt: skip
    want = s.internal_force if squeeze is None else squeeze
    assert seg.hold_force(0.0) == pytest.approx(0.3)  # from the smaller sensed force
    assert seg.hold_force(s.startup_time) == pytest.approx(want)
    assert seg.hold_force(seg.duration) == pytest.approx(want)
    assert float(seg.hold_force.many(np.array([seg.duration]))[0]) == pytest.approx(want)
    assert math.isfinite(seg.duration)


def test_joint_at_limit_names_the_finger_the_joint_and_the_stop():
    from planner.exploration.planar.phase_planning import joint_at_limit
    from robots.planar_hand import PlanarHand

    lim = PlanarHand().joint_limits
    q = lim.mean(axis=1)
    q[5] = lim[5, 0] + math.radians(0.5)  # right distal joint near its lower stop
    q[1] = lim[1, 1] - math.radians(2.0)  # left middle joint near its upper stop
    assert joint_at_limit(q, lim, 5) == "the right finger's joint 3 0.5 deg from its lower limit"
    assert joint_at_limit(q, lim, 1) == "the left finger's joint 2 2.0 deg from its upper limit"
    q[0] = lim[0, 0]
    assert joint_at_limit(q, lim, 0) == "the left finger's joint 1 0.0 deg from its lower limit"
