"""The planar world's compiled run loop: the driver around :func:`run_kernel.advance`.

Why this design. With the step compiled (~30 us in contact), the Python run loop around it
(observation, controller call, log row, event checks: ~145 us per step in the hand scenes)
was what kept whole runs at ~2x real time. Vectorizing that Python would still pay the
interpreter per step; so the loop itself is compiled, and the parts that must stay Python
are entered only when needed:

* the preset :class:`~planner.sim.planar.presets.FingertipForceControl` (and no controller)
  run inside the kernel: :data:`planner.sim.loop.CHUNK` steps per call, with the log rows,
  events and world bookkeeping done there too;
* a Python controller (the gait's) is called from Python when its call is due; between
  calls (``control_rate`` below 1/dt) the kernel advances with the held torque; at 1 kHz
  each call is one kernel step, whose log row and events cost no Python;
* a ``stop`` callback is called after every step (the kernel then advances one step per
  call), exactly as in the reference loop;
* a controller with a ``fast_loop_plugin(fast_loop, stop)`` method may return a plugin
  that advances the run instead (its own compiled loop: the gait's phases,
  :mod:`planner.exploration.planar.gait_loop`), or None;
* an iteration the kernel cannot do as the reference does (position projection, the Python
  contact search, an LCP the kernel cannot verify, a bad command) is handed back before
  anything is committed, and run by :meth:`planner.sim.loop.LoopState.iteration`.

The world's event bookkeeping (joint limits on, fingertip touches, dropped bodies), the
loop's held torque, saturation flag, active pairs and the log's pair table are copied into
the kernel's arrays once per run and back whenever Python needs them, so a run mixes both
paths freely and its :class:`SimLog` equals the reference loop's to the bit
(``tests/test_sim_fast_run.py``). Noise draws: every controller call of the reference loop
reads the strain gauges (one draw of the world's generator); the kernel counts its calls and
the driver draws as many, so the generator ends in the same state.
"""

from __future__ import annotations

import numpy as np

from planner.sim.events import SimEvent
from planner.sim.lcp import COVERS
from planner.sim.planar.bodies import FREE
from planner.sim.planar.run_kernel import (
    BLOW_UP,
    CALL_DUE,
    CALLS,
    EV_DROP,
    EV_LIMIT,
    EV_LOST,
    EV_MADE,
    EV_SAT,
    NEV,
    NPAIRS,
    NTOUCH,
    PYTHON_STEP,
    SAT,
    advance,
)
from planner.sim.planar.sensing import GaugeNoise
from planner.sim.planar.stepper import _NO_HAND, _compiled

__all__ = ["FastLoop", "compiled_law"]

EVENTS = 256  # rows of the event buffer (at least)


def compiled_law(controller) -> tuple | None:
    """``(mode, q_ref, Pc, tasks, ctrl_s)`` of a controller the kernel runs (mode 0: none,
    1: the preset), or ``None`` for a Python controller (mode 2)."""
    from planner.sim.planar.presets import FingertipForceControl

    if controller is None:
        return 0, np.zeros(6), _NO_HAND[1], np.zeros((0, 12)), np.zeros(4)
    if type(controller) is FingertipForceControl:
        c = controller
        ctrl_s = np.array([c.joint_stiffness, c.joint_damping, *c.gravity], float)
        return 1, np.asarray(c.q_ref, float), c._packed, c._tasks, ctrl_s
    return None


def _standard_sensors(sens) -> bool:
    """Whether the kernel reproduces the readings (:mod:`robots.sensors` encoder and gauge
    models, or exact readings)."""
    from robots.sensors import Encoder, ForceSensor

    enc, force = sens.encoder, sens.force
    return (enc is None or type(enc) is Encoder) and (force is None or type(force) is ForceSensor)


