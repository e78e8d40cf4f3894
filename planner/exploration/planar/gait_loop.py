"""The gait's phases run inside the planar world's compiled loop: many steps per numba call.

Why. With the simulator step compiled (~30 us) and the controller's laws compiled
(:func:`.controller_kernel.gait_kernel`, ~10 us), a phase still paid ~100 us of Python per
step: the loop's controller call, the observation (readings, gauge noise, tactile image),
the machine's ``stop`` callback after every step.
:func:`.gait_loop_kernel.gait_advance` is the body of
:func:`planner.sim.planar.run_kernel.advance` with the gait controller's call compiled into
it, so a phase advances in chunks of up to :data:`CHUNK` steps per call; Python is left
with the segment's references (its spline callables, evaluated ahead for the chunk's
predicted call times) and the bookkeeping of the chunk.

Equality with the reference (``world.run(..., stop=PhaseStop(...), loop="python")``: one
Python controller call and one ``stop`` call per step; tested to the bit in
``tests/test_gait_speed.py``): a call in the kernel does what
:meth:`GaitController.__call__` does on the observation of
:func:`planner.sim.planar.sensing.observe`, in the same order - encoder readings, gauges
``rint((f + noise) / res) * res`` with the noise drawn ahead for the chunk (the generator is
then rewound and advanced by the calls made), the left pad's image
(:func:`planner.sim.planar.sensing.pad_image`), the kernel, the fallback command, the trace
row, every fifth image, then the loop's saturation. The compiled :class:`PhaseStop` check
after every step only *proposes* a stop: the kernel returns after that step and the Python
:class:`PhaseStop` decides (it also runs after every chunk's last step). A call before the
world's first step or at a time not predicted runs in Python (nothing of it done in the
kernel); a step the compiled step cannot do returns after its call, and the loop's
reference iteration does the step (its call is no longer due).

Used when the run's controller is a :class:`~.controller.GaitController` with its compiled
step and the ``stop`` is a :class:`PhaseStop` of it (:meth:`GaitController.fast_loop_plugin`);
other runs keep :mod:`planner.sim.planar.fast_run`.
"""

from __future__ import annotations

import math
import time

import numpy as np

from planner.errors import InvalidParameter
from planner.exploration.planar import controller_kernel as ck
from planner.exploration.planar.gait_loop_kernel import (
    C_C0,
    C_CALLS,
    C_EVENT,
    C_FALLBACK,
    C_IMAGES,
    N_STOP,
    S_INDEX,
    S_N,
    S_REF,
    S_SLIP,
    STEP_IN_PYTHON,
    gait_advance,
)
from planner.exploration.planar.phase_segment import references
from planner.exploration.planar.sensing import B_C, B_TIPS
from planner.sim.lcp import COVERS
from planner.sim.planar.run_kernel import BLOW_UP, CALL_DUE, NPAIRS, PYTHON_STEP
from planner.sim.planar.sensing import _hand_geometry

__all__ = ["CHUNK", "GaitLoop", "PhaseStop"]

#: steps of the first kernel call of a run and after a step run in Python: chunks double up
#: to CHUNK while the kernel runs them through (references evaluated for calls the kernel
#: never reached were a third of the gait's Python time with fixed chunks)
FIRST_CHUNK = 4


try:  # the segments' vectorized references (s4-ball), equal to the callables' values
    from planner.exploration.planar.segments import segment_references as _vectorized
except ImportError:  # pragma: no cover (the branch without them)
    _vectorized = None

#: steps per kernel call at most (the references of its calls are evaluated ahead; past a
#: phase's end they are evaluated for nothing: cheap when vectorized)
CHUNK = 256 if _vectorized is not None else 64

#: ``rows0, pn0, pt0`` of :func:`gait_advance` when the world has not stepped yet
_NO_STEP = (np.zeros((0, 0)), np.zeros(0), np.zeros(0))


