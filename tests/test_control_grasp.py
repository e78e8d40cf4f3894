"""Tests of the planar grasp controllers: kinematics vs Pinocchio and finite differences,
control laws against closed forms, and the compiled step against the reference step."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.control.fingertip_impedance import fingertip_force
from planner.control.grasp_layout import N_PAR, N_REF, PAR, REF, pack
from planner.control.internal_force import (
    InternalForceGains,
    InternalForcePI,
    sensed_internal_force,
)
from planner.control.object_impedance import (
    ObjectImpedanceGains,
    object_twist_two_contacts,
    object_wrench,
)
from planner.control.rolling_pd import (
    RollingGains,
    contact_arclength,
    contact_offset,
    rolling_moment,
)
from planner.errors import InvalidParameter
from robots.planar_hand import PlanarHand

HAND = PlanarHand()


def _rot(a, v):
    return np.array(
        [math.cos(a) * v[0] - math.sin(a) * v[1], math.sin(a) * v[0] + math.cos(a) * v[1]]
    )


def _grasp_inputs(mode=(1, 0, 0), seed=0):
    """A reachable grasp of a 5 cm ball at (0, 0.065) with small random joint rates."""
    R, c = 0.05, np.array([0.0, 0.065])
    nL = np.array([math.cos(math.radians(140)), math.sin(math.radians(140))])
    qL = HAND.inverse_kinematics("left", c + R * nL, angle=math.atan2(nL[0], -nL[1]))
    nR = np.array([math.cos(math.radians(30)), math.sin(math.radians(30))])
    qR = HAND.inverse_kinematics("right", c + (R + 0.025) * nR)
    q = np.r_[qL, qR]
    offR = _rot(-q[3:].sum(), -nR) * 0.025
    geo = np.r_[0.0, 0.0, offR, 0.0, 1.0, offR / 0.025]
    rng = np.random.default_rng(seed)
    qd = rng.normal(scale=0.05, size=6)
    ref = pack(
        {
            "x_des": [0.002, 0.068, 0.05], "xd_des": [0, 0, 0.1], "xdd_des": [0.1, 0, 0.2],
            "rho": [R, R], "f_int": 1.0, "m_roll": [0.001, -0.002], "p_des": [0.06, 0.1],
            "v_des": [0.0, 0.01], "phi_des": [-1.9, 1.0], "palm": [0.0, 0.015], "flags": mode,
            "p_hold": [-0.037, 0.098],
        },
        REF, N_REF,
    )  # fmt: skip
    par = pack(
        {
            "kp": [60, 60, 0.6], "kv": [4, 4, 0.02], "mass": 0.05, "inertia": 1e-4,
            "gravity": [0, -9.81], "mu": 0.8, "f_min": 0.1, "tau_max": 2.0, "kp_tip": 40,
            "kv_tip": 2, "f_n_tip": 0.3, "k_phi": 0.2, "d_phi": 0.01, "w_wrench": 1.0,
            "w_int": 1.0, "w_track": 1.0, "w_reg": 1e-4,
        },
        PAR, N_PAR,
    )  # fmt: skip
    return q, qd, geo, ref, par


@pytest.fixture(scope="module")
def step():
    from planner.control.grasp_step import GraspStep

    return GraspStep(HAND)


def _sx_terms():
    import casadi as cs

    from planner.control.grasp_kinematics import finger_terms_sx

    q, qd, off, g = (cs.SX.sym(n, k) for n, k in (("q", 6), ("qd", 6), ("o", 4), ("g", 2)))
    T = finger_terms_sx(HAND.model, q, qd, off, g)
    outs = []
    for s in ("left", "right"):
        outs += [T[s]["p"], T[s]["J"], T[s]["Jdqd"]]
    outs += [T["left"]["M"] + T["right"]["M"], T["left"]["g"] + T["right"]["g"]]
    return cs.Function("terms", [q, qd, off, g], outs)


def test_casadi_terms_match_pinocchio():
    from planner.control.grasp_kinematics import numeric_finger_terms

    F = _sx_terms()
    data = HAND.model.createData()
    rng = np.random.default_rng(3)
    for _ in range(5):
        q, qd = rng.uniform(-1, 1, 6), rng.uniform(-1, 1, 6)
        off, g = rng.uniform(-0.02, 0.02, 4), np.array([0.3, -9.81])
        out = [np.asarray(v) for v in F(q, qd, off, g)]
        N = numeric_finger_terms(HAND.model, data, q, qd, off, g)
        for k, s in enumerate(("left", "right")):
            np.testing.assert_allclose(out[3 * k].ravel(), N[s]["p"], atol=1e-12)
            np.testing.assert_allclose(out[3 * k + 1], N[s]["J"], atol=1e-12)
            np.testing.assert_allclose(out[3 * k + 2].ravel(), N[s]["Jdqd"], atol=1e-12)
        np.testing.assert_allclose(out[6], N["hand"]["M"], atol=1e-12)
        np.testing.assert_allclose(out[7].ravel(), N["hand"]["g"], atol=1e-12)


def test_contact_jacobians_finite_differences():
    F = _sx_terms()
    rng = np.random.default_rng(5)
    q, qd, off, g = (
        rng.uniform(-1, 1, 6),
        rng.uniform(-1, 1, 6),
        rng.uniform(-0.02, 0.02, 4),
        [0, -9.81],
    )
    out = [np.asarray(v) for v in F(q, qd, off, g)]
    h = 1e-6
    for k in range(2):
        J = out[3 * k + 1]
        for j in range(6):
            e = np.zeros(6)
            e[j] = h
            dp = (
                np.asarray(F(q + e, qd, off, g)[3 * k]) - np.asarray(F(q - e, qd, off, g)[3 * k])
            ) / (2 * h)
            np.testing.assert_allclose(J[:, j], dp.ravel(), atol=1e-8)
        # Jdot qdot: d/dt (J qdot) along q(t) = q + t qdot
        Jp = np.asarray(F(q + h * qd, qd, off, g)[3 * k + 1])
        Jm = np.asarray(F(q - h * qd, qd, off, g)[3 * k + 1])
        np.testing.assert_allclose(((Jp - Jm) / (2 * h)) @ qd, out[3 * k + 2].ravel(), atol=1e-7)
    # the hand's own numpy Jacobian at a contact offset agrees too
    np.testing.assert_allclose(HAND.jacobian(q, "left", off[:2]), out[1][:, :3], atol=1e-12)


def test_gravity_is_gradient_of_potential():
    F = _sx_terms()
    q = np.array([0.2, -0.5, 0.3, -0.1, 0.7, 0.4])
    g = np.array([0.0, -9.81])
    gq = np.asarray(F(q, np.zeros(6), np.zeros(4), g)[7]).ravel()
    model = HAND.model

    def potential(qq):
        import pinocchio as pin

        d = model.createData()
        pin.forwardKinematics(model, d, qq)
        return sum(
            -model.inertias[j].mass * g @ (d.oMi[j].act(model.inertias[j].lever))[:2]
            for j in range(1, model.njoints)
        )

    h = 1e-6
    fd = [(potential(q + h * e) - potential(q - h * e)) / (2 * h) for e in np.eye(6)]
    np.testing.assert_allclose(gq, fd, atol=1e-8)


def test_object_wrench_closed_forms():
    # at the target, at rest: the wrench only carries the weight (eq. 2.7 gravity term)
    W = object_wrench(
        [0, 0, 0], [0, 0, 0], [0, 0, 0], [0] * 3, [0] * 3, 0.2, 1e-3, [0, -9.81], [50] * 3, [2] * 3
    )
    np.testing.assert_allclose(W, [0, 0.2 * 9.81, 0])
    W = object_wrench(
        [0, 0, 0],
        [0, 0, 0],
        [0.01, 0, 0.1],
        [0] * 3,
        [0, 0, 2.0],
        0.0,
        1e-3,
        [0, 0],
        [50, 50, 0.5],
        [2] * 3,
    )
    np.testing.assert_allclose(W, [0.5, 0.0, 0.05 + 2e-3])
    with pytest.raises(InvalidParameter, match="kp"):
        ObjectImpedanceGains(kp=(1.0, -1.0, 0.0))


@settings(max_examples=50, deadline=None, derandomize=True)
@given(
    st.floats(-1, 1), st.floats(-1, 1), st.floats(-5, 5),
    st.floats(-0.1, 0.1), st.floats(-0.1, 0.1), st.floats(0.0, 6.28),
)  # fmt: skip
def test_object_twist_recovers_rigid_motion(vx, vy, w, cx, cy, a):
    c = np.array([cx, cy])
    p1 = c + 0.05 * np.array([math.cos(a), math.sin(a)])
    p2 = c - 0.04 * np.array([math.cos(a + 0.3), math.sin(a + 0.3)])

    def vel(p):
        r = p - c
        return np.array([vx - w * r[1], vy + w * r[0]])

    tw = object_twist_two_contacts(p1, p2, vel(p1), vel(p2), c)
    np.testing.assert_allclose(tw, [vx, vy, w], atol=1e-9)


def test_internal_force_is_smaller_squeeze():
    p1, p2 = np.array([0.0, 0.0]), np.array([0.1, 0.0])
    assert sensed_internal_force(p1, p2, [2.0, 0.5], [-1.5, 0.3]) == pytest.approx(1.5)
    assert sensed_internal_force(p1, p1, [2.0, 0.5], [-1.5, 0.3]) == 0.0
    pi = InternalForcePI(InternalForceGains(kp=0.0, ki=10.0, max_correction=0.5))
    for _ in range(1000):  # a persistent deficit winds the integral up to its clamp only
        cmd = pi.command(1.0, 0.0, 1e-3)
    assert cmd == pytest.approx(1.5)
    assert pi.integral == pytest.approx(0.5)


def test_rolling_pd_sign_and_offsets():
    g = RollingGains(kp=1.0, kv=0.0, max_moment=10.0)
    # contact behind its command (s < s_des): roll clockwise (negative moment), ds = -dphi/k
    assert rolling_moment(0.0, 0.0, 0.01, 0.0, g) < 0
    for tip in ("round", "flat"):
        for s in (-0.01, 0.0, 0.013):
            ox, oy = contact_offset(s, tip, 0.025)
            assert contact_arclength(ox, oy, tip, 0.025) == pytest.approx(s)
    assert contact_offset(0.0, "round", 0.025) == pytest.approx((0.0, 0.025))


def test_fingertip_force_has_commanded_normal_component():
    n = np.array([0.6, -0.8])
    f = fingertip_force([0, 0], [0, 0], [0.01, 0.02], [0, 0], n, 0.3, 40.0, 2.0)
    assert np.dot(f, n) == pytest.approx(0.3)
    e = 40.0 * np.array([0.01, 0.02])
    assert n[0] * f[1] - n[1] * f[0] == pytest.approx(n[0] * e[1] - n[1] * e[0])


@pytest.mark.parametrize("mode", [(1, 0, 0), (0, 0, 1), (0, 1, 0)])
def test_compiled_step_matches_reference(step, mode):
    from planner.control.grasp_reference import reference_step

    q, qd, geo, ref, par = _grasp_inputs(mode)
    step.q[:], step.qd[:], step.geo[:], step.ref[:], step.par[:] = q, qd, geo, ref, par
    tau = step().copy()
    assert step.flag == 1
    out = reference_step(HAND.model, HAND.model.createData(), q, qd, geo, ref, par)
    assert out["ok"]
    np.testing.assert_allclose(step.forces, out["forces"], atol=1e-7)
    np.testing.assert_allclose(tau, out["tau"], atol=1e-7)


def test_step_forces_satisfy_constraints(step):
    q, qd, geo, ref, par = _grasp_inputs((1, 0, 0), seed=2)
    step.q[:], step.qd[:], step.geo[:], step.ref[:], step.par[:] = q, qd, geo, ref, par
    tau = step()
    f = step.forces.reshape(2, 2)
    n = step.diag[4:8].reshape(2, 2)
    mu = par[PAR["mu"]][0]
    for k in range(2):
        fn = f[k] @ n[k]
        ft = abs(f[k] @ np.array([-n[k][1], n[k][0]]))
        assert fn >= par[PAR["f_min"]][0] - 1e-7
        assert ft <= mu * fn + 1e-7
    assert np.all(np.abs(tau) <= par[PAR["tau_max"]][0] + 1e-7)
    # the commanded squeeze shows up along the contact line
    p = step.diag[0:4].reshape(2, 2)
    assert sensed_internal_force(p[0], p[1], f[0], f[1]) > 0.5
