"""Compiled run loop of the planar world: N steps of :func:`planner.sim.loop.run` in one call.

:func:`advance` is the body of the reference loop (:func:`planner.sim.loop.run` with
:meth:`PlanarWorld.step`, :meth:`PlanarWorld.observe`, :meth:`PlanarWorld.record` and the
event checks) compiled with numba, for up to ``n_max`` steps per call:

1. the controller, when a call is due (same schedule and zero-order hold as the loop): the
   preset :class:`~planner.sim.planar.presets.FingertipForceControl` law
   (:func:`~planner.sim.planar.presets._task_torques`) on the encoder readings (``floor``
   quantization of ``q``, ``rint`` of ``qd``, exactly :func:`planner.sim.observation.read_joints`),
   then the torque saturation of the loop;
2. :func:`~planner.sim.planar.step_kernel.full_step` (the compiled step);
3. the world events of :meth:`PlanarWorld._watch` (joint limit reached, object dropped), the
   NaN / runaway guard, contact made / lost, the torque-saturation onset: written as codes
   into an event buffer (``ev_i`` step, kind, a, b; ``ev_f`` time and the six commanded
   torques) that :mod:`planner.sim.planar.fast_run` turns into the loop's :class:`SimEvent`
   records with the same messages and order;
4. the log row (time, free-body poses and velocities of the profile frames, joints,
   torques, contact slots, pair codes in order of first appearance) straight into the
   :class:`SimLog` arrays.

Everything the kernel cannot do the way the Python loop does it makes it return BEFORE the
iteration is committed (state, clock, controller hold, events untouched): a step that needs
the position projection, the Python contact search or a larger candidate buffer, an LCP
without verified answer, a non-finite command, a Python controller's call (``mode`` 2), a
full event buffer. The driver then runs that one iteration through the reference Python
path and calls the kernel again, so the log is the reference loop's, to the bit (tested).
A blow-up is detected after the step (the loop's order): the kernel returns with the step
committed and its row unwritten, as the loop stops.
"""

from __future__ import annotations

import math

import numpy as np

from planner.jit import njit
from planner.sim.planar.presets import _task_torques
from planner.sim.planar.step_kernel import full_step

__all__ = ["EV_DROP", "EV_LIMIT", "EV_LOST", "EV_MADE", "EV_SAT", "advance"]

FREE, TIP = 1, 2
MAX_SPEED = 1.0e3  # [m/s] or [rad/s]; the loop's runaway threshold

# exit codes of advance()
DONE, PYTHON_STEP, BLOW_UP, EVENTS_FULL, CALL_DUE = 0, 1, 2, 3, 4
# event codes
EV_SAT, EV_LIMIT, EV_DROP, EV_MADE, EV_LOST = 1, 2, 3, 4, 5
# clock[:]: world time, next controller call, controller period [s]
# flags[:]: saturated, pair codes in use, bodies in touch order, events written, calls made
SAT, NPAIRS, NTOUCH, NEV, CALLS = 0, 1, 2, 3, 4


@njit(cache=True)
def _command(t, q, qd, sens, ctrl_s, q_ref, Pc, tasks, lim, tau_new):
    """The preset controller's saturated command into ``tau_new``; returns (ok, onset)."""
    qm = np.empty(6)
    qdm = np.empty(6)
    for i in range(6):
        qm[i] = q[i] if sens[0] == 0.0 else np.floor(q[i] / sens[0]) * sens[0]
        qdm[i] = qd[i] if sens[1] == 0.0 else np.rint(qd[i] / sens[1]) * sens[1]
    cmd = _task_torques(t, qm, qdm, q_ref, ctrl_s[0], ctrl_s[1], ctrl_s[2], ctrl_s[3], Pc, tasks)
    if not math.isfinite(np.dot(cmd, cmd)):
        return False, False, cmd
    over = -np.inf
    for i in range(lim.shape[0]):
        over = max(over, abs(cmd[i]) - lim[i])
    if lim.shape[0] == 0 or over <= 0.0:
        tau_new[:] = cmd
        return True, False, cmd  # saturated flag resets
    for i in range(6):
        tau_new[i] = min(max(cmd[i], -lim[i]), lim[i])
    return True, True, cmd


