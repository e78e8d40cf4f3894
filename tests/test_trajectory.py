"""Tests of planner.trajectory: the rolling NLP (eqs. 2.3-2.4) and the startup splines."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.trajectory import ForceRamp, QuinticSpline, RollingNLP
from robots.planar_hand import PlanarHand

HAND = PlanarHand()
R, r = 0.05, 0.025


def _start(bl_deg=145.0, br_deg=15.0):
    from planner.exploration.planar.heuristics import best_margin_ik, pad_angle

    c = np.array([0.0, R])
    bl, br = math.radians(bl_deg), math.radians(br_deg)
    nL = np.array([math.cos(bl), math.sin(bl)])
    nR = np.array([math.cos(br), math.sin(br)])
    qL = HAND.inverse_kinematics("left", c + R * nL, angle=pad_angle(bl, -2.0))
    qR = best_margin_ik(HAND, "right", c + (R + r) * nR, around=br + math.pi / 2)
    return np.r_[qL, qR], c, np.array([bl, br])


@pytest.fixture(scope="module")
def nlp():
    return RollingNLP(HAND, knots=6)


def test_plan_rotates_clockwise_with_pure_rolling(nlp):
    q0, c, beta = _start()
    plan = nlp.solve(q0, c, R, r, 0.8, beta, 0.0, warm=False)
    assert plan.success
    assert plan.rotation < -math.radians(3)
    # eq. (2.4): equal arclengths on the object and on each fingertip
    obj_L = R * ((plan.beta[:, 0] - plan.theta) - plan.beta[0, 0])
    np.testing.assert_allclose(obj_L, plan.u - plan.u[0], atol=1e-7)
    phiR = plan.q[:, 3:6].sum(axis=1)
    obj_R = R * ((plan.beta[:, 1] - plan.theta) - plan.beta[0, 1])
    tip_R = r * ((plan.beta[:, 1] - phiR) - (plan.beta[0, 1] - phiR[0]))
    np.testing.assert_allclose(obj_R + tip_R, 0.0, atol=1e-7)
    # finger kinematics: the round tip's centre at distance R + r from the object centre
    for k in range(len(plan.theta)):
        tip = HAND.fingertip_pose(plan.q[k], "right").position
        assert np.linalg.norm(tip - plan.centre[k]) == pytest.approx(R + r, abs=1e-6)  # IPOPT tol
        assert HAND.within_limits(plan.q[k], tol=1e-6)
    assert np.all(np.diff(plan.theta) <= 1e-9)  # monotone clockwise


def test_warm_start_reproduces_the_plan(nlp):
    q0, c, beta = _start()
    cold = nlp.solve(q0, c, R, r, 0.8, beta, 0.0, warm=False)
    warm = nlp.solve(q0, c, R, r, 0.8, beta, 0.0, warm=True)
    assert warm.success
    assert warm.rotation == pytest.approx(cold.rotation, abs=1e-4)
    # IPOPT iteration counts are deterministic: the warm start needs fewer
    assert 1 <= warm.iterations < cold.iterations


def test_lower_friction_rotates_less(nlp):
    q0, c, beta = _start()
    hi = nlp.solve(q0, c, R, r, 1.0, beta, 0.0, warm=False)
    lo = nlp.solve(q0, c, R, r, 0.45, beta, 0.0, warm=False)
    assert hi.success
    assert (not lo.success) or lo.rotation >= hi.rotation - 1e-6


def test_bad_inputs():
    with pytest.raises(InvalidParameter, match="knots"):
        RollingNLP(HAND, knots=1)
    with pytest.raises(InvalidParameter, match="duration"):
        QuinticSpline.between([0.0], [1.0], 0.0)
    with pytest.raises(InvalidParameter, match="duration"):
        ForceRamp(0.0, 1.0, -1.0)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(
    st.floats(-1, 1), st.floats(-1, 1), st.floats(-2, 2), st.floats(-2, 2),
    st.floats(-5, 5), st.floats(-5, 5), st.floats(0.05, 3.0),
)  # fmt: skip
def test_quintic_meets_its_boundary_conditions(x0, x1, v0, v1, a0, a1, T):
    sp = QuinticSpline.between([x0], [x1], T, v0=[v0], v1=[v1], a0=[a0], a1=[a1])
    p, v, a = sp(0.0)
    assert (p[0], v[0], a[0]) == pytest.approx((x0, v0, a0), abs=1e-9)
    p, v, a = sp(T)
    assert (p[0], v[0], a[0]) == pytest.approx((x1, v1, a1), abs=1e-6 * (1 + abs(a1)))
    # velocity is the derivative of position (finite differences at an interior time)
    t, h = 0.37 * T, 1e-6
    fd = (sp(t + h)[0][0] - sp(t - h)[0][0]) / (2 * h)
    assert sp(t)[1][0] == pytest.approx(fd, rel=1e-5, abs=1e-6)


def test_force_ramp_is_smooth_and_bounded():
    ramp = ForceRamp(0.2, 1.0, 0.1)
    ts = np.linspace(-0.05, 0.15, 401)
    f = np.array([ramp(t) for t in ts])
    assert f[0] == pytest.approx(0.2) and f[-1] == pytest.approx(1.0)
    assert np.all(np.diff(f) >= -1e-12)  # monotone
    assert ramp(0.05) == pytest.approx(0.6)  # symmetric quintic step
    # zero slope at both ends (C1; the quintic step is C2)
    h = 1e-6
    assert (ramp(h) - ramp(0.0)) / h == pytest.approx(0.0, abs=1e-3)
    assert (ramp(0.1) - ramp(0.1 - h)) / h == pytest.approx(0.0, abs=1e-3)


def test_home_term_pulls_the_object_back_over_the_hand(nlp):
    """The objective's home term: a plan asked to end at x = -5 mm ends left of one asked to
    end at +5 mm (the object impedance then rolls it back along the palm)."""
    q0, c, beta = _start()
    left = nlp.solve(q0, c, R, r, 0.8, beta, 0.0, warm=False, home_x=-0.005)
    right = nlp.solve(q0, c, R, r, 0.8, beta, 0.0, warm=False, home_x=0.005)
    assert left.success and right.success
    assert left.centre[-1, 0] < right.centre[-1, 0] - 1e-3


@given(
    st.floats(-1, 1), st.floats(-1, 1), st.floats(-2, 2), st.floats(0.05, 3.0),
    st.floats(-0.5, 3.5),
)  # fmt: skip
@settings(max_examples=60, deadline=None, derandomize=True)
def test_scalar_quintic_equals_the_vector_one(x0, x1, v0, T, t):
    s = QuinticSpline.between([x0], [x1], T, v0=[v0])
    p, v, a = s(t)
    ps, vs, as_ = s.scalar()(t)
    assert isinstance(ps, float)
    assert ps == pytest.approx(float(p[0]), abs=1e-12)
    assert vs == pytest.approx(float(v[0]), abs=1e-9)
    assert as_ == pytest.approx(float(a[0]), abs=1e-8)


def test_scalar_ramp_and_interpolation_equal_numpy():
    from planner.exploration.planar.segments import _interp

    ramp = ForceRamp(0.2, 1.0, 0.08)
    for t in (-0.1, 0.0, 0.03, 0.08, 0.2):
        assert isinstance(ramp(t), float)
        assert ramp(t) == pytest.approx(float(ForceRamp(np.array(0.2), 1.0, 0.08)(t)))
    times = np.array([0.0, 0.1, 0.4, 0.7])
    values = np.random.default_rng(0).normal(size=(4, 3))
    f = _interp(times, values)
    for t in (-0.05, 0.0, 0.05, 0.1, 0.33, 0.7, 0.9):
        v, rate = f(t)
        k = int(np.clip(np.searchsorted(times, t) - 1, 0, 2))
        w = min(max((t - times[k]) / (times[k + 1] - times[k]), 0.0), 1.0)
        np.testing.assert_allclose(v, values[k] + w * (values[k + 1] - values[k]), atol=1e-15)
        inside = times[0] <= t <= times[-1]
        expect = (values[k + 1] - values[k]) / (times[k + 1] - times[k]) if inside else 0.0
        np.testing.assert_allclose(rate, expect, atol=1e-12)


def test_plan_sets_the_object_down_where_it_started(nlp):
    """Phase 1 ends with the object back at its start height (on the palm): a plan that left
    a 3 cm circle 11 mm up let it fall back under the holding finger in phase 2, rolling
    back 14 of its 27 deg."""
    from planner.trajectory.rolling_nlp import SET_DOWN

    q0, c, beta = _start()
    plan = nlp.solve(q0, c, R, r, 0.8, beta, 0.0, warm=False)
    assert plan.success
    assert plan.centre[-1, 1] <= plan.centre[0, 1] + SET_DOWN + 1e-6


@pytest.mark.parametrize("shrink", [0.0, 0.5, 1.2])
def test_a_start_inside_the_joint_margin_is_feasible(nlp, shrink):
    """A start whose closest joint is inside the joint margin band (``shrink`` 1.2: beyond
    the margin-reduced limit as well) plans from where it is: that joint never moves
    further toward its limit, every other keeps the margin (phases 2/3 that end on a
    workspace event leave a joint inside the band)."""
    q0, c, beta = _start()
    lim = HAND.joint_limits
    gap = np.minimum(q0 - lim[:, 0], lim[:, 1] - q0)
    j = int(np.argmin(gap))
    qm = gap[j] / shrink if shrink > 0 else gap[j] + 0.05
    plan = nlp.solve(q0, c, R, r, 0.8, beta, 0.0, warm=False, joint_margin=qm)
    assert plan.success
    lo = np.minimum(lim[:, 0] + qm, q0)
    hi = np.maximum(lim[:, 1] - qm, q0)
    assert np.all(plan.q[1:] >= lo - 1e-6)
    assert np.all(plan.q[1:] <= hi + 1e-6)


def test_constraint_rows_repeat_bounds_over_vector_rows():
    """A vector expression's bounds apply to each of its rows, in the order added."""
    import casadi as cs

    from planner.trajectory.nlp_rows import ConstraintRows

    x = cs.SX.sym("x", 3)
    rows = ConstraintRows()
    rows.add(x[0], -1.0, 2.0)
    rows.add(x[1:3], 0.0, cs.inf)
    rows.add(x[0] + x[2], 5.0, 5.0)
    lo, hi = rows.bounds()
    assert lo.tolist() == [-1.0, 0.0, 0.0, 5.0]
    assert hi.tolist() == [2.0, float("inf"), float("inf"), 5.0]
    assert int(cs.vertcat(*rows.g).shape[0]) == 4


