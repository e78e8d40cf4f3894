"""What the phase machine does when phase 1 cannot be planned (machine._Runner): the right
finger's regrasp (phase 2), then the left pad's (phase 3, ``GaitSettings.left_regrasp``),
then, where the gait would end, the last resort of planning from the grasp as it is
(``RollingNLP(relax_start=True)``, ``GaitSettings.last_resort``); and the blocking
constraint named when the right tip touches beyond its rolling range."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.exploration.planar import phase_planning
from planner.exploration.planar.machine import _Runner
from planner.exploration.planar.phase_planning import blocking, tip_contact_angle
from planner.exploration.planar.settings import GaitSettings


@pytest.fixture(scope="module")
def hand():
    from robots.planar_hand import PlanarHand, gait_hand_params

    return PlanarHand(gait_hand_params(1.0))


def _runner(**settings_kw):
    r = _Runner.__new__(_Runner)
    r.s = GaitSettings(**settings_kw)
    r.world = SimpleNamespace(time=2.0)
    r.events, r.nlps, r.shape, r.records = [], {}, None, []
    r.status, r.reason = "ok", ""
    return r


def test_phase_1_without_a_plan_regrasps_right_then_left_then_ends():
    r = _runner()
    assert [r._after_no_plan(1, k) for k in (1, 2, 3)] == [2, 3, None]
    assert not r.events  # the question has no side effects
    assert r._no_plan(1, 1, "why 1") == 2
    assert [e["kind"] for e in r.events] == ["no_plan"]
    assert r._no_plan(1, 2, "why 2") == 3
    assert [e["kind"] for e in r.events] == ["no_plan", "no_plan", "regrasp"]
    assert r.events[-1]["phase"] == 3 and r.status == "ok"
    assert r._no_plan(1, 3, "why 3") is None
    assert r.events[-1]["kind"] == "end" and r.status == "failed"
    assert r.reason == "no stable grasp within the workspace (why 3)"


def test_without_left_regrasp_the_second_failure_ends_the_gait():
    r = _runner(left_regrasp=False)
    assert r._after_no_plan(1, 1) == 2
    assert r._after_no_plan(1, 2) is None
    assert not r.events


@pytest.mark.parametrize("kind", [2, 3])
def test_phase_2_or_3_without_a_plan_goes_back_to_phase_1_once(kind):
    r = _runner()
    assert r._after_no_plan(kind, 1) == 1
    assert r._after_no_plan(kind, 2) is None


def test_last_resort_plans_with_the_relaxed_nlp_and_restores_the_runners(monkeypatch):
    built, seen = [], []

    class FakeNLP:
        def __init__(self, hand, knots, relax_start=False):
            built.append((knots, relax_start))

    monkeypatch.setattr("planner.trajectory.RollingNLP", FakeNLP)

    def plan(r, kind, est, q):
        seen.append((kind, r.nlp))
        return "segment", -0.3, 0.01, ""

    monkeypatch.setattr(phase_planning, "plan", plan)
    r = _runner()
    r.hand, strict = object(), object()
    r.nlp = strict
    out = r._last_resort("est", np.zeros(6), "phase-1 NLP: solver failed; blocking: x")
    assert out == ("segment", -0.3, 0.01, "")
    assert built == [(r.s.nlp_knots, True)]
    assert seen[0][0] == 1 and isinstance(seen[0][1], FakeNLP)
    assert r.nlp is strict  # the runner's NLP is back
    assert r.events[-1]["kind"] == "last_resort"
    assert r.events[-1]["message"].startswith("phase-1 NLP: solver failed")
    # built once: the second use takes the same NLP
    r._last_resort("est", np.zeros(6), "why")
    assert len(built) == 1


def test_last_resort_without_a_plan_keeps_the_first_reason(monkeypatch):
    monkeypatch.setattr("planner.trajectory.RollingNLP", lambda *a, **k: object())
    monkeypatch.setattr(phase_planning, "plan", lambda r, kind, est, q: (None, 0.0, 0.02, "b"))
    r = _runner()
    r.hand, r.nlp = object(), object()
    assert r._last_resort("est", np.zeros(6), "first") == (None, 0.0, 0.02, "first")
    assert not r.events


@pytest.mark.parametrize("how", ["setting off", "posed outline"])
def test_no_last_resort_when_switched_off_or_on_a_posed_outline(how, monkeypatch):
    monkeypatch.setattr(phase_planning, "plan", lambda *a: pytest.fail("planned"))
    r = _runner(last_resort=how != "setting off")
    if how == "posed outline":
        r.shape = object()
    assert r._last_resort("est", np.zeros(6), "why") == (None, 0.0, 0.0, "why")


# a start recorded from the 10 cm rounded square (corner radius 3 cm, nominal circle, seed
# 0): after a phase 2 that ended at the right finger's joint-3 stop the round tip touches the
# object 99 deg from its axis, beyond the NLP's 1.2 rad (IPOPT: Infeasible_Problem_Detected)
START = {
    "q0": [0.12118448224296566, -1.9742332740088202, 0.047553404424454875,
           -0.6335340653967698, 1.8146992720687134, 2.107689602554871],
    "centre": [0.037958710163651224, 0.06403247602759685],
    "radius": 0.0503527164563459,
    "tip_radius": 0.025,
    "mu": 0.8,
    "beta0": [2.90689359304329, -0.0029978007663671617],
    "u0": -0.0034775535540191994,
}  # fmt: skip


def test_relaxed_nlp_plans_where_the_strict_one_is_infeasible(hand):
    from planner.trajectory import RollingNLP

    start = tip_contact_angle(hand, START["q0"], START["beta0"][1])
    assert abs(start) > 1.2  # the recorded start is beyond the tip's range
    s = START
    args = (s["q0"], s["centre"], s["radius"], s["tip_radius"], s["mu"], s["beta0"], s["u0"])
    kw = {"margin": 0.15, "joint_margin": 0.05, "home_x": 0.0, "warm": False}
    strict = RollingNLP(hand, knots=6).solve(*args, **kw)
    assert not strict.success and strict.stop == "solver failed"
    nlp = RollingNLP(hand, knots=6, relax_start=True)
    plan = nlp.solve(*args, **kw)
    assert plan.success
    assert plan.rotation < -math.radians(5.0)  # clockwise
    # no knot farther round the tip than the plan's start (its knot 0, the sensed start
    # made kinematically consistent: within 1 deg of it) - the relaxed bound
    pairs = zip(plan.q, plan.beta[:, 1], strict=True)
    angles = [abs(tip_contact_angle(hand, q, b)) for q, b in pairs]
    assert angles[0] == pytest.approx(abs(start), abs=math.radians(1.0))
    assert max(angles[1:]) <= max(angles[0], 1.2) + 1e-6
    # the fingertips stay on the planned circle: the tip centre R + r from its centre
    from planner.trajectory.nlp_rows import tip_frames

    fk = tip_frames(hand)
    for q, c in zip(plan.q, plan.centre, strict=True):
        pR = np.asarray(fk(q)[2]).ravel()
        assert np.linalg.norm(pR - c) == pytest.approx(s["radius"] + s["tip_radius"], abs=1e-5)


def test_relaxed_nlp_is_the_strict_one_where_the_start_is_inside():
    """A start inside the cones and the tip's range (test_trajectory's grasp of the 10 cm
    circle at 145/15 deg): both NLPs plan the same rotation."""
    from planner.trajectory import RollingNLP
    from robots.planar_hand import PlanarHand
    from tests.test_trajectory import R, _start, r

    h = PlanarHand()
    q0, c, beta = _start()
    assert abs(tip_contact_angle(h, q0, beta[1])) < 1.2
    a = RollingNLP(h, knots=6).solve(q0, c, R, r, 0.8, beta, 0.0, warm=False)
    b = RollingNLP(h, knots=6, relax_start=True).solve(q0, c, R, r, 0.8, beta, 0.0, warm=False)
    assert a.success and b.success
    assert a.rotation < -math.radians(3.0)
    assert b.rotation == pytest.approx(a.rotation, abs=1e-5)
    # the joint path is set by a weak smoothness term (weight 1e-2): the two IPOPT runs end
    # it 1e-4 rad apart at the 1e-5 tolerance
    np.testing.assert_allclose(b.q, a.q, atol=1e-3)


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.floats(-1.0, 1.0), min_size=6, max_size=6),
    st.floats(-math.pi, math.pi),
)
def test_tip_contact_angle_is_the_nlps_bound(u, beta):
    """``tip_contact_angle`` (numpy kinematics) against the NLP's expression
    ``cos((beta_R + pi - phi_R) - pi/2)`` (CasADi kinematics walked from the Pinocchio
    model) over the joint ranges."""
    from planner.trajectory.nlp_rows import tip_frames
    from robots.planar_hand import PlanarHand, gait_hand_params

    h = _HAND.setdefault("hand", PlanarHand(gait_hand_params(1.0)))
    fk = _HAND.setdefault("fk", tip_frames(h))
    lim = h.joint_limits
    q = lim[:, 0] + (np.asarray(u) + 1.0) / 2.0 * (lim[:, 1] - lim[:, 0])
    a = tip_contact_angle(h, q, beta)
    phi = float(np.asarray(fk(q)[3]).ravel()[0])
    assert -math.pi <= a <= math.pi
    assert math.cos(a) == pytest.approx(math.cos((beta + math.pi - phi) - math.pi / 2), abs=1e-9)
    assert math.sin(a) == pytest.approx(math.sin((beta + math.pi - phi) - math.pi / 2), abs=1e-9)


_HAND: dict = {}


def test_blocking_names_the_tip_beyond_its_range(hand):
    """A stable contact pair (symmetric, 30 deg below the horizontal) at mid-range joints with
    the tip touching 100 deg from its axis: the blocking constraint is the tip's range."""
    q = hand.neutral()
    phi = hand.fingertip_pose(q, "right").angle
    beta_r = phi - 0.5 * math.pi - math.radians(100.0)  # tip_contact_angle = -100 deg
    beta_r = math.remainder(beta_r, 2 * math.pi)
    est = SimpleNamespace(beta=np.array([math.pi - beta_r, beta_r]))
    r = SimpleNamespace(hand=hand, s=GaitSettings(), nlp=SimpleNamespace(max_tip_angle=1.2))
    from planner.exploration.planar.heuristics import stable_pair

    assert stable_pair(est.beta[0], est.beta[1], 0.8, 0.0) > 0  # the pair is not what blocks
    why = blocking(r, est, q, 0.8)
    assert why == ("blocking: workspace (the right tip touches 100.0 deg from its axis; "
                   "phase 1 rolls it within 69 deg)")  # fmt: skip


