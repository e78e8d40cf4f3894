"""The phase-1 squeeze that carries the object off the palm (planar/carry_squeeze.py)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.exploration.planar.carry_squeeze import (
    carrying_squeeze,
    phase1_squeeze,
    symmetric_squeeze,
)
from planner.exploration.planar.settings import GaitSettings


def _one_parameter(beta_left: float, beta_right: float, mu: float, load: float) -> float:
    """The same minimum without an LP: the grasp has one free parameter, the left
    tangential force ``T`` (the right one is ``-T``: no moment about the centre); the force
    balance gives the normal forces as affine functions of ``T`` (a 2 x 2 solve), the cones
    an interval of ``T``, and the (concave) objective is smallest at one of its ends."""
    nL = -np.array([math.cos(beta_left), math.sin(beta_left)])
    nR = -np.array([math.cos(beta_right), math.sin(beta_right)])
    tL = np.array([nL[1], -nL[0]])  # counter-clockwise tangent (-sin, cos)
    tR = np.array([nR[1], -nR[0]])
    u = nL - nR  # from the left contact (-nL) to the right one (-nR)
    u = u / np.linalg.norm(u)
    A = np.column_stack([nL, nR])
    N0 = np.linalg.solve(A, np.array([0.0, load]))
    N1 = np.linalg.solve(A, tR - tL)  # N(T) = N0 + T N1
    lo, hi = -math.inf, math.inf
    for i in range(2):  # +-T <= mu (N0_i + T N1_i)  <=>  (+-1 - mu N1_i) T <= mu N0_i
        for sgn in (1.0, -1.0):
            a, b = sgn - mu * N1[i], mu * N0[i]
            if abs(a) < 1e-15:
                if b < 0:
                    return math.inf
            elif a > 0:
                hi = min(hi, b / a)
            else:
                lo = max(lo, b / a)
    ends = [T for T in (lo, hi) if math.isfinite(T)]  # more squeeze is always feasible
    if lo > hi or not ends:
        return math.inf

    def objective(T: float) -> float:
        NL, NR = N0 + T * N1
        fL, fR = NL * nL + T * tL, NR * nR - T * tR
        return min(fL @ u, -(fR @ u))

    return max(min(objective(T) for T in ends), 0.0)


def test_horizontal_contacts_need_the_classic_two_finger_hold():
    # each finger carries W/2 by friction: squeeze W / (2 mu)
    W, mu = 0.49, 0.8
    assert carrying_squeeze(math.pi, 0.0, mu, W) == pytest.approx(W / (2 * mu), rel=1e-9)
    assert symmetric_squeeze(0.0, mu, W) == pytest.approx(W / (2 * mu), rel=1e-12)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(alpha=st.floats(-1.2, 0.6), mu=st.floats(0.3, 1.5), load=st.floats(0.01, 3.0))
def test_symmetric_grasps_match_the_closed_form(alpha, mu, load):
    want = symmetric_squeeze(alpha, mu, load)
    got = carrying_squeeze(math.pi - alpha, alpha, mu, load)
    if math.isinf(want):
        assert math.isinf(got)
    else:
        assert got == pytest.approx(want, rel=1e-7, abs=1e-9)


def test_contacts_beyond_the_cone_cannot_carry():
    # alpha above atan(mu): the contact line leaves the cones, no squeeze holds the load
    mu = 0.8
    a = math.atan(mu) + 0.05
    assert math.isinf(symmetric_squeeze(a, mu, 0.5))
    assert math.isinf(carrying_squeeze(math.pi - a, a, mu, 0.5))


@pytest.mark.parametrize(
    "bl, br", [(150.1, 21.1), (129.3, 9.4), (144.7, 0.4), (160.0, -15.0), (135.0, 30.0)]
)
def test_asymmetric_grasps_match_the_one_parameter_solution(bl, br):
    bl, br = math.radians(bl), math.radians(br)
    got = carrying_squeeze(bl, br, 0.8, 0.61)
    assert got == pytest.approx(_one_parameter(bl, br, 0.8, 0.61), rel=1e-7)


@settings(max_examples=30, deadline=None, derandomize=True)
@given(bl=st.floats(2.2, 3.0), br=st.floats(-0.3, 0.5), k=st.floats(0.1, 10.0))
def test_the_squeeze_scales_with_the_load(bl, br, k):
    base = carrying_squeeze(bl, br, 0.8, 0.5)
    if math.isinf(base):
        return
    assert carrying_squeeze(bl, br, 0.8, k * 0.5) == pytest.approx(k * base, rel=1e-6, abs=1e-9)


def test_higher_contacts_need_more_squeeze():
    # contacts moving up the circle lean the load further onto friction
    needs = [symmetric_squeeze(math.radians(a), 0.8, 0.5) for a in (0, 10, 20, 30)]
    assert all(b > a for a, b in zip(needs, needs[1:], strict=False))


def test_phase1_squeeze_floors_raises_and_caps():
    s = GaitSettings()
    load = s.object_mass * s.gravity
    mu = s.mu * (1 - s.friction_margin)
    low = np.radians([[180.0, 0.0], [178.0, -2.0]])  # needs W / (2 mu) ~ 0.31 N
    assert phase1_squeeze(low, s, 0.0) == s.internal_force
    high = np.radians([[150.1, 21.1], [129.3, 9.4]])
    need = max(carrying_squeeze(*row, mu, load) for row in high)
    assert need > s.internal_force
    assert phase1_squeeze(high, s, 0.0) == pytest.approx((1 + s.carry_margin) * need)
    lifted = s.object_kp[1] * 0.002
    need_lift = max(carrying_squeeze(*row, mu, load + lifted) for row in high)
    assert phase1_squeeze(high, s, 0.002) == pytest.approx((1 + s.carry_margin) * need_lift)
    capped = dataclasses.replace(s, max_squeeze=1.5)
    assert phase1_squeeze(high, capped, 0.0) == 1.5
    beyond = np.radians([[120.0, 60.0]])  # outside the cones: the cap
    assert phase1_squeeze(beyond, s, 0.0) == s.max_squeeze


def test_bad_arguments_raise():
    with pytest.raises(InvalidParameter, match="mu"):
        carrying_squeeze(math.pi, 0.0, 0.0, 1.0)
    with pytest.raises(InvalidParameter, match="load"):
        carrying_squeeze(math.pi, 0.0, 0.8, -1.0)
    with pytest.raises(InvalidParameter, match="carry_margin"):
        GaitSettings(carry_margin=-0.1)
    with pytest.raises(InvalidParameter, match="max_squeeze"):
        GaitSettings(max_squeeze=0.0)
