"""The compiled body of the gait's phase loop (:mod:`.gait_loop`): numba kernels.

:func:`gait_advance` is :func:`planner.sim.planar.run_kernel.advance` (mode 2) with the
gait controller's call compiled in (:func:`_gait_call`: what
:meth:`~.controller.GaitController.__call__` does on the observation of
:func:`planner.sim.planar.sensing.observe`, in its order) and the loop's saturation
(:func:`_saturated`), plus the proposal of the :class:`.gait_loop.PhaseStop` check after
every step. The driver, the references and the equality argument are in :mod:`.gait_loop`.
"""

from __future__ import annotations

import math

import numpy as np

from planner.exploration.planar import controller_kernel as ck
from planner.exploration.planar.controller_kernel import REJECTED, gait_kernel
from planner.jit import njit
from planner.sim.planar.run_kernel import (
    BLOW_UP,
    CALL_DUE,
    DONE,
    EV_SAT,
    NEV,
    PYTHON_STEP,
    SAT,
    _contact_events,
    _event,
    _healthy,
    _reading,
    _record,
    _world_events,
)
from planner.sim.planar.sensing import pad_image
from planner.sim.planar.step_kernel import full_step

__all__ = ["N_STOP", "STEP_IN_PYTHON", "STOP_HINT", "gait_advance"]

#: exit code: a stop may be due after the last step (the Python :class:`PhaseStop` decides)
STOP_HINT = 5
#: exit code: the call ran, its step needs the Python fallback (commit the call, step there)
STEP_IN_PYTHON = 6
#: command damping of the fallback (``controller.FALLBACK_DAMPING``) [N m s/rad]
_DAMP = 0.02
# cnt[:] of gait_advance: calls made, fallbacks, images kept, event code, c0 known
C_CALLS, C_FALLBACK, C_IMAGES, C_EVENT, C_C0 = 0, 1, 2, 3, 4
# stop_s[:] of gait_advance: hold_slip [m], number of watched points (1-2), their indices
# in the sensing buffer, their positions after the phase's first step [m]
S_SLIP, S_N, S_INDEX, S_REF = 0, 1, 2, 4
N_STOP = S_REF + 4


