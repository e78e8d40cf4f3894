"""The hybrid force/velocity law of §4.3 in plain numpy: the reference for the compiled step.

Same equations, same state layout as :func:`planner.control.hybrid_kernel.hybrid_step`, written
with the library's readable building blocks (:class:`robots.sensors.OWTS`,
:meth:`robots.three_gm.ThreeGM.forward_kinematics_and_jacobian`,
:mod:`planner.control.hybrid_frames`). The tests check that both give the same torques; the
benchmark times both in the same run.
"""

from __future__ import annotations

import numpy as np

from planner.control import hybrid_kernel as hk
from planner.control.hybrid_frames import filter_normal, gain_matrix, surface_frame, tcs_rotation

__all__ = [
    "gravity_torque",
    "reference_closed_loop_step",
    "reference_normal_force_pi",
    "reference_step",
]


def gravity_torque(finger, theta: np.ndarray, par: np.ndarray) -> np.ndarray:
    """Gravity compensation τ_g (3,) [N m]: ∇V of the weights in ``par`` plus eq. C.11.

    ``V = Σ m_i g z_i(θ)`` over the centres of mass of the bodies on theta1, gamma1, theta2,
    gamma2 (``z = z_joint + c_x sin a + c_y cos a`` for a body at absolute angle ``a``) and an
    extra tip mass; the passive-angle derivatives follow from the loop closure (``∂γ1/∂θ`` as
    in the corrected eq. C.8; ``∂γ2/∂θ`` by projecting the closure on u(γ1)).
    """
    p = finger.params
    st = finger.state(theta)
    t1, t2 = theta[0], theta[1]
    g1, g2 = st.gamma1, st.gamma2
    l1, l2, l3, l4, l5 = (p[k] for k in ("l1", "l2", "l3", "l4", "l5"))
    d1 = np.array([l1 * np.sin(t1 - g2), l2 * np.sin(g2 - t2)]) / (l4 * np.sin(g2 - g1))
    d2 = np.array([l1 * np.sin(g1 - t1), -l2 * np.sin(g1 - t2)]) / (l3 * np.sin(g1 - g2))
    w1, w5, w2, w3, wt = par[hk.P_G1 : hk.P_GT + 1]
    c = par[hk.P_C1X : hk.P_C3Y + 1].reshape(4, 2)

    def dz(k: int, a: float) -> float:  # d z_com / d a of body k at absolute angle a
        return c[k, 0] * np.cos(a) - c[k, 1] * np.sin(a)

    dz_p1 = np.array([l1 * np.cos(t1), 0.0])
    tg = (
        w1 * np.array([dz(0, t1), 0.0])
        + w5 * (dz_p1 + dz(1, g1) * d1)
        + w2 * np.array([0.0, dz(2, t2)])
        + w3 * (np.array([0.0, l2 * np.cos(t2)]) + dz(3, g2) * d2)
        + wt * (dz_p1 + l5 * np.cos(g1) * d1)
    )
    tg[0] += par[hk.P_GC11] * l5 * np.cos(t1)
    return np.array([tg[0], tg[1], 0.0])


def _saturate(jtf: np.ndarray, tg: np.ndarray, lim: np.ndarray) -> tuple[np.ndarray, float]:
    room = lim - np.abs(tg)
    if np.any(room <= 0):
        scale = 0.0
    else:
        ratio = np.where(np.abs(jtf) > room, room / np.maximum(np.abs(jtf), 1e-300), 1.0)
        scale = float(min(1.0, ratio.min()))
    return np.clip(tg + scale * jtf, -lim, lim), scale


def reference_step(finger, owts, theta, thd, volts, state, target, par) -> np.ndarray:
    """One servo period of the law (numpy); updates ``state`` and returns τ (3,) [N m]."""
    theta = np.asarray(theta, float)
    _, n_t = owts.contact_from_voltages(volts)
    x_f, J = finger.forward_kinematics_and_jacobian(theta)
    r_wt = tcs_rotation(finger.state(theta).gamma1, theta[2])  # eq. 4.1 corrected
    n_w = filter_normal(state[:3], n_t, r_wt, par[hk.P_ALPHA])  # eq. 4.2
    state[:3] = n_w
    r_ws, _ = surface_frame(-n_w)  # eqs. 4.3-4.4
    x = x_f + par[hk.P_RTIP] * n_w  # eq. 4.7
    xdot = J @ thd  # eq. C.10
    w = par[hk.P_RATE]
    dv = target - state[6:9]
    dmax = par[hk.P_RAMP] / w
    if np.linalg.norm(dv) > dmax:
        dv *= dmax / np.linalg.norm(dv)
    state[6:9] += dv  # linear ramp
    v_t = state[6:9] - (state[6:9] @ n_w) * n_w
    state[9:12] = v_t
    state[3:6] += v_t / w  # eq. 4.9
    e = state[3:6] - x
    e_s = r_ws.T @ e
    emax = par[hk.P_EMAX]
    et = np.linalg.norm(e_s[:2])
    if et > emax:
        e_s[:2] *= emax / et
        state[3:6] = x + r_ws @ e_s
        e = r_ws @ e_s
    kp_w = gain_matrix(r_ws, par[hk.P_KP])  # eqs. 4.10-4.11
    kv_w = gain_matrix(r_ws, par[hk.P_KV])
    f = kp_w @ e + kv_w @ (v_t - xdot) + par[hk.P_FN] * n_w  # eqs. 4.8, 4.12, 4.13
    tg = gravity_torque(finger, theta, par)
    tau, _ = _saturate(J.T @ f, tg, par[hk.P_TAU1 : hk.P_TAU3 + 1])
    return tau


def reference_normal_force_pi(force, volts, state, fstate, fpar, par, saturated: bool) -> float:
    """:func:`planner.control.hybrid_kernel.normal_force_pi` in numpy: the PI's command [N]."""
    fd = par[hk.P_FN]
    meas = float(np.dot(force, state[:3]))
    fstate[hk.S_MEAS] = meas
    if float(np.sum(volts)) <= par[hk.P_OWTS_THR]:  # no contact: reset, press with f_des
        fstate[hk.S_INT] = 0.0
        return float(fd)
    e = fd - meas
    if not saturated:
        lim = fpar[hk.F_IMAX]
        fstate[hk.S_INT] = np.clip(fstate[hk.S_INT] + e / par[hk.P_RATE], -lim, lim)
    cmd = fd + fpar[hk.F_KP] * e + fpar[hk.F_KI] * fstate[hk.S_INT]
    return float(np.clip(cmd, 0.0, fpar[hk.F_FMAX]))


def reference_closed_loop_step(
    finger, owts, theta, thd, volts, force, state, fstate, target, par, fpar, saturated
) -> np.ndarray:
    """The closed-loop variant in numpy: the PI's command, then :func:`reference_step`."""
    p = par.copy()
    p[hk.P_FN] = reference_normal_force_pi(force, volts, state, fstate, fpar, par, saturated)
    return reference_step(finger, owts, theta, thd, volts, state, target, p)