@njit(cache=True)
def _reading(q, qd, sens, n, out, pn, pt, kind, index, h, obs):
    """The hand's readings after the last step into ``obs`` (16,): encoder angles (6,),
    velocity estimate (6,), true fingertip forces (2, 2) row-major - the operations of
    :func:`planner.sim.planar.sensing._read_hand`, in the same order."""
    for i in range(6):
        obs[i] = q[i] if sens[0] == 0.0 else np.floor(q[i] / sens[0]) * sens[0]
        obs[6 + i] = qd[i] if sens[1] == 0.0 else np.rint(qd[i] / sens[1]) * sens[1]
    obs[12:16] = 0.0
    for r in range(n):
        if pn[r] <= 0:
            continue
        a, b = int(out[r, 0]), int(out[r, 1])
        if kind[a] != TIP and kind[b] != TIP:
            continue
        nx, ny = out[r, 7], out[r, 8]
        fx, fy = (pn[r] * nx - pt[r] * ny) / h, (pn[r] * ny + pt[r] * nx) / h  # on a
        if kind[a] == TIP:
            obs[12 + 2 * index[a]] -= fx
            obs[13 + 2 * index[a]] -= fy
        if kind[b] == TIP:
            obs[12 + 2 * index[b]] += fx
            obs[13 + 2 * index[b]] += fy


@njit(cache=True)
def _event(ev_i, ev_f, flags, k, kind, a, b, t):
    e = flags[NEV]
    ev_i[e, 0], ev_i[e, 1], ev_i[e, 2], ev_i[e, 3] = k, kind, a, b
    ev_f[e, 0] = t
    flags[NEV] = e + 1


@njit(cache=True)
def _world_events(n, out, pn, lj, lp, kind, index, watch, order, flags, ev_i, ev_f, k, t, tdrop):
    """Joint-limit onsets and dropped objects (:meth:`PlanarWorld._watch`).

    ``watch`` (3, nb) rows: joint limit active (first 6 entries), last touch time by a
    fingertip (NaN: never), dropped flag; ``order`` the bodies in order of first touch.
    """
    on = np.zeros(6)
    for m in range(lj.shape[0]):
        if lp[m] > 0:
            on[lj[m]] = 1.0
    for j in range(6):
        if on[j] == 1.0 and watch[0, j] == 0.0:
            _event(ev_i, ev_f, flags, k, EV_LIMIT, j, 0, t)
        watch[0, j] = on[j]
    for r in range(n):
        i, j = int(out[r, 0]), int(out[r, 1])
        if pn[r] > 0 and (kind[i] == TIP or kind[j] == TIP):
            o = j if kind[i] == TIP else i
            if kind[o] == FREE:
                if math.isnan(watch[1, o]):
                    order[flags[NTOUCH]] = o
                    flags[NTOUCH] += 1
                watch[1, o] = t
                watch[2, o] = 0.0
    for m in range(flags[NTOUCH]):
        o = order[m]
        if watch[2, o] == 0.0 and t - watch[1, o] >= tdrop - 1e-12:
            watch[2, o] = 1.0
            _event(ev_i, ev_f, flags, k, EV_DROP, o, 0, t)


@njit(cache=True)
def _healthy(x, v, q, qd):
    s, w = 0.0, 0.0
    for a in (x.ravel(), v.ravel(), q, qd):
        for i in range(a.shape[0]):
            s += a[i] * a[i]
    for a in (v.ravel(), qd):
        for i in range(a.shape[0]):
            w += a[i] * a[i]
    return math.isfinite(s) and w <= MAX_SPEED * MAX_SPEED