def test_tip_frames_match_the_hand_forward_kinematics():
    """The CasADi fingertip frames equal the hand's own forward kinematics."""
    import numpy as np

    from planner.trajectory.nlp_rows import tip_frames
    from robots.planar_hand import PlanarHand

    hand = PlanarHand()
    fk = tip_frames(hand)
    q = np.array([0.3, 0.6, 0.4, -0.2, 0.7, 0.5])
    pL, phiL, pR, phiR = (np.asarray(v, float).ravel() for v in fk(q))
    for side, p, phi in (("left", pL, phiL), ("right", pR, phiR)):
        ref = hand.fingertip_pose(q, side)
        assert np.allclose(p, ref.position, rtol=0, atol=1e-12), side
        assert abs(phi[0] - ref.angle) <= 1e-12, side


def _round_left_hand(radius=0.025):
    from robots.planar_hand.params import gait_hand_params

    return PlanarHand(gait_hand_params(1.0, left_tip_radius=radius))


@pytest.mark.parametrize("rL", [0.025, 0.015])
def test_a_round_left_tip_rolls_by_eq_2_4(rL):
    """A round left tip: its centre on the circle of radius R + r_L, its contact arclength
    ``u = r_L (beta + pi/2 - phi)`` (from the apex), and pure rolling on both tips."""
    from planner.exploration.planar.heuristics import start_grasp_candidates
    from planner.exploration.planar.sensing import round_contact_arclength

    hand = _round_left_hand(rL)
    c = np.array([0.0, R])
    bl, br, q0, _ = start_grasp_candidates(hand, c, R, 0.8)[0]
    u0 = round_contact_arclength(bl, q0[:3].sum(), rL)
    plan = RollingNLP(hand, knots=6).solve(q0, c, R, r, 0.8, np.array([bl, br]), u0)
    assert plan.success
    assert plan.rotation < -math.radians(10)
    for k in range(len(plan.theta)):
        tip = hand.fingertip_pose(plan.q[k], "left")
        b = plan.beta[k, 0]
        assert np.linalg.norm(tip.position - plan.centre[k]) == pytest.approx(R + rL, abs=1e-6)
        assert math.atan2(*(plan.centre[k] - tip.position)[::-1]) == pytest.approx(
            math.remainder(b + math.pi, 2 * math.pi), abs=1e-5
        )
        assert plan.u[k] == pytest.approx(round_contact_arclength(b, tip.angle, rL), abs=1e-7)
    obj_L = R * ((plan.beta[:, 0] - plan.theta) - plan.beta[0, 0])
    np.testing.assert_allclose(obj_L + (plan.u - plan.u[0]), 0.0, atol=1e-7)
