"""The gait's phases run inside the planar world's compiled loop: many steps per numba call.

Why. With the simulator step compiled (~30 us) and the controller's laws compiled
(:func:`.controller_kernel.gait_kernel`, ~10 us), a phase still paid ~100 us of Python per
step: the loop's controller call, the observation (readings, gauge noise, tactile image),
the machine's ``stop`` callback after every step. :func:`gait_advance` is the body of
:func:`planner.sim.planar.run_kernel.advance` with the gait controller's call compiled into
it, so a phase advances in chunks of :data:`CHUNK` steps per call; Python is left only with
the segment's references (its spline callables, evaluated ahead for the chunk's call times)
and the bookkeeping of the chunk.

Equality with the reference (``world.run(..., stop=PhaseStop(...))`` one Python call per
step; tested in ``tests/test_gait_speed.py``): a call in the kernel does exactly what
:meth:`GaitController.__call__` does on the observation :func:`planner.sim.planar.sensing.observe`
gives, in the same order - encoder readings, gauges ``rint((f + noise) / res) * res`` with
the noise drawn ahead (:class:`planner.sim.planar.sensing.GaugeNoise`), the left pad's image
(:func:`planner.sim.planar.sensing.pad_image`), the kernel, the fallback command, the trace
row, every fifth image, then the loop's saturation - and the compiled :class:`PhaseStop`
check after every step only *proposes* a stop: the kernel returns after that step and the
Python :class:`PhaseStop` decides. What the kernel cannot do (the first call of a chunk,
a step needing the Python fallback, a call time not predicted) goes back to the reference
path before anything is committed.

Used when the run's controller is a :class:`~.controller.GaitController` with its compiled
step and the ``stop`` is a :class:`PhaseStop` of it (:meth:`GaitController.fast_loop_plugin`);
other runs keep :mod:`planner.sim.planar.fast_run`.
"""

from __future__ import annotations

import math
import time

import numpy as np
from numba import njit

from planner.exploration.planar import controller_kernel as ck
from planner.exploration.planar.controller_kernel import REJECTED, gait_kernel
from planner.sim.lcp import COVERS
from planner.sim.planar.run_kernel import (
    BLOW_UP,
    CALL_DUE,
    DONE,
    EV_SAT,
    NEV,
    NPAIRS,
    PYTHON_STEP,
    SAT,
    _contact_events,
    _event,
    _healthy,
    _reading,
    _record,
    _world_events,
)
from planner.sim.planar.sensing import _hand_geometry, pad_image
from planner.sim.planar.step_kernel import full_step

__all__ = ["CHUNK", "GaitLoop", "PhaseStop", "gait_advance"]

#: steps per kernel call at most (the references of its calls are evaluated ahead)
CHUNK = 64
#: steps of the first kernel call of a run and after a step run in Python: chunks double up
#: to CHUNK while the kernel runs them through (references evaluated for calls the kernel
#: never reached were a third of the gait's Python time with fixed chunks)
FIRST_CHUNK = 4
#: exit code: a stop may be due after the last step (the Python :class:`PhaseStop` decides)
STOP_HINT = 5
#: exit code: the call ran, its step needs the Python fallback (commit the call, step there)
STEP_IN_PYTHON = 6
#: command damping of the fallback (``controller.FALLBACK_DAMPING``) [N m s/rad]
_DAMP = 0.02
# cnt[:] of gait_advance: calls made, fallbacks, images kept, event code, c0 known
C_CALLS, C_FALLBACK, C_IMAGES, C_EVENT, C_C0 = 0, 1, 2, 3, 4


#: ``rows0, pn0, pt0`` of :func:`gait_advance` when the world has not stepped yet
_NO_STEP = (np.zeros((0, 0)), np.zeros(0), np.zeros(0))


class PhaseStop:
    """The ``stop`` callback of one gait phase (the machine's per-step check).

    Returns the controller's event (:meth:`GaitController.stop`); with ``hold_slip`` (phases
    2/3: the held object must stay put) first ``"object moved"`` when the sensed object
    centre moved more than ``hold_slip`` [m] from where it was after the phase's first step
    (``moved`` is then True). ``progress(t)`` is called with the simulated time [s] after
    every step (from the compiled loop: after every chunk).
    """

    def __init__(self, ctrl, hold_slip: float | None = None, progress=None) -> None:
        self.ctrl, self.hold_slip, self.progress = ctrl, hold_slip, progress
        self.c0: np.ndarray | None = None
        self.moved = False

    def __call__(self, t: float, world) -> str | None:
        centre = self.ctrl.sensing.est.centre
        if self.c0 is None:
            self.c0 = centre.copy()
        if self.progress is not None:
            self.progress(t)
        if self.hold_slip is not None and math.hypot(*(centre - self.c0)) > self.hold_slip:
            self.moved = True
            return "object moved"
        return self.ctrl.stop(t, world)


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
    (6,) counters (``C_*``; ``cnt[5]`` trace rows before the chunk); ``stop_s`` (3,): the
    centre after the phase's first step (2) and ``hold_slip`` [m] (<= 0: none);
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
        if cnt[C_C0] == 0:
            stop_s[0], stop_s[1] = buf[10], buf[11]
            cnt[C_C0] = 1
        if event:
            return done + 1, STOP_HINT, n_last, pn, pt, slip, mu, lj, lp
        slip_limit = stop_s[2]
        if slip_limit > 0.0:
            d = math.hypot(buf[10] - stop_s[0], buf[11] - stop_s[1])
            if d > slip_limit * (1.0 - 1e-9):
                return done + 1, STOP_HINT, n_last, pn, pt, slip, mu, lj, lp
    return n_max, DONE, n_last, pn, pt, slip, mu, lj, lp