@njit(cache=True)
def _contact_events(n, out, pn, active, now, ev_i, ev_f, flags, k, t):
    """Pairs starting / stopping to carry force; ``active`` becomes ``now``."""
    now[:, :] = False
    for r in range(n):
        if pn[r] > 0.0:
            now[int(out[r, 0]), int(out[r, 1])] = True
    nb = active.shape[0]
    for i in range(nb):
        for j in range(nb):
            if now[i, j] and not active[i, j]:
                _event(ev_i, ev_f, flags, k, EV_MADE, i, j, t)
    for i in range(nb):
        for j in range(nb):
            if active[i, j] and not now[i, j]:
                _event(ev_i, ev_f, flags, k, EV_LOST, i, j, t)
            active[i, j] = now[i, j]


@njit(cache=True)
def _record(row, t, x, v, com, q, qd, tau, n, out, pn, pt, slip, h, pair_code, flags, lg):
    """Log row ``row`` (:meth:`PlanarWorld.record`)."""
    (lt, poses, vels, lq, lqd, ltau, count, cpair, cpoint, cnormal, fn, ft, sv, gap) = lg
    lt[row] = t
    for b in range(x.shape[0]):
        xx, yy, a = x[b, 0], x[b, 1], x[b, 2]
        vx, vy, w = v[b, 0], v[b, 1], v[b, 2]
        c, s = math.cos(a), math.sin(a)
        rx, ry = -c * com[b, 0] + s * com[b, 1], -s * com[b, 0] - c * com[b, 1]
        poses[b, row, 0], poses[b, row, 1], poses[b, row, 2] = xx + rx, yy + ry, a
        vels[b, row, 0], vels[b, row, 1], vels[b, row, 2] = vx - w * ry, vy + w * rx, w
    for i in range(lq.shape[1]):
        lq[row, i], lqd[row, i], ltau[row, i] = q[i], qd[i], tau[i]
    count[row] = n
    for r in range(min(n, cpair.shape[1])):
        i, j = int(out[r, 0]), int(out[r, 1])
        p = pair_code[i, j]
        if p < 0:
            p = flags[NPAIRS]
            pair_code[i, j] = p
            flags[NPAIRS] = p + 1
        cpair[row, r] = p
        cpoint[row, r, 0], cpoint[row, r, 1] = out[r, 5], out[r, 6]
        cnormal[row, r, 0], cnormal[row, r, 1] = out[r, 7], out[r, 8]
        fn[row, r] = pn[r] / h
        ft[row, r] = pt[r] / h
        sv[row, r] = slip[r]
        gap[row, r] = out[r, 2]


