"""The run loop shared by the planar and the spatial world (issue 15, items 4-6).

:func:`run` advances a world for ``duration`` seconds, calls the controller at its own rate
with a zero-order hold of its torques, saturates the torques at the world's limits, records
every step in a preallocated :class:`SimLog`, and turns faults into :class:`SimEvent` records:

* ``contact_made`` / ``contact_lost``: a body pair starts / stops carrying force;
* ``torque_saturated``: the command exceeded a joint's torque limit (once per onset);
* world-specific events (``joint_limit``, ``object_dropped``, ``singular``, ``jammed``)
  drained from the world after each step;
* ``blow_up``: non-finite or runaway state (``|v| > max_speed``) -> status ``"failed"``;
* ``stopped``: the controller raised a :class:`planner.errors.HapexError` or returned a bad
  command, or the world failed a step (status ``"failed"``), or the user's ``stop``
  callback returned a reason (status ``"ok"``).

The run always returns its log; nothing escapes but programming errors.

**Two implementations, one behaviour.** :class:`LoopState` is the reference loop, one
Python iteration per step (``run(..., loop="python")``; the only loop of the spatial world
and of ``PlanarWorld(compiled=False)``). A world may offer a compiled loop
(``world.compiled_loop(state)``): the planar world's (:mod:`planner.sim.planar.fast_run`)
runs :data:`CHUNK` iterations per numba call - the step, its preset controller, the
observation that controller reads, the events and the log rows - and hands single
iterations back to :meth:`LoopState.iteration` / :meth:`LoopState.control` for what it
cannot do the reference way (Python controllers' calls, ``stop`` after every step, steps
needing the Python fallback). Its logs equal the reference loop's to the bit
(``tests/test_sim_fast_run.py``). A controller may bring its own compiled loop through the
planar world's (``fast_loop_plugin``: the gait's phases, with their ``stop`` check,
:mod:`planner.exploration.planar.gait_loop`; equal to the reference loop to the bit,
``tests/test_gait_speed.py``). Why compiled and not vectorized: with the step at ~10 us,
the per-step Python of the loop (observation objects, controller call, log row, event sets:
~145 us) was 90 % of a run; only removing the interpreter from the step brought the hand
scenes past 20x real time.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from planner import checks
from planner.checks import shown
from planner.errors import HapexError, InvalidParameter
from planner.sim.events import SimEvent
from planner.sim.log import SimLog

__all__ = ["CHUNK", "LoopState", "run"]

_SIGNATURES = {"controller": "controller(t, observation) -> tau", "stop": "stop(t, world) -> str"}

MAX_SPEED = 1.0e3  # [m/s] or [rad/s]: beyond this the state is considered blown up


def _stop(log: SimLog, t: float, kind: str, reason: str, failed: bool, **data: Any) -> None:
    log.events.append(SimEvent(t, kind, reason, dict(data)))
    if kind != "stopped":
        log.events.append(SimEvent(t, "stopped", reason, {}))
    log.status = "failed" if failed else "ok"
    log.reason = reason


def _command(world, controller, t: float, oracle: bool, n: int) -> tuple[np.ndarray | None, str]:
    """The controller's torque (n,) or None with the reason it failed."""
    try:
        tau = controller(t, world.observe(oracle=oracle))
    except (HapexError, ArithmeticError, np.linalg.LinAlgError) as exc:
        return None, f"controller failed at t={t:.6g} s: {type(exc).__name__}: {exc}"
    if tau is None:
        tau = np.zeros(n)
    try:  # a string, a dict, an object or a ragged list is a bad command, not a crash
        tau = np.asarray(tau)
    except (TypeError, ValueError) as exc:
        return None, f"controller returned a non-numeric command at t={t:.6g} s ({exc})"
    if tau.dtype.kind not in "iuf":
        return None, (
            f"controller returned a non-numeric command {shown(tau.tolist())} "
            f"(dtype {tau.dtype}) at t={t:.6g} s, expected ({n},) joint torques [N m]"
        )
    tau = tau.astype(float, copy=False)
    if tau.shape != (n,):
        return None, f"controller returned torques of shape {tau.shape}, expected ({n},)"
    # one dot product first (finite => every entry finite); the exact test only when it trips
    if not math.isfinite(float(tau @ tau)) and not np.all(np.isfinite(tau)):
        return None, f"controller returned non-finite torques {tau.tolist()} at t={t:.6g} s"
    return tau, ""