class PhaseStop:
    """The ``stop`` callback of one gait phase (the machine's per-step check).

    Returns the controller's event (:meth:`GaitController.stop`); with ``hold_slip`` (phases
    2/3: the held object must stay put) first ``"object moved"`` when every watched point
    moved more than ``hold_slip`` [m] from where it was after the phase's first step
    (``moved`` is then True). The watched points: the sensed object centre (``centre``)
    and the HOLDING fingertip's encoder position (``holder``: 0 left, 1 right).

    The machine watches the centre on the circle model and the fingertip on a posed
    outline. Neither signal is reliable alone, and watching both does not fix that (all
    measured on 2026-11-24):

    * on a flat face the centre estimate ``p + R n`` follows the pad's pressure centroid.
      It jumps 13-15 mm when the releasing finger lets go, while the object and the holding
      fingertip move 0.1 mm. On a 12 cm rounded square this raises a false alarm at the
      phase's first steps;
    * on the ball the centre estimate is exact, but the holding fingertip leads it: the tip
      had moved 10 mm when the dragged ball had moved 7 mm. Stopping then, 70 ms early,
      cost ``ball_with_ridge`` its gait (seeds 0/1: "no progress" at -26/-20 deg);
    * with both required, the false alarms are gone and the ball is unchanged, and the
      batch gave 34 instead of 32 successful runs of 96 (noise). But an object that slips
      out from under a still holding pad is no longer caught: ``long_thin_gait`` seeds 0
      and 2 ran on and ended as simulator faults instead of naming force closure.

    On a posed outline the circle's centre estimate means nothing, so the fingertip is all
    there is. ``progress(t)`` is called with the simulated time [s] after every step
    (from the compiled loop: after every chunk).
    """

    def __init__(self, ctrl, hold_slip: float | None = None, progress=None,
                 holder: int | None = None, centre: bool = True) -> None:  # fmt: skip
        if holder not in (None, 0, 1):
            raise InvalidParameter(f"holder must be None, 0 or 1, got {holder!r}")
        if holder is None and not centre:
            raise InvalidParameter("a PhaseStop watches the centre, a holding fingertip or both")
        self.ctrl, self.hold_slip, self.progress = ctrl, hold_slip, progress
        #: indices in the sensing buffer of the watched points' x (y follows)
        self.index = ((B_C.start,) if centre else ()) + (
            () if holder is None else (B_TIPS.start + 2 * holder,)
        )
        #: the watched points after the phase's first step [m], (len(index), 2)
        self.c0: np.ndarray | None = None
        self.moved = False

    def points(self) -> np.ndarray:
        """The watched points now [m], (len(index), 2) (a copy)."""
        buf = self.ctrl.sensing.est.buffer
        return np.array([buf[i : i + 2] for i in self.index])

    def __call__(self, t: float, world) -> str | None:
        points = self.points()
        if self.c0 is None:
            self.c0 = points
        if self.progress is not None:
            self.progress(t)
        if self.hold_slip is not None and all(
            math.hypot(*d) > self.hold_slip for d in points - self.c0
        ):
            self.moved = True
            return "object moved"
        return self.ctrl.stop(t, world)


class GaitLoop:
    """Runs :func:`.gait_loop_kernel.gait_advance` for a
    :class:`planner.sim.planar.fast_run.FastLoop` whose controller is ``ctrl`` and whose
    ``stop`` is a :class:`PhaseStop` of it (the plugin of
    :meth:`GaitController.fast_loop_plugin`).

    Per chunk: the call times of its steps are predicted with the loop's clock arithmetic,
    their references evaluated and their gauge noise drawn ahead (the generator is rewound
    and advanced by the calls made); after the kernel: the trace rows, kept images,
    fallbacks and step times go to the controller, the controller's event to
    :meth:`GaitController._event`, the stop after the chunk's last step to the Python
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
        self.stop_s = np.zeros(N_STOP)
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
        references into ``times``/``sv_rows``; returns their number. The references come
        from ``segments.segment_references`` (vectorized; s4-ball) when it exists, else
        from the segment's callables call by call (:func:`.phase_segment.references`)."""
        s, w, c = self.fast.s, self.fast.w, self.ctrl
        t, nc, per, h = w.time, s.next_call, s.period, w.dt
        k = 0
        for _ in range(m):
            if t >= nc - 1e-9 * h:
                self.times[k] = t
                k += 1
                nc += per * max(1, math.ceil((t - nc) / per + 1e-9))
            t = t + h
        if k:
            seg, times, rows = c.segment, self.times[:k], self.sv_rows[:k]
            tl = times - c.t0
            rows[:, ck.V_T], rows[:, ck.V_TL] = times, tl
            if _vectorized is not None:
                rows[:, : ck.V_T] = _vectorized(seg, tl)
            else:
                for i, x in enumerate(tl.tolist()):
                    rows[i, : ck.V_T] = (seg.hold_force(x), *references(seg, x))
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
        stop_s = self.stop_s
        stop_s[S_SLIP] = stop.hold_slip if stop.hold_slip is not None else 0.0
        stop_s[S_N] = len(stop.index)
        stop_s[S_INDEX : S_INDEX + len(stop.index)] = stop.index
        if stop.c0 is not None:
            stop_s[S_REF : S_REF + stop.c0.size] = stop.c0.ravel()
            cnt[C_C0] = 1
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
            c.compiled_calls += made
        if stop.c0 is None and cnt[C_C0]:
            k = len(stop.index)
            stop.c0 = self.stop_s[S_REF : S_REF + 2 * k].reshape(k, 2).copy()
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
