"""Hybrid force/velocity law (thesis §4.3): frames, filter, ramp, Jacobian, gravity, torques."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.control import hybrid_kernel as hk
from planner.control.hybrid_frames import (
    SWITCH_SIN2,
    filter_normal,
    gain_matrix,
    surface_frame,
    tcs_rotation,
)
from planner.control.hybrid_law import (
    HybridController,
    HybridSettings,
    check_force_feasible,
    force_parameters,
    kernel_parameters,
)
from planner.control.hybrid_reference import (
    gravity_torque,
    reference_closed_loop_step,
    reference_step,
)
from planner.control.hybrid_variants import TorqueLimitQP
from planner.errors import InvalidParameter
from robots.sensors import OWTS
from robots.three_gm import ThreeGM, rotation_tcs_to_wcs
from robots.three_gm.model import configuration

FINGER = ThreeGM()
CENTER = FINGER.center_theta


def _random_thetas(n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        th = CENTER + rng.uniform(-0.35, 0.35, 3)
        try:
            FINGER.jacobian(th)
        except Exception:
            continue
        out.append(th)
    return np.array(out)


unit3 = st.tuples(*[st.floats(-1, 1)] * 3).map(np.array).filter(lambda v: np.linalg.norm(v) > 0.1)


# ---------------------------------------------------------------- eq. 4.1 corrected
def test_tcs_pole_follows_the_distal_link_like_pinocchio():
    model = FINGER.model
    data = model.createData()
    fid = model.getFrameId("endpoint")
    for th in _random_thetas(20):
        s = FINGER.state(th)
        R = tcs_rotation(s.gamma1, th[2])
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
        assert np.linalg.det(R) == pytest.approx(1.0)
        pin.framesForwardKinematics(model, data, configuration(th, s.gamma1, s.gamma2))
        np.testing.assert_allclose(R[:, 2], data.oMf[fid].rotation[:, 0], atol=1e-12)


def test_printed_eq_4_1_pole_is_horizontal_at_the_workspace_centre():
    """The documented disagreement: eq. 4.1 as printed points the pole sideways."""
    s = FINGER.state(CENTER)
    printed = rotation_tcs_to_wcs(s.gamma1, CENTER[2])[:, 2]
    corrected = tcs_rotation(s.gamma1, CENTER[2])[:, 2]
    assert abs(printed[2]) < 0.2 and corrected[2] < -0.95


# ---------------------------------------------------------------- eq. 4.2
def test_filter_no_contact_uses_the_tcs_z_axis():
    R = tcs_rotation(-1.4, 0.1)
    n = R[:, 2].copy()
    out = filter_normal(n, np.zeros(3), R)
    np.testing.assert_allclose(out, R[:, 2], atol=1e-12)


def test_filter_is_a_first_order_low_pass_to_the_measurement():
    R = tcs_rotation(-1.4, 0.1)
    meas = np.array([0.3, 0.0, np.sqrt(1 - 0.09)])
    n = R[:, 2].copy()
    for _ in range(200):
        n = filter_normal(n, meas, R, alpha=0.05)
        assert np.linalg.norm(n) == pytest.approx(1.0)
    np.testing.assert_allclose(n, R @ meas, atol=1e-4)
    with pytest.raises(InvalidParameter, match="alpha"):
        filter_normal(n, meas, R, alpha=0.0)


# ---------------------------------------------------------------- eqs. 4.3-4.4, 4.10-4.11
@settings(max_examples=200, deadline=None, derandomize=True)
@given(unit3)
def test_surface_frame_orthonormal_and_gain_independent_of_frame(z):
    z = z / np.linalg.norm(z)
    R, _ = surface_frame(z)
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-12)
    assert np.linalg.det(R) == pytest.approx(1.0)
    np.testing.assert_allclose(R[:, 2], z, atol=1e-12)
    K = gain_matrix(R, 7.0)
    np.testing.assert_allclose(K, 7.0 * (np.eye(3) - np.outer(z, z)), atol=1e-12)


@settings(max_examples=100, deadline=None, derandomize=True)
@given(st.floats(0, 2 * np.pi), st.floats(-1, 1))
def test_gains_continuous_across_the_singular_switch(phi, side):
    """Just inside and outside the switch cone the frames differ, the law does not."""
    s = np.sqrt(SWITCH_SIN2)
    eps = 1e-7
    zs = []
    for rad in (s - eps, s + eps):
        zs.append(np.array([rad * np.cos(phi), np.sign(side or 1) * np.sqrt(1 - rad**2), 0.0]))
        zs[-1][2] = rad * np.sin(phi)
    (Ra, alt_a), (Rb, alt_b) = surface_frame(zs[0]), surface_frame(zs[1])
    assert alt_a and not alt_b
    np.testing.assert_allclose(gain_matrix(Ra, 1.0), gain_matrix(Rb, 1.0), atol=1e-6)


def test_frame_at_the_printed_singularity_uses_the_alternative():
    R, alt = surface_frame(np.array([0.0, 1.0, 0.0]))
    assert alt and np.all(np.isfinite(R))
    R, alt = surface_frame(np.array([0.0, 0.0, 1.0]))
    assert not alt
    np.testing.assert_allclose(R[:, 0], [1.0, 0.0, 0.0], atol=1e-12)  # x_S in the x-z plane


# ---------------------------------------------------------------- kernel: Jacobian, gravity
def _kernel(th, thd, volts=None, target=None, state=None, settings_=None):
    s = settings_ or HybridSettings()
    par = kernel_parameters(FINGER, s)
    stt = np.zeros(12) if state is None else state
    if not stt[:3].any():
        stt[:3] = tcs_rotation(FINGER.state(th).gamma1, th[2])[:, 2]
    out = np.zeros(hk.NOUT)
    hk.hybrid_step(
        np.asarray(th, float),
        np.asarray(thd, float),
        np.zeros(4) if volts is None else volts,
        stt,
        np.zeros(3) if target is None else target,
        par,
        out,
    )
    return out, stt, par


def test_kernel_jacobian_matches_finite_differences():
    h = 1e-6
    for th in _random_thetas(10, seed=1):
        J_fd = np.empty((3, 3))
        J_k = np.empty((3, 3))
        for i in range(3):
            e = np.zeros(3)
            e[i] = h
            J_fd[:, i] = (
                _kernel(th + e, np.zeros(3))[0][6:9] - _kernel(th - e, np.zeros(3))[0][6:9]
            ) / (2 * h)
            J_k[:, i] = _kernel(th, np.eye(3)[i])[0][9:12]
        np.testing.assert_allclose(J_k, J_fd, atol=1e-7)
        np.testing.assert_allclose(_kernel(th, np.zeros(3))[0][6:9], FINGER.forward_kinematics(th))


def _potential(th, par):
    p = FINGER.params
    s = FINGER.state(th)
    w1, w5, w2, w3, wt = par[hk.P_G1 : hk.P_GT + 1]
    c = par[hk.P_C1X : hk.P_C3Y + 1].reshape(4, 2)

    def z(k, a):
        return c[k, 0] * np.sin(a) + c[k, 1] * np.cos(a)

    zp1 = p["l1"] * np.sin(th[0])
    return (
        w1 * z(0, th[0])
        + w5 * (zp1 + z(1, s.gamma1))
        + w2 * (-p["h1"] + z(2, th[1]))
        + w3 * (-p["h1"] + p["l2"] * np.sin(th[1]) + z(3, s.gamma2))
        + wt * (zp1 + p["l5"] * np.sin(s.gamma1))
    )


def test_gravity_torque_is_the_gradient_of_the_potential_and_matches_pinocchio():
    par = kernel_parameters(FINGER, HybridSettings(tip_mass=0.0))
    assert par[hk.P_G5] > 0.3  # the distal link carries the fingertip
    model = FINGER.model
    data = model.createData()
    model.gravity.linear = np.array([0.0, 0.0, -9.81])
    h = 1e-6
    for th in _random_thetas(8, seed=2):
        grad = np.array(
            [
                (_potential(th + h * e, par) - _potential(th - h * e, par)) / (2 * h)
                for e in np.eye(3)
            ]
        )
        tg = gravity_torque(FINGER, th, par)
        np.testing.assert_allclose(tg, grad, atol=1e-7)
        # Pinocchio: tree gravity projected through the loop closure, tau = dq/dtheta^T g(q)
        s = FINGER.state(th)
        q = configuration(th, s.gamma1, s.gamma2)
        g_tree = pin.computeGeneralizedGravity(model, data, q)
        dq = np.empty((5, 3))
        for i, e in enumerate(np.eye(3)):
            sp, sm = FINGER.state(th + h * e), FINGER.state(th - h * e)
            dq[:, i] = (
                configuration(th + h * e, sp.gamma1, sp.gamma2)
                - configuration(th - h * e, sm.gamma1, sm.gamma2)
            ) / (2 * h)
        np.testing.assert_allclose(tg, dq.T @ g_tree, atol=1e-6)
        out, _, _ = _kernel(th, np.zeros(3), settings_=HybridSettings(tip_mass=0.0, kp=0, kv=0))
        fn_tau = FINGER.jacobian(th).T @ (0.3 * tcs_rotation(s.gamma1, th[2])[:, 2])
        np.testing.assert_allclose(out[:3], tg + fn_tau, atol=1e-9)


# ---------------------------------------------------------------- kernel == numpy reference
def test_kernel_equals_numpy_reference_over_a_random_run():
    rng = np.random.default_rng(3)
    owts = OWTS(radius=0.008)
    s = HybridSettings(kp=200.0, kv=3.0, normal_force=0.4, max_error=0.002)
    par = kernel_parameters(FINGER, s, owts)
    st_k, st_r = np.zeros(12), np.zeros(12)
    th0 = CENTER
    st_k[:3] = st_r[:3] = tcs_rotation(FINGER.state(th0).gamma1, th0[2])[:, 2]
    st_k[3:6] = st_r[3:6] = FINGER.forward_kinematics(th0) + 0.008 * st_k[:3]
    out = np.zeros(hk.NOUT)
    for k in range(300):
        th = th0 + 0.02 * np.sin(0.01 * k + np.arange(3))
        thd = rng.normal(0, 0.2, 3)
        n = np.array([rng.normal(0, 0.3), rng.normal(0, 0.3), 1.0])
        volts = owts.voltages_from_contact(n) if k % 7 else np.zeros(4)
        target = np.array([0.02, 0.01 * np.cos(0.02 * k), 0.0])
        hk.hybrid_step(th, thd, volts, st_k, target, par, out)
        tau_r = reference_step(FINGER, owts, th, thd, volts, st_r, target, par)
        np.testing.assert_allclose(out[:3], tau_r, atol=1e-10)
        np.testing.assert_allclose(st_k, st_r, atol=1e-12)


# ---------------------------------------------------------------- eq. 4.9 ramp
def test_desired_position_follows_the_ramped_velocity():
    s = HybridSettings(ramp=0.5, rate=1000.0)
    ctl = HybridController(FINGER, s)
    v = np.array([0.02, 0.0, 0.0])
    ctl.command_velocity(v)
    th = CENTER
    ctl.step(th, np.zeros(3), np.zeros(4))
    x0 = ctl.state[3:6].copy() - ctl.state[9:12] / 1000.0
    n = ctl.normal
    vt = v - (v @ n) * n
    expected = np.zeros(3)
    for k in range(1, 101):
        if k > 1:
            ctl.step(th, np.zeros(3), np.zeros(4))
        speed = min(k * 0.5 / 1000.0, 0.02)
        np.testing.assert_allclose(np.linalg.norm(ctl.state[6:9]), speed, rtol=1e-12)
        expected += (min(k * 0.5 / 1000.0, 0.02) / 0.02) * vt / 1000.0
    # ramp of 40 steps to 20 mm/s, then constant: x_des moved by the integral of the ramp
    assert ctl.state[6] == pytest.approx(0.02)
    np.testing.assert_allclose(ctl.state[3:6] - x0, expected, atol=1e-12)


# ---------------------------------------------------------------- limits
def test_torque_limits_flag_saturation_and_keep_gravity():
    ctl = HybridController(FINGER, HybridSettings(normal_force=50.0))
    tau = ctl.step(CENTER, np.zeros(3), np.zeros(4))
    assert ctl.saturated
    assert np.all(np.abs(tau) <= FINGER.torque_limits + 1e-12)
    ok = HybridController(FINGER, HybridSettings(normal_force=0.3))
    ok.step(CENTER, np.zeros(3), np.zeros(4))
    assert not ok.saturated
    with pytest.raises(InvalidParameter, match="normal_force"):
        check_force_feasible(FINGER, CENTER, 20.0)


@pytest.mark.parametrize(
    "kw",
    [{"kp": -1.0}, {"alpha": 0.0}, {"alpha": 1.5}, {"gravity": "full"}, {"tip_radius": 0.0}],
)
def test_settings_reject_bad_values(kw):
    with pytest.raises(InvalidParameter):
        HybridSettings(**kw)


# ---------------------------------------------------------------- appended outputs
def test_appended_outputs_are_the_jacobian_gravity_force_and_frame():
    owts = OWTS(radius=0.008)
    for th in _random_thetas(5, seed=4):
        volts = owts.voltages_from_contact(np.array([0.2, -0.1, 1.0]))
        out, stt, par = _kernel(th, np.full(3, 0.1), volts, np.array([0.01, 0.0, 0.0]))
        np.testing.assert_allclose(out[hk.O_J : hk.O_J + 9].reshape(3, 3), FINGER.jacobian(th))
        tg = gravity_torque(FINGER, th, par)
        np.testing.assert_allclose(out[hk.O_TG : hk.O_TG + 2], tg[:2], atol=1e-12)
        R, _ = surface_frame(-stt[:3])
        np.testing.assert_allclose(out[hk.O_XS : hk.O_XS + 3], R[:, 0], atol=1e-12)
        np.testing.assert_allclose(out[hk.O_YS : hk.O_YS + 3], R[:, 1], atol=1e-12)
        f = out[hk.O_F : hk.O_F + 3]
        assert f @ stt[:3] == pytest.approx(par[hk.P_FN], abs=1e-12)  # eq. 4.12: f_des along n
        assert not out[13]
        np.testing.assert_allclose(out[:3], tg + FINGER.jacobian(th).T @ f, atol=1e-12)


# ---------------------------------------------------------------- closed-loop variant
def _pi(force, volts, fd=0.3, integral=0.0, saturated=False, **kw):
    s = HybridSettings(normal_force=fd, control="closed_loop", **kw)
    par = kernel_parameters(FINGER, s)
    fpar = force_parameters(s)
    state = np.zeros(12)
    state[:3] = [0.0, 0.0, -1.0]
    fstate = np.array([integral, 0.0])
    cmd = hk.normal_force_pi(np.asarray(force, float), volts, state, fstate, fpar, par, saturated)
    return cmd, fstate, s


def test_pi_command_is_f_des_plus_proportional_and_integral_terms():
    on = np.full(4, 1.0)
    # pressing 0.1 N too little along n = -z: the tip force on the surface is (0, 0, -0.2)
    cmd, fst, s = _pi([0.0, 0.0, -0.2], on, integral=0.002)
    assert fst[hk.S_MEAS] == pytest.approx(0.2)
    e = 0.1
    integral = 0.002 + e / s.rate
    assert fst[hk.S_INT] == pytest.approx(integral)
    assert cmd == pytest.approx(0.3 + s.force_kp * e + s.force_ki * integral)
    # no contact: integral reset, open-loop force
    cmd, fst, _ = _pi([0.0, 0.0, -0.2], np.zeros(4), integral=0.002)
    assert cmd == 0.3 and fst[hk.S_INT] == 0.0
    # torque limited at the previous step: the integral is frozen (no wind-up)
    _, fst, _ = _pi([0.0, 0.0, -0.2], on, integral=0.002, saturated=True)
    assert fst[hk.S_INT] == 0.002
    # bounds: integral within +-force_imax, command within [0, force_max]
    cmd, fst, s = _pi([0.0, 0.0, -5.0], on, integral=-0.0099)
    assert fst[hk.S_INT] == -s.force_imax and cmd == 0.0
    cmd, _, s = _pi([0.0, 0.0, 0.0], on, integral=0.01, force_kp=10.0)
    assert cmd == s.force_max == pytest.approx(0.9)


def test_closed_loop_with_zero_gains_is_the_open_loop_law():
    owts = OWTS(radius=0.008)
    s = HybridSettings(control="closed_loop", force_kp=0.0, force_ki=0.0)
    par, fpar = kernel_parameters(FINGER, s, owts), force_parameters(s)
    th = CENTER + 0.05
    volts = owts.voltages_from_contact(np.array([0.1, 0.1, 1.0]))
    a, b = np.zeros(12), np.zeros(12)
    a[:3] = b[:3] = tcs_rotation(FINGER.state(th).gamma1, th[2])[:, 2]
    out_a, out_b = np.zeros(hk.NOUT), np.zeros(hk.NOUT)
    target = np.array([0.01, 0.0, 0.0])
    hk.hybrid_step(th, np.full(3, 0.1), volts, a, target, par, out_a)
    force = np.array([0.3, -0.2, 1.0])
    fst = np.zeros(hk.NFSTATE)
    hk.hybrid_step_closed_loop(th, np.full(3, 0.1), volts, force, b, fst, target, par, fpar, out_b)
    np.testing.assert_array_equal(out_a, out_b)
    np.testing.assert_array_equal(a, b)


def test_closed_loop_kernel_equals_numpy_reference_over_a_random_run():
    rng = np.random.default_rng(5)
    owts = OWTS(radius=0.008)
    s = HybridSettings(normal_force=0.4, control="closed_loop", force_kp=0.3, force_ki=80.0)
    par, fpar = kernel_parameters(FINGER, s, owts), force_parameters(s)
    st_k, st_r = np.zeros(12), np.zeros(12)
    st_k[:3] = st_r[:3] = tcs_rotation(FINGER.state(CENTER).gamma1, CENTER[2])[:, 2]
    st_k[3:6] = st_r[3:6] = FINGER.forward_kinematics(CENTER) + 0.008 * st_k[:3]
    fs_k, fs_r = np.zeros(hk.NFSTATE), np.zeros(hk.NFSTATE)
    out = np.zeros(hk.NOUT)
    for k in range(300):
        th = CENTER + 0.02 * np.sin(0.01 * k + np.arange(3))
        thd = rng.normal(0, 0.2, 3)
        n = np.array([rng.normal(0, 0.3), rng.normal(0, 0.3), 1.0])
        volts = owts.voltages_from_contact(n) if k % 7 else np.zeros(4)
        force = np.array([0.0, 0.0, -0.4]) + rng.normal(0, 0.05, 3)
        target = np.array([0.02, 0.01 * np.cos(0.02 * k), 0.0])
        sat = bool(out[13])
        hk.hybrid_step_closed_loop(th, thd, volts, force, st_k, fs_k, target, par, fpar, out)
        tau_r = reference_closed_loop_step(
            FINGER, owts, th, thd, volts, force, st_r, fs_r, target, par, fpar, sat
        )
        np.testing.assert_allclose(out[:3], tau_r, atol=1e-10)
        np.testing.assert_allclose(fs_k, fs_r, atol=1e-15)
        np.testing.assert_allclose(st_k, st_r, atol=1e-12)


# ---------------------------------------------------------------- QP variant
def _saturated_step(fd=16.0, seed=0):
    owts = OWTS(radius=0.008)
    rng = np.random.default_rng(seed)
    th = _random_thetas(1, seed=seed)[0]
    volts = owts.voltages_from_contact(np.array([*rng.normal(0, 0.2, 2), 1.0]))
    s = HybridSettings(normal_force=fd, control="qp", max_error=0.003)
    out, stt, par = _kernel(th, np.zeros(3), volts, np.array([0.03, 0.0, 0.0]), settings_=s)
    stt[3:6] += 0.003 * out[hk.O_XS : hk.O_XS + 3]  # a tracking error: tangential force too
    out, stt, par = _kernel(th, rng.normal(0, 0.5, 3), volts, None, stt, s)
    return out, stt, s


def _qp_objective(qp, ft, fn, x):
    a, s = x
    return 0.5 * qp.w_t * float(ft @ ft) * (a - 1.0) ** 2 + 0.5 * qp.w_n * (s - fn) ** 2


@pytest.mark.parametrize("seed", range(4))
def test_qp_keeps_the_limits_and_beats_the_uniform_scaling(seed):
    out, stt, s = _saturated_step(seed=seed)
    assert out[13], "the open-loop law must be torque limited here"
    qp = TorqueLimitQP(FINGER.torque_limits, s.qp_weights)
    n = stt[:3]
    ft, fn = qp.split(out, n)
    assert fn == pytest.approx(s.normal_force)  # eq. 4.12: the law asks f_des along n
    np.testing.assert_allclose(ft + fn * n, out[hk.O_F : hk.O_F + 3], atol=1e-12)
    sigma = out[18] / fn  # the law's uniform scale
    tau = qp.solve(out, n)
    assert tau is not None
    assert np.all(np.abs(tau) <= FINGER.torque_limits + 1e-6)
    a, sn = qp.last
    assert -1e-9 <= a <= 1 + 1e-9 and -1e-9 <= sn <= fn + 1e-9  # never beyond the law's asks
    # the uniformly scaled force is feasible for the QP: its optimum is at least as good
    assert _qp_objective(qp, ft, fn, qp.last) <= _qp_objective(qp, ft, fn, (sigma, sigma * fn))
    assert sn >= sigma * fn - 1e-6  # the normal force goes first
    # the same QP through another solver of planner.optim gives the same optimum
    other = TorqueLimitQP(FINGER.torque_limits, s.qp_weights, solver="proxqp")
    other.solve(out, n)
    np.testing.assert_allclose(other.last, qp.last, atol=1e-6)
    tg = np.array([*out[hk.O_TG : hk.O_TG + 2], 0.0])
    J = out[hk.O_J : hk.O_J + 9].reshape(3, 3)
    np.testing.assert_allclose(tau, tg + J.T @ (a * ft + sn * n), atol=1e-9)


def test_qp_variant_is_the_open_loop_law_when_not_saturated():
    owts = OWTS(radius=0.008)
    volts = owts.voltages_from_contact(np.array([0.1, 0.0, 1.0]))
    th = CENTER + 0.03
    a = HybridController(FINGER, HybridSettings(control="qp"))
    b = HybridController(FINGER, HybridSettings())
    for k in range(20):
        ta = a.step(th, np.full(3, 0.01 * k), volts).copy()
        tb = b.step(th, np.full(3, 0.01 * k), volts).copy()
        np.testing.assert_array_equal(ta, tb)
    assert a.qp.solves == 0
    c = HybridController(FINGER, HybridSettings(normal_force=50.0, control="qp"))
    tau = c.step(CENTER, np.zeros(3), volts)
    assert c.saturated and c.qp.solves == 1
    assert np.all(np.abs(tau) <= FINGER.torque_limits + 1e-6)
    assert c.out[18] > 0.0


@pytest.mark.parametrize(
    "kw",
    [{"control": "pid"}, {"force_kp": -1.0}, {"force_imax": -0.1}, {"qp_weights": (0.0, 1.0)}],
)
def test_variant_settings_reject_bad_values(kw):
    with pytest.raises(InvalidParameter):
        HybridSettings(**kw)