class GaitLoop:
    """Runs :func:`gait_advance` for a :class:`planner.sim.planar.fast_run.FastLoop` whose
    controller is ``ctrl`` and whose ``stop`` is a :class:`PhaseStop` of it (the plugin of
    :meth:`GaitController.fast_loop_plugin`).

    Per chunk: the call due first is the reference's (Python); the next call times are
    predicted with the loop's clock arithmetic, their references evaluated and their gauge
    noise drawn ahead (the generator is rewound and advanced by the calls made); after the
    kernel: the trace rows, kept images, fallbacks and step times go to the controller, the
    controller's event to :meth:`GaitController._event`, a proposed stop to the Python
    :class:`PhaseStop`, a step needing Python to :meth:`LoopState.iteration`.
    """

    def __init__(self, fast, ctrl, stop: PhaseStop) -> None:
        self.fast, self.ctrl, self.stop = fast, ctrl, stop
        w = fast.w
        force = w.sensors.force
        if force is None:
            self.gauge = np.zeros(2)
        else:
            self.gauge = np.array([2.0 if force.noise_std > 0 else 1.0, force.resolution])
        self.std = 0.0 if force is None else float(force.noise_std)
        arr = w.sensors.tactile
        has = arr is not None and w.hand.hand.params.left.tip == "flat"
        if has:
            fu, fv, Bv, BuT, modulus, cell, thr = arr.kernel_args
            self.padg = (*_hand_geometry(w.hand), fu, fv, Bv, BuT)
            self.pad = np.array([1.0, modulus, cell, thr])
            self.img = np.zeros((arr.rows, arr.cols))
        else:
            z = np.zeros((1, 1))
            self.padg = (np.zeros((2, 2)), np.zeros((2, 3)), np.zeros(1), np.zeros(1), z, z)
            self.pad = np.zeros(4)
            self.img = np.zeros_like(ctrl.sensing._no_image)
        self.times = np.zeros(CHUNK)
        self.sv_rows = np.zeros((CHUNK, ck.N_SV))
        self.trace = np.zeros((CHUNK, len(ctrl._row)))
        self.imgs = np.zeros((CHUNK // 5 + 2, *self.img.shape))
        self.img_t = np.zeros(CHUNK // 5 + 2)
        self.cnt = np.zeros(6, np.int64)
        self.stop_s = np.zeros(3)
        self.last_tau = np.zeros(6)
        self.size = FIRST_CHUNK  # steps of the next chunk (doubling up to CHUNK)

    @staticmethod
    def usable(fast, ctrl, stop) -> bool:
        """Whether the run of ``fast`` can use the plugin (compiled step, standard sensors,
        the :class:`TactileArray` model, a :class:`PhaseStop` of ``ctrl``)."""
        from robots.sensors import TactileArray

        w = fast.w
        arr = w.sensors.tactile
        return (
            type(stop) is PhaseStop
            and stop.ctrl is ctrl
            and not ctrl._python_step
            and fast.mode == 2
            and fast.readings
            and not fast.s.oracle
            and (arr is None or type(arr) is TactileArray)
        )

    # ------------------------------------------------------------------ one chunk
    def _predict(self, m: int) -> int:
        """The call times of the next ``m`` steps (the loop's clock arithmetic) and their
        references into ``times``/``sv_rows``; returns their number."""
        from planner.exploration.planar.controller import _references

        s, w, c = self.fast.s, self.fast.w, self.ctrl
        t, nc, per, h = w.time, s.next_call, s.period, w.dt
        seg, t0 = c.segment, c.t0
        k = 0
        for _ in range(m):
            if t >= nc - 1e-9 * h:
                tl = t - t0
                self.times[k] = t
                self.sv_rows[k] = (seg.hold_force(tl), *_references(seg, tl), t, tl)
                k += 1
                nc += per * max(1, math.ceil((t - nc) / per + 1e-9))
            t = t + h
        return k

    def _kernel(self, m: int, calls: int, noise: np.ndarray):
        f, c = self.fast, self.ctrl
        w, s = f.w, f.s
        from planner.sim.planar.stepper import _compiled

        cs = _compiled(w)
        hand, pk = w.hand, cs.packed
        sens = c.sensing
        n_pairs0, calls0 = int(f.flags[NPAIRS]), int(f.flags[4])
        prev = w._step_rows() or _NO_STEP
        done, code, n, pn, pt, slip, mu, lj, lp = gait_advance(
            m, s.k, f.clock, f.flags, f.tau, f.sens, s.lim, f.sc, pk.F, pk.I, pk.pairs,
            cs.poses, cs.kind, cs.index, cs.mu, w._x, w._v, cs.mass, cs.inertia, f.com, w.q,
            w.qd, hand.packed, hand.limits, COVERS, cs.out, cs.counts, f.watch, f.order,
            f.active, f.pair_code, f.ev_i, f.ev_f, f.lg, f.obs, self.times[:calls],
            self.sv_rows[:calls], noise, self.gauge, self.padg, self.pad, self.img, sens.geo,
            sens.taxel_u, sens.buffer, c._sv, c._ks, c._inputs, c._row, c._tau, self.last_tau,
            self.trace, self.imgs, self.img_t, self.cnt, self.stop_s, *prev,
        )  # fmt: skip
        if n >= 0:
            w._set_pending(cs.out[:n].copy(), mu, pn, pt, slip, lj, lp)
        f._from_kernel(n_pairs0, calls0)
        return done, code

    def _chunk(self, m: int) -> tuple[int, int]:
        """One kernel call of at most ``m`` steps; its outputs to the controller."""
        c, w, stop = self.ctrl, self.fast.w, self.stop
        calls = self._predict(m)
        rng = w.rng
        state = None
        if self.gauge[0] == 2.0 and calls:
            state = rng.bit_generator.state
            noise = rng.normal(0.0, self.std, (calls, 2, 2))
        else:
            noise = np.zeros((max(calls, 1), 2, 2))
        cnt = self.cnt
        cnt[:] = 0
        cnt[5] = len(c.trace)
        if stop.c0 is not None:
            self.stop_s[0], self.stop_s[1] = stop.c0
            cnt[C_C0] = 1
        self.stop_s[2] = stop.hold_slip if stop.hold_slip is not None else 0.0
        self.last_tau[:] = c._last_tau
        t0 = time.perf_counter()
        done, code = self._kernel(m, calls, noise)
        wall = time.perf_counter() - t0
        made = int(cnt[C_CALLS])
        if state is not None:  # the generator as after one draw per call made
            rng.bit_generator.state = state
            if made:
                rng.normal(0.0, self.std, (made, 2, 2))
        if made:
            c.trace.extend(map(tuple, self.trace[:made].tolist()))
            c.images.extend((float(self.img_t[i]), self.imgs[i].copy())
                            for i in range(int(cnt[C_IMAGES])))  # fmt: skip
            c.fallbacks += int(cnt[C_FALLBACK])
            c._last_tau = self.last_tau.copy()
            c.step_times.extend([wall / made] * made)  # call + step, per call
        if stop.c0 is None and cnt[C_C0]:
            stop.c0 = self.stop_s[:2].copy()
        if cnt[C_EVENT]:
            c._event(int(cnt[C_EVENT]))
        return done, code

    # ------------------------------------------------------------------ the driver
    def advance(self, n_max: int) -> None:
        """Up to ``n_max`` iterations of the run (fewer when it stops)."""
        f = self.fast
        s, w = f.s, f.w
        left = n_max
        python_call = False  # the kernel could not make the call that is due
        while left > 0 and not s.stopped:
            due = w.time >= s.next_call - 1e-9 * w.dt
            if due and (python_call or w._step_rows() is None):  # the reference's call
                f._sync_noise()
                f._control(0)
                python_call = False
                if s.stopped:
                    return
            # an event of that call ends the run after one step: the kernel does only that
            m = 1 if self.ctrl.event is not None else min(left, self.size)
            done, code = self._chunk(m)
            self.size = min(2 * self.size, CHUNK) if done == m else FIRST_CHUNK
            s.k += done
            left -= done
            if code == BLOW_UP:
                from planner.sim.loop import _health, _stop

                s.rows = s.k
                _stop(s.log, w.time, "blow_up", _health(w) or "blow-up", failed=True)
                s.stopped = True
                return
            s.rows = s.k + 1
            if done and code != STEP_IN_PYTHON:
                # the stop after the chunk's last step (the kernel proposed any other; after
                # STEP_IN_PYTHON its check ran before the call that followed, which Python
                # cannot see)
                s.check_stop()
                if s.stopped:
                    return
            python_call = code == CALL_DUE
            if code in (PYTHON_STEP, STEP_IN_PYTHON):
                f._sync_world()
                s.iteration()  # the reference iteration (a call made here is not due again)
                left -= 1
                f._to_kernel()