@njit(cache=True)
def advance(
    n_max, row0, mode, clock, flags, tau, sens, ctrl_s, q_ref, Pc, tasks, lim, sc, F, I,
    pairs, poses, kind, index, mu_body, x, v, mass, inertia, com, has_hand, q, qd, P,
    limits, covers, out, counts, watch, order, active, pair_code, ev_i, ev_f, lg, obs,
):  # noqa: E741  # fmt: skip
    """Up to ``n_max`` iterations of the run loop (module docstring).

    Args:
        n_max: iterations at most; row0: log row of the current state (rows row0+1... are
            written).
        mode: 0 no controller (zero torques), 1 the compiled preset, 2 a Python controller
            (return when its call is due).
        clock: (3,) world time, next call time, call period [s] (updated).
        flags: (5,) int64 :data:`SAT`, :data:`NPAIRS`, :data:`NTOUCH`, :data:`NEV`,
            :data:`CALLS` (updated).
        tau: (6,) held torque [N m] (updated).
        sens: (2,) encoder resolution [rad] (0: exact), velocity resolution [rad/s].
        ctrl_s: (4,) K_q, D_q, controller gravity (gx, gy); q_ref, Pc, tasks: the preset's
            packed law; lim: (6,) torque limits [N m] or (0,).
        sc: (6,) dt [s], gravity gx, gy [m/s^2], margin, projection tolerance [m], drop time
            [s]; F ... counts: the arguments of :func:`full_step`; com: (nfree, 2) centres
            of mass in the profile frames [m].
        watch, order: :func:`_world_events`; active: (nb, nb) pairs carrying force;
        pair_code: (nb, nb) log pair index (-1: not seen); ev_i, ev_f: event buffers.
        lg: the log arrays (t, poses (nfree, T, 3), velocities, q, qd, tau, contact_count,
            contact_pair, contact_point, contact_normal, normal_force, tangential_force,
            slip_velocity, gap).
        obs: (16,) the hand's readings (:func:`_reading`), written when a Python
            controller's call is due after a step of this call (also after its last step:
            ``CALL_DUE`` with ``done = n_max``).

    Returns:
        ``(done, exit, n, pn, pt, slip, mu, lim_joint, lim_impulse)``: iterations done, the
        exit code, and the last step's result (candidates ``out[:n]``; ``n`` = -1 when no
        step was done).
    """
    h, gx, gy, margin, ptol, tdrop = sc[0], sc[1], sc[2], sc[3], sc[4], sc[5]
    nb = kind.shape[0]
    now = np.zeros((nb, nb), np.bool_)
    tau_new = np.empty(6)
    pn, pt, slip, mu, lp = np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0)
    lj = np.zeros(0, np.int64)
    n_last = -1
    for done in range(n_max):
        if flags[NEV] + 2 * nb * nb + nb + 16 > ev_i.shape[0]:  # room for one iteration
            return done, EVENTS_FULL, n_last, pn, pt, slip, mu, lj, lp
        t = clock[0]
        tau_new[:] = tau
        call = mode != 0 and t >= clock[1] - 1e-9 * h
        sat_new, onset = flags[SAT], False
        cmd = tau
        if call:
            if mode == 2:
                if n_last >= 0 and has_hand:
                    _reading(q, qd, sens, n_last, out, pn, pt, kind, index, h, obs)
                return done, CALL_DUE, n_last, pn, pt, slip, mu, lj, lp
            ok, sat, cmd = _command(t, q, qd, sens, ctrl_s, q_ref, Pc, tasks, lim, tau_new)
            if not ok:
                return done, PYTHON_STEP, n_last, pn, pt, slip, mu, lj, lp
            onset = sat and flags[SAT] == 0
            sat_new = 1 if sat else 0
        st, n, pn_, pt_, slip_, mu_, lj_, lp_ = full_step(
            h, gx, gy, margin, ptol, F, I, pairs, poses, kind, index, mu_body, x, v, mass,
            inertia, has_hand, q, qd, tau_new, P, limits, covers, out, counts,
        )  # fmt: skip
        if st != 0:
            return done, PYTHON_STEP, n_last, pn, pt, slip, mu, lj, lp
        pn, pt, slip, mu, lj, lp, n_last = pn_, pt_, slip_, mu_, lj_, lp_, n
        # the iteration is committed from here on
        if call:
            period = clock[2]
            clock[1] += period * max(1.0, math.ceil((t - clock[1]) / period + 1e-9))
            flags[CALLS] += 1
            flags[SAT] = sat_new
            if onset:
                _event(ev_i, ev_f, flags, row0 + done + 1, EV_SAT, 0, 0, t)
                ev_f[flags[NEV] - 1, 1:7] = cmd
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
    if mode == 2 and n_last >= 0 and clock[0] >= clock[1] - 1e-9 * h:
        # the next iteration begins with a Python controller's call: read the sensors now
        # (the driver calls the controller without entering the kernel once more)
        if has_hand:
            _reading(q, qd, sens, n_last, out, pn, pt, kind, index, h, obs)
        return n_max, CALL_DUE, n_last, pn, pt, slip, mu, lj, lp
    return n_max, DONE, n_last, pn, pt, slip, mu, lj, lp