class FastLoop:
    """Advances a :class:`planner.sim.loop.LoopState` of a :class:`PlanarWorld` with the
    compiled kernel (module docstring)."""

    def __init__(self, state) -> None:
        w = self.w = state.world
        self.s = state
        law = compiled_law(state.controller)
        if law is None:
            law = (2, *compiled_law(None)[1:])
        self.mode, self.q_ref, self.Pc, self.tasks, self.ctrl_s = law
        sens = w.sensors
        if not _standard_sensors(sens):  # other sensor models: observed from Python
            self.mode = 2 if self.mode == 1 else self.mode
        enc = 0.0 if sens.encoder is None else float(sens.encoder.resolution)
        self.sens = np.array([enc, float(sens.velocity_resolution)])
        self.noise = sens.force is not None and sens.force.noise_std > 0 and w.hand is not None
        self.free = [b for b in w.bodies if b.kind == FREE]
        self.com = np.array([b.com for b in self.free], float).reshape(-1, 2)
        nb = len(w.bodies)
        self.names = [b.name for b in w.bodies]
        self.index = {n: i for i, n in enumerate(self.names)}
        self.clock = np.array([w.time, state.next_call, state.period])
        self.flags = np.zeros(5, np.int64)
        self.tau = np.zeros(6)
        self.watch = np.zeros((3, max(nb, 6)))
        self.order = np.zeros(nb, np.int64)
        self.active = np.zeros((nb, nb), np.bool_)
        self.pair_code = np.full((nb, nb), -1, np.int64)
        rows = max(EVENTS, 4 * nb * nb + 64)  # the kernel needs 2 nb^2 + nb + 16 free per step
        self.ev_i = np.zeros((rows, 4), np.int64)
        self.ev_f = np.zeros((rows, 7))
        self.obs = np.zeros(16)
        self._readings = (self.obs[:6], self.obs[6:12], self.obs[12:].reshape(2, 2))
        w._noise = None
        self.readings = _standard_sensors(sens) and w.hand is not None
        self.sc = np.array([w.dt, *w.gravity, w.margin, w.projection_tolerance, w.drop_time], float)
        lg = state.log
        T = len(lg.t)
        poses = np.zeros((len(self.free), T, 3))
        vels = np.zeros((len(self.free), T, 3))
        for i, b in enumerate(self.free):  # the log's per-body arrays become views
            poses[i], vels[i] = lg.poses[b.name], lg.velocities[b.name]
            lg.poses[b.name], lg.velocities[b.name] = poses[i], vels[i]
        self.lg = (lg.t, poses, vels, lg.q, lg.qd, lg.tau, lg.contact_count, lg.contact_pair,
                   lg.contact_point, lg.contact_normal, lg.normal_force, lg.tangential_force,
                   lg.slip_velocity, lg.gap)  # fmt: skip
        self._to_kernel()
        # a controller may run inside its own compiled loop (the gait's phases:
        # planner.exploration.planar.gait_loop); it drives this loop's state and kernel
        hook = getattr(state.controller, "fast_loop_plugin", None)
        self.plugin = hook(self, state.stop) if hook is not None and self.mode == 2 else None

    # ------------------------------------------------------------------ state copies
    def _to_kernel(self) -> None:
        """World, loop and log bookkeeping -> the kernel's arrays."""
        w, s = self.w, self.s
        self.clock[0], self.clock[1] = w.time, s.next_call
        self.flags[SAT] = 1 if s.saturated else 0
        self.tau[:] = s.tau if len(s.tau) else 0.0
        self.watch[:] = 0.0
        self.watch[1] = np.nan
        for j in w._limits_on:
            self.watch[0, j] = 1.0
        for m, (name, t) in enumerate(w._touch.items()):
            i = self.index[name]
            self.watch[1, i] = t
            self.order[m] = i
        self.flags[NTOUCH] = len(w._touch)
        for name in w._dropped:
            self.watch[2, self.index[name]] = 1.0
        self.active[:] = False
        for a, b in s.active:
            self.active[self.index[a], self.index[b]] = True
        cache = s.log.__dict__.setdefault("_pair_of_bodies", {})
        for (i, j), p in cache.items():
            self.pair_code[i, j] = p
        self.flags[NPAIRS] = len(s.log.pairs)

    def _from_kernel(self, n_pairs0: int, calls0: int) -> None:
        """The kernel's clock, hold, pairs, events and noise draws -> world, loop, log."""
        w, s = self.w, self.s
        w.time, s.next_call = float(self.clock[0]), float(self.clock[1])
        s.saturated = bool(self.flags[SAT])
        if s.n:
            s.tau = self.tau.copy()
        if self.flags[NPAIRS] > n_pairs0:
            self._new_pairs(n_pairs0)
        if self.flags[NEV]:
            self._flush_events()
        calls = int(self.flags[CALLS]) - calls0
        if calls and self.noise:  # the gauge readings of the reference loop's observations
            self._sync_noise()
            w.rng.normal(0.0, w.sensors.force.noise_std, (calls, 2, 2))

    def _sync_noise(self) -> None:
        """The noise drawn ahead for the Python controller's readings -> the generator's
        reference state (before anything else draws from it)."""
        noise = getattr(self.w, "_noise", None)
        if noise is not None:
            noise.sync()
            self.w._noise = None

    def _sync_world(self) -> None:
        """The kernel's event bookkeeping -> the world's and the loop's (before a Python
        iteration and at the end of the run; in between only the kernel uses it)."""
        w, s = self.w, self.s
        w._unjam_after_kernel()
        w._limits_on = {j for j in range(6) if self.watch[0, j] == 1.0}
        order = self.order[: self.flags[NTOUCH]].tolist()
        w._touch = {self.names[i]: float(self.watch[1, i]) for i in order}
        w._dropped = {self.names[i] for i in np.flatnonzero(self.watch[2] == 1.0)}
        ia, ib = np.nonzero(self.active)
        s.active = {(self.names[i], self.names[j]) for i, j in zip(ia, ib, strict=True)}

    def _new_pairs(self, n0: int) -> None:
        log = self.s.log
        cache = log.__dict__.setdefault("_pair_of_bodies", {})
        ia, ib = np.nonzero(self.pair_code >= n0)
        for i, j in sorted(zip(ia, ib, strict=True), key=lambda ij: self.pair_code[ij]):
            p = log.pair_index(self.names[i], self.names[j])
            assert p == self.pair_code[i, j], "pair table out of step"
            cache[(int(i), int(j))] = p

    def _flush_events(self) -> None:
        """Event codes -> :class:`SimEvent` records (the reference loop's messages/order)."""
        ne = int(self.flags[NEV])
        out: list[SimEvent] = []
        group: list[tuple] = []  # contact events of one step and kind, sorted by names
        for e in range(ne):
            k, kind, a, b = self.ev_i[e].tolist()
            t = float(self.ev_f[e, 0])
            if group and (group[0][0] != k or group[0][1] != kind):
                out += [g[3] for g in sorted(group, key=lambda g: g[2])]
                group = []
            if kind in (EV_MADE, EV_LOST):
                pa, pb = self.names[a], self.names[b]
                msg = f"{pa} touches {pb}" if kind == EV_MADE else f"{pa} left {pb}"
                name = "contact_made" if kind == EV_MADE else "contact_lost"
                group.append((k, kind, (pa, pb), SimEvent(t, name, msg, {})))
            elif kind == EV_LIMIT:
                out.append(SimEvent(t, "joint_limit", f"joint {a} reached its limit", {"joint": a}))
            elif kind == EV_DROP:
                name = self.names[a]
                out.append(
                    SimEvent(t, "object_dropped", f"{name} left the fingers", {"body": name})
                )
            elif kind == EV_SAT:
                cmd = self.ev_f[e, 1:7]
                lim = self.s.lim
                sat = np.abs(cmd) > lim
                idx = np.flatnonzero(sat).tolist()
                out.append(
                    SimEvent(
                        t,
                        "torque_saturated",
                        f"joint torque(s) {idx} saturated at {lim[sat].tolist()} N m",
                        {"joints": idx, "command": cmd[sat].tolist()},
                    )
                )
        out += [g[3] for g in sorted(group, key=lambda g: g[2])]
        self.s.log.events.extend(out)
        self.flags[NEV] = 0

    # ------------------------------------------------------------------ advancing
    def _call(self, n_max: int):
        w, s, ck = self.w, self.s, _compiled(self.w)
        hand = w.hand
        if hand is not None:
            q, qd, P, limits, lim = w.q, w.qd, hand.packed, hand.limits, s.lim
        else:
            q, qd, P, limits, lim = np.zeros(6), np.zeros(6), _NO_HAND[1], _NO_HAND[2], np.zeros(0)
        pk = ck.packed
        n_pairs0, calls0 = int(self.flags[NPAIRS]), int(self.flags[CALLS])
        done, code, n, pn, pt, slip, mu, lj, lp = advance(
            n_max, s.k, self.mode, self.clock, self.flags, self.tau, self.sens, self.ctrl_s,
            self.q_ref, self.Pc, self.tasks, lim, self.sc, pk.F, pk.I, pk.pairs, ck.poses,
            ck.kind, ck.index, ck.mu, w._x, w._v, ck.mass, ck.inertia, self.com,
            hand is not None, q, qd, P, limits, COVERS, ck.out, ck.counts, self.watch,
            self.order, self.active, self.pair_code, self.ev_i, self.ev_f, self.lg, self.obs,
        )  # fmt: skip
        if n >= 0:  # the StepResult is built when something reads it
            w._set_pending(ck.out[:n].copy(), mu, pn, pt, slip, lj, lp)
        self._from_kernel(n_pairs0, calls0)
        return done, code

    def advance(self, n_max: int) -> None:
        """Up to ``n_max`` iterations (fewer when the run stops or a ``stop`` is given)."""
        if self.plugin is not None:
            self.plugin.advance(n_max)
            return
        s = self.s
        if s.stop is not None:
            n_max = 1
        left = n_max
        while left > 0 and not s.stopped:
            done, code = self._call(left)
            s.k += done
            left -= done
            if code == BLOW_UP:
                from planner.sim.loop import _health, _stop

                s.rows = s.k
                _stop(s.log, self.w.time, "blow_up", _health(self.w) or "blow-up", failed=True)
                s.stopped = True
                return
            s.rows = s.k + 1
            if done and s.stop is not None:
                s.check_stop()
                if code == CALL_DUE and not s.stopped and s.k < s.n_steps:
                    self._control(done)  # the next iteration's call, read by the kernel
                return
            if code == CALL_DUE:
                if s.k < s.n_steps:
                    self._control(done)
            elif code == PYTHON_STEP:
                self._sync_world()
                self._sync_noise()
                s.iteration()  # the reference iteration (it checks ``stop`` itself)
                left -= 1
                self._to_kernel()
                if s.stop is not None:
                    return

    def _control(self, done: int) -> None:
        """The Python controller's call that begins the next iteration
        (:meth:`LoopState.control`), on the readings the kernel took after its last step
        when it did one (``done``), with the gauge noise drawn ahead (:class:`GaugeNoise`)."""
        w, s = self.w, self.s
        if done and self.readings:
            w._reading = self._readings
            if self.noise and w._noise is None:
                w._noise = GaugeNoise(w.rng, w.sensors.force.noise_std)
        s.control()
        w._reading = None
        self.clock[1], self.flags[SAT] = s.next_call, 1 if s.saturated else 0
        if s.n:
            self.tau[:] = s.tau

    def close(self) -> None:
        """Hand the event bookkeeping and the generator back to the world (the run is
        over)."""
        self._sync_world()
        self._sync_noise()