def _saturate(lim, tau: np.ndarray, log: SimLog, t: float, was: bool) -> tuple[np.ndarray, bool]:
    if lim is None or len(tau) == 0:
        return tau, False
    if max(abs(a) - b for a, b in zip(tau.tolist(), lim.tolist(), strict=True)) <= 0.0:
        return tau, False
    sat = np.abs(tau) > lim
    if sat.any():
        if not was:
            idx = np.flatnonzero(sat).tolist()
            log.events.append(
                SimEvent(
                    t,
                    "torque_saturated",
                    f"joint torque(s) {idx} saturated at {lim[sat].tolist()} N m",
                    {"joints": idx, "command": tau[sat].tolist()},
                )
            )
        return np.clip(tau, -lim, lim), True
    return tau, False


def _active(world) -> set:
    """Body pairs carrying force (``world.active_pairs()`` when the world has it)."""
    fast = getattr(world, "active_pairs", None)
    if fast is not None:
        return fast()
    return {c.bodies for c in world.contacts() if c.normal_force > 0.0}


def _contact_events(world, log: SimLog, active: set, t: float) -> set:
    now = _active(world)
    if now == active:
        return now
    for pair in sorted(now - active):
        log.events.append(SimEvent(t, "contact_made", f"{pair[0]} touches {pair[1]}", {}))
    for pair in sorted(active - now):
        log.events.append(SimEvent(t, "contact_lost", f"{pair[0]} left {pair[1]}", {}))
    return now


def _health(world) -> str:
    x = world.state_vector()
    v = world.velocity_vector()
    # cheap first: a finite x.x means every entry is finite, and |v|_inf <= |v|_2
    if math.isfinite(float(x @ x)) and float(v @ v) <= MAX_SPEED * MAX_SPEED:
        return ""
    if not np.all(np.isfinite(x)):
        return "non-finite state (NaN/inf)"
    if v.size and np.max(np.abs(v)) > MAX_SPEED:
        return f"runaway velocity {np.max(np.abs(v)):.3g} > {MAX_SPEED:g} ({_whose(world, v)})"
    return ""


def _whose(world, v) -> str:
    """Which coordinate of the velocity vector ``v`` is the fastest: a free body's
    component [m/s or rad/s] or a joint [rad/s] (bodies first, then joints)."""
    k = int(np.argmax(np.abs(v)))
    per = world.velocity_size  # per free body; a spatial finger's rates are its joints'
    nb = (len(v) - world.n_joints) // per
    if k < per * nb:
        return f"{world.body_names[k // per]}, component {k % per}"
    return f"joint {k - per * nb}, {abs(float(v[k])):.3g} rad/s"