@pytest.mark.parametrize(
    "name", ["left_regrasp", "last_resort", "corner_probe", "carry_weight", "sensed_features"]
)
@pytest.mark.parametrize("value", ["false", 0, None])
def test_settings_switches_must_be_booleans(name, value):
    """A switch given "false" (a string: true in Python) or 0 is refused, named."""
    from planner.errors import InvalidParameter

    with pytest.raises(InvalidParameter, match=rf"^{name}: expected true or false"):
        GaitSettings(**{name: value})
    assert getattr(GaitSettings(**{name: False}), name) is False


def test_a_simulator_fault_ends_the_gait_with_the_simulators_own_message(monkeypatch):
    """A phase whose simulation stops (an LCP without a verified answer) ends the gait as
    failed, the reason naming the phase and the simulator's message (it read "sim fault in
    phase 2: sim fault")."""
    import dataclasses

    from planner.exploration import explore_object
    from planner.geometry import shapes
    from planner.sim import PlanarWorld

    real = PlanarWorld.run
    calls = []
    msg = "step failed at t=0.1 s: contact problem: Lemke stopped on a ray"

    def failing_second_phase(self, *args, **kwargs):
        log = real(self, *args, **kwargs)
        calls.append(1)
        return dataclasses.replace(log, status="failed", reason=msg) if len(calls) == 2 else log

    monkeypatch.setattr(PlanarWorld, "run", failing_second_phase)
    res = explore_object(shapes.circle(0.05), duration=3.0)
    assert res.status == "failed"
    assert res.reason == f"sim fault in phase {res.phases[-1].kind}: {msg}"
    assert len(res.phases) == 2 and res.phases[-1].event == "sim fault"