@njit(cache=True)
def _gait_call(j, t, n, out, pn, pt, q, qd, kind, index, h, sens, obs, noise, gauge, padg,
               pad, img, geo, taxel_u, buf, sv, sv_rows, ks, inputs, row, ctau, last_tau,
               trace, imgs, img_t, cnt, cmd):  # fmt: skip  # pragma: no cover
    """Controller call ``j`` of the chunk at time ``t`` (:meth:`GaitController.__call__` on
    the observation of the last step): its command into ``cmd``; returns the event code."""
    _reading(q, qd, sens, n, out, pn, pt, kind, index, h, obs)
    forces = np.empty((2, 2))
    for i in range(4):  # sensing._gauges: rint((f + noise) / res) * res
        f = obs[12 + i]
        if gauge[0] == 2.0:
            f = f + noise[j, i // 2, i % 2]
        forces[i // 2, i % 2] = f if gauge[0] == 0.0 else np.rint(f / gauge[1]) * gauge[1]
    has_image = pad[0] != 0.0
    if has_image:
        base, lengths, fu, fv, Bv, BuT = padg
        pad_image(img, 0, out[:n], pn, h, kind, index, q, base, lengths, fu, fv, Bv, BuT,
                  pad[1], pad[2], pad[3])  # fmt: skip
    sv[:] = sv_rows[j]
    code = gait_kernel(obs[:6], obs[6:12], forces, img, has_image, geo, taxel_u, buf, sv, ks,
                       inputs, row, ctau)  # fmt: skip
    if code & REJECTED:
        for i in range(6):
            cmd[i] = last_tau[i] - _DAMP * obs[6 + i]
        cnt[C_FALLBACK] += 1
    else:
        last_tau[:] = ctau
        cmd[:] = ctau
    trace[j] = row
    if has_image and (cnt[5] + j + 1) % 5 == 0:  # cnt[5]: trace rows before the chunk
        imgs[cnt[C_IMAGES]] = img
        img_t[cnt[C_IMAGES]] = t
        cnt[C_IMAGES] += 1
    cnt[C_CALLS] = j + 1
    return code & 7


@njit(cache=True)
def _saturated(cmd, lim, tau_new):
    """The loop's saturation of ``cmd`` into ``tau_new``; returns whether it saturated."""
    over = -np.inf
    for i in range(lim.shape[0]):
        over = max(over, abs(cmd[i]) - lim[i])
    if lim.shape[0] == 0 or over <= 0.0:
        tau_new[:] = cmd
        return False
    for i in range(6):
        tau_new[i] = min(max(cmd[i], -lim[i]), lim[i])
    return True


@njit(cache=True)
def gait_advance(
    n_max, row0, clock, flags, tau, sens, lim, sc, F, I, pairs, poses, kind, index, mu_body,
    x, v, mass, inertia, com, q, qd, P, limits, covers, out, counts, watch, order, active,
    pair_code, ev_i, ev_f, lg, obs, times, sv_rows, noise, gauge, padg, pad, img, geo,
    taxel_u, buf, sv, ks, inputs, row, ctau, last_tau, trace, imgs, img_t, cnt, stop_s,
    rows0, pn0, pt0,
):  # noqa: E741  # fmt: skip  # pragma: no cover
    """Up to ``n_max`` iterations of the run loop with the gait controller compiled in.

    The arguments up to ``obs`` are :func:`planner.sim.planar.run_kernel.advance`'s (the
    world, the loop's clock/flags/held torque, the event buffers and the log; mode 2). Then
    the controller's: ``times`` (m,) the predicted call times [s] and ``sv_rows`` (m,
    N_SV) their references; ``noise`` (m, 2, 2) their gauge noise [N]; ``gauge`` (2,):
    0 exact / 1 quantized / 2 noisy and quantized, resolution [N]; ``padg``, ``pad``: the
    left pad's geometry and array (``pad[0]`` 0: no image); ``img`` (rows, cols) scratch;
    ``geo`` ... ``ctau``: :func:`gait_kernel`'s arrays; ``last_tau`` (6,) the last good
    command; ``trace`` (m, 29) and ``imgs``/``img_t`` its rows and kept images; ``cnt``
    (6,) counters (``C_*``; ``cnt[5]`` trace rows before the chunk); ``stop_s`` (N_STOP,):
    the :class:`.gait_loop.PhaseStop`'s ``hold_slip`` [m] (<= 0: none), its watched points'
    number and indices in ``buf`` and their positions after the phase's first step (``S_*``);
    ``rows0`` (n, 10), ``pn0``, ``pt0``: the step before this call
    (:meth:`PlanarWorld._step_rows`; ``rows0`` of shape (0, 0): none, its call runs in
    Python).

    Returns:
        ``(done, exit, n, pn, pt, slip, mu, lim_joint, lim_impulse)`` as ``advance``; exit
        :data:`STOP_HINT` after a step the :class:`PhaseStop` may end the run at,
        :data:`STEP_IN_PYTHON` when a call ran but its step needs Python (not committed
        beyond the call: the driver runs the iteration without its call), ``CALL_DUE``
        when a call cannot run here (nothing of it done).
    """
    h, gx, gy, margin, ptol, tdrop = sc[0], sc[1], sc[2], sc[3], sc[4], sc[5]
    nb = kind.shape[0]
    now = np.zeros((nb, nb), np.bool_)
    tau_new = np.empty(6)
    cmd = np.empty(6)
    pn, pt, slip, mu, lp = np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0)
    lj = np.zeros(0, np.int64)
    n_last = -1
    if rows0.shape[1] == 10 and rows0.shape[0] <= out.shape[0]:
        # the last step before this call (its rows into the candidate buffer, scratch until
        # the next step): the chunk's first call reads it
        n_last = rows0.shape[0]
        out[:n_last] = rows0
        pn, pt = pn0, pt0
    j = 0  # calls made
    for done in range(n_max):
        if flags[NEV] + 2 * nb * nb + nb + 16 > ev_i.shape[0]:
            return done, DONE, n_last, pn, pt, slip, mu, lj, lp
        t = clock[0]
        tau_new[:] = tau
        call = t >= clock[1] - 1e-9 * h
        sat_new, onset, event = flags[SAT], False, 0
        if call:
            if n_last < 0 or j >= times.shape[0] or times[j] != t:
                return done, CALL_DUE, n_last, pn, pt, slip, mu, lj, lp
            event = _gait_call(j, t, n_last, out, pn, pt, q, qd, kind, index, h, sens, obs,
                               noise, gauge, padg, pad, img, geo, taxel_u, buf, sv, sv_rows,
                               ks, inputs, row, ctau, last_tau, trace, imgs, img_t, cnt,
                               cmd)  # fmt: skip
            j += 1
            if event:
                cnt[C_EVENT] = event
                ks[ck.S_DONE] = 1.0
            sat = _saturated(cmd, lim, tau_new)
            onset = sat and flags[SAT] == 0
            sat_new = 1 if sat else 0
            period = clock[2]
            clock[1] += period * max(1.0, math.ceil((t - clock[1]) / period + 1e-9))
            flags[SAT] = sat_new
            tau[:] = tau_new
            if onset:
                _event(ev_i, ev_f, flags, row0 + done + 1, EV_SAT, 0, 0, t)
                ev_f[flags[NEV] - 1, 1:7] = cmd
        st, n, pn_, pt_, slip_, mu_, lj_, lp_ = full_step(
            h, gx, gy, margin, ptol, F, I, pairs, poses, kind, index, mu_body, x, v, mass,
            inertia, True, q, qd, tau_new, P, limits, covers, out, counts,
        )  # fmt: skip
        if st != 0:
            code = STEP_IN_PYTHON if call else PYTHON_STEP
            return done, code, n_last, pn, pt, slip, mu, lj, lp
        pn, pt, slip, mu, lj, lp, n_last = pn_, pt_, slip_, mu_, lj_, lp_, n
        tau[:] = tau_new
        clock[0] = t + h
        t1 = clock[0]
        k = row0 + done + 1
        _world_events(n, out, pn, lj, lp, kind, index, watch, order, flags, ev_i, ev_f, k, t1,
                      tdrop)  # fmt: skip
        if not _healthy(x, v, q, qd):
            return done + 1, BLOW_UP, n_last, pn, pt, slip, mu, lj, lp
        _contact_events(n, out, pn, active, now, ev_i, ev_f, flags, k, t1)
        _record(k, t1, x, v, com, q, qd, tau, n, out, pn, pt, slip, h, pair_code, flags, lg)
        # the PhaseStop, proposed (the Python one decides; the margin covers math.hypot's
        # rounding against numba's)
        nw = int(stop_s[S_N])
        if cnt[C_C0] == 0:
            for i in range(nw):
                iw = int(stop_s[S_INDEX + i])
                stop_s[S_REF + 2 * i], stop_s[S_REF + 2 * i + 1] = buf[iw], buf[iw + 1]
            cnt[C_C0] = 1
        if event:
            return done + 1, STOP_HINT, n_last, pn, pt, slip, mu, lj, lp
        slip_limit = stop_s[S_SLIP]
        if slip_limit > 0.0:
            moved = True
            for i in range(nw):
                iw = int(stop_s[S_INDEX + i])
                ir = S_REF + 2 * i
                d = math.hypot(buf[iw] - stop_s[ir], buf[iw + 1] - stop_s[ir + 1])
                moved = moved and d > slip_limit * (1.0 - 1e-9)
            if moved:
                return done + 1, STOP_HINT, n_last, pn, pt, slip, mu, lj, lp
    return n_max, DONE, n_last, pn, pt, slip, mu, lj, lp