class LoopState:
    """The state of one run of the reference loop, one iteration at a time.

    :func:`run` drives it with :meth:`iteration`; a world's compiled loop (the planar
    world's :mod:`planner.sim.planar.fast_run`) advances many iterations in one call and
    hands single iterations back to :meth:`iteration` / :meth:`control` when it cannot do
    them the reference way. Attributes: ``log``, ``k`` (steps done), ``rows`` (rows
    written), ``tau`` (held torque), ``next_call`` [s], ``period`` [s], ``saturated``,
    ``active`` (body-name pairs carrying force), ``stopped``.
    """

    def __init__(self, world, duration, controller, control_rate, oracle, stop, max_contacts):
        checks.nonnegative("duration", duration, "s")
        checks.positive("control_rate", control_rate, "Hz")
        checks.integer("max_contacts", max_contacts, 1)
        for name, fn in (("controller", controller), ("stop", stop)):
            if fn is not None and not callable(fn):
                raise InvalidParameter(
                    f"{name}: expected a callable {_SIGNATURES[name]} or None, got {shown(fn)}"
                )
        self.world, self.controller, self.oracle, self.stop = world, controller, oracle, stop
        self.n_steps = int(round(duration / world.dt))
        self.n = n = world.n_joints
        self.log = SimLog.allocate(
            self.n_steps + 1,
            world.body_names,
            world.pose_size,
            world.velocity_size,
            n,
            max_contacts,
            world.contact_dim,
        )
        self.tau = np.zeros(n)
        self.period, self.next_call = 1.0 / control_rate, world.time
        self.lim = world.torque_limits
        self.saturated, self.active = False, _active(world)
        self.k, self.rows, self.stopped = 0, 1, False
        world.record(self.log, 0, self.tau)

    def control(self) -> None:
        """Call the controller if a call is due (zero-order hold in between)."""
        world, t = self.world, self.world.time
        if self.controller is None or t < self.next_call - 1e-9 * world.dt:
            return
        cmd, why = _command(world, self.controller, t, self.oracle, self.n)
        if cmd is None:
            _stop(self.log, t, "stopped", why, failed=True)
            self.stopped = True
            return
        self.tau, self.saturated = _saturate(self.lim, cmd, self.log, t, self.saturated)
        self.next_call += self.period * max(1, math.ceil((t - self.next_call) / self.period + 1e-9))

    def iteration(self) -> None:
        """One step of the reference loop: control, step, events, guard, log row, stop."""
        world, log = self.world, self.log
        self.control()
        if self.stopped:
            return
        t = world.time
        try:
            world.step(self.tau)
        except HapexError as exc:
            kind = "singular" if type(exc).__name__ == "SingularConfiguration" else "stopped"
            _stop(log, t, kind, f"step failed at t={t:.6g} s: {exc}", failed=True)
            self.stopped = True
            return
        self.k += 1
        log.events.extend(world.drain_events())
        why = _health(world)
        if why:
            _stop(log, world.time, "blow_up", why, failed=True)
            self.stopped = True
            return
        self.active = _contact_events(world, log, self.active, world.time)
        world.record(log, self.k, self.tau)
        self.rows = self.k + 1
        self.check_stop()

    def check_stop(self) -> None:
        """The user's ``stop(t, world)`` after a step."""
        if self.stop is not None:
            reason = self.stop(self.world.time, self.world)
            if reason:
                _stop(self.log, self.world.time, "stopped", str(reason), failed=False)
                self.stopped = True

    def finish(self) -> SimLog:
        """The log, trimmed to the rows written, torques shifted onto their steps."""
        log, rows = self.log, self.rows
        # rows were written after each step with the torque of that step: shift so that
        # tau[k] is the torque held over [t_k, t_k+1] (the last row repeats the last command)
        log.tau[: rows - 1] = log.tau[1:rows].copy()
        log.trim(rows)
        return log


CHUNK = 500
"""Iterations per call of a world's compiled loop (progress bar granularity)."""


def run(
    world,
    duration: float,
    controller: Callable | None = None,
    control_rate: float = 1000.0,
    progress: bool = False,
    oracle: bool = False,
    stop: Callable | None = None,
    max_contacts: int = 8,
    loop: str = "auto",
) -> SimLog:
    """Simulate ``world`` for ``duration`` [s] and return the log.

    Args:
        world: a planar or spatial world (see :class:`planner.sim.world.WorldBase`).
        duration: simulated time [s] (rounded to whole steps of ``world.dt``).
        controller: ``controller(t, observation) -> tau`` or None (zero torques).
        control_rate: controller calls per second [Hz]; torques are held in between
            (zero-order hold); a rate above ``1/dt`` calls it every step.
        progress: show a tqdm progress bar.
        oracle: pass the true state in ``observation.truth`` (debugging only).
        stop: ``stop(t, world) -> str | None``; a reason string ends the run (status "ok").
            It is called after every step, also by the compiled loop.
        max_contacts: contact slots per logged row.
        loop: ``"auto"``: the world's compiled loop when it has one (the planar world with
            ``compiled=True``: :mod:`planner.sim.planar.fast_run`; the same log and events
            as the reference); ``"python"``: the reference loop, one Python iteration per
            step.

    Returns:
        the :class:`SimLog` (``status`` "failed" with a ``reason`` when a fault ended it).
    """
    checks.choice("loop", loop, ("auto", "python"))
    state = LoopState(world, duration, controller, control_rate, oracle, stop, max_contacts)
    fast = None
    if loop == "auto" and getattr(world, "compiled_loop", None) is not None:
        fast = world.compiled_loop(state)
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=state.n_steps, unit="step", desc="sim")
    while state.k < state.n_steps and not state.stopped:
        k0 = state.k
        if fast is None:
            state.iteration()
        else:
            fast.advance(min(CHUNK, state.n_steps - state.k))
        if bar is not None and state.k // 100 > k0 // 100:
            bar.update(100 * (state.k // 100 - k0 // 100))
    if fast is not None:
        fast.close()
    if bar is not None:
        bar.close()
    return state.finish()
