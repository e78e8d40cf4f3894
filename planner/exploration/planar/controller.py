"""The gait's controller: one callable ``controller(t, obs) -> tau`` for every phase (§2.2).

Per control step it (1) evaluates the phase's references (plan of phase 1, or the exploring
finger's path of phases 2/3, with the startup ramps of §2.2.3: the segment's callables),
(2) runs one compiled kernel (:func:`.controller_kernel.gait_kernel`): the sensed grasp of
:mod:`.sensing`, the object rotation estimate, the internal-force PI and the rolling PD
(eq. 2.8), the step's inputs, the compiled step itself
(:class:`planner.control.grasp_step.GraspStep`: kinematics, Jacobians, object impedance
eq. 2.7, fingertip impedance and the QP, called through its C entry point), the check of
its command (a command beyond :data:`FALLBACK_RATIO` torque limits is replaced), the trace
row and the checks of the events that end a phase (workspace limit, contact lost, grasp
stability lost, path finished). The first event is kept in
:attr:`GaitController.event`; the world's ``stop`` callback returns it.

The laws themselves live in :mod:`planner.control` (the reference implementations, used by
the plain controller of ``benchmarks/naive_gait.py``); the replay test
(tests/test_gait_controller.py) checks torques, trace and events against the controller as
first written, on observations recorded from ``ball_with_ridge``.

Run with a :class:`.gait_loop.PhaseStop` in the planar world's compiled loop, the calls of a
phase run inside that loop (:meth:`GaitController.fast_loop_plugin`, :mod:`.gait_loop`):
the same kernel on the same readings, many steps per numba call.
"""

from __future__ import annotations

import math
import struct
import time

import numpy as np

from planner.control.grasp_layout import N_PAR, PAR, pack
from planner.control.internal_force import InternalForcePI
from planner.control.rolling_pd import RollingGains
from planner.exploration.planar import controller_kernel as ck
from planner.exploration.planar.controller_kernel import gait_kernel
from planner.exploration.planar.phase_segment import Segment, references
from planner.exploration.planar.sensing import SOURCES, GraspSensing
from planner.exploration.planar.settings import GaitSettings

#: columns of :attr:`GaitController.trace` (sensed and commanded series, one row per call)
TRACE_NAMES = (
    "t", "kind", "u", "pad_touch", "pLx", "pLy", "pRx", "pRy", "nLx", "nLy", "nRx", "nRy",
    "cx", "cy", "theta", "fnL", "fnR", "f_cmd", "f_int", "pdx", "pdy", "u_des", "sR",
    "sR_des", "f_des", "fLx", "fLy", "fRx", "fRy",
)  # fmt: skip


#: a command beyond this many torque limits is rejected (safe fallback) [-]
FALLBACK_RATIO = 5.0
#: joint damping of the fallback command [N m s/rad]
FALLBACK_DAMPING = 0.02


class GaitController:
    """The controller of the whole gait; :meth:`start` switches it to a new phase.

    Args:
        hand: the ``PlanarHand``; settings: :class:`GaitSettings`; radius: the estimate's
            radius [m]; gravity: (2,) [m/s^2].

    Attributes:
        step_times: wall time of every call [s] (the whole call: sensing, references,
            control laws, the compiled step with its QP, the trace and the event checks;
            for the calls made in the compiled phase loop, ``compiled_calls`` of them, the
            chunk's wall time per call: the call AND its simulator step).
        compiled_calls: how many calls ran in the compiled phase loop.
    """

    def __init__(self, hand, settings: GaitSettings, radius: float, gravity) -> None:
        from planner.control.grasp_step import STEP_INPUTS, GraspStep

        self.hand, self.s = hand, settings
        self.step = GraspStep(hand)
        self.sensing = GraspSensing(hand, radius)
        self.r = hand.params.right.tip_radius
        self.pi = InternalForcePI(settings.internal_gains)
        self.roll = RollingGains(*settings.rolling_gains)
        self.lim = hand.joint_limits
        s = settings
        self.step.par[:] = pack(
            {
                "kp": s.object_kp, "kv": s.object_kv, "mass": s.object_mass,
                "inertia": s.object_mass * radius**2 / 2, "gravity": gravity,
                "mu": s.planning_mu, "f_min": s.min_force,
                "tau_max": s.torque_limit, "kp_tip": s.tip_kp, "kv_tip": s.tip_kv,
                "f_n_tip": s.explore_force, "k_phi": s.phi_kp, "d_phi": s.phi_kv,
                "w_wrench": 1.0, "w_int": 1.0, "w_track": 1.0, "w_reg": 1e-4,
                "kp_hold": s.hold_stiffness, "kv_hold": s.hold_damping,
            },
            PAR, N_PAR,
        )  # fmt: skip
        self._ks = _constants(self, STEP_INPUTS + PAR["f_n_tip"].start)
        self._sv = np.zeros(ck.N_SV)
        self._inputs = self.step.inputs
        self._row = np.zeros(len(TRACE_NAMES))
        self._pack_sv = struct.Struct(f"{ck.N_SV}d").pack_into
        self._tau_bound = FALLBACK_RATIO * s.torque_limit
        self._tau = self.step.tau
        entry = self.step.c_entry  # the kernel runs the compiled step itself
        self._python_step = entry is None
        if entry is not None:  # addresses < 2**53: exact as float64
            self._ks[ck.K_STEP_FN], self._ks[ck.K_STEP_ARG] = entry
        self._ks[ck.K_TAU_BOUND] = self._tau_bound
        self.segment: Segment | None = None
        self.t0 = 0.0
        self.event: str | None = None
        self.event_data: dict = {}
        self.step_times: list[float] = []
        self.compiled_calls = 0
        self.fallbacks = 0  # control steps that used the safe fallback command
        self._last_tau = np.zeros(6)
        self.trace: list[tuple] = []
        self.images: list[tuple[float, np.ndarray]] = []

    @property
    def theta(self) -> float:
        """The object rotation estimate [rad] (rolling integration of eq. 2.4 in phase 1)."""
        return float(self._ks[ck.S_THETA])

    def set_radius(self, radius: float) -> None:
        """Use ``radius`` [m] as the estimate's radius (sensing, rolling integration, object
        model) from the next control step on (SH's executor re-plans non-round objects on a
        local circle; needs ``GraspSensing.set_radius`` of s4-shape)."""
        self.sensing.set_radius(radius)
        self._ks[ck.K_R] = float(radius)

    # ------------------------------------------------------------------ phases
    def start(self, segment: Segment, t: float) -> None:
        """Begin ``segment`` at world time ``t`` [s]."""
        self.segment, self.t0 = segment, t
        self.event, self.event_data = None, {}
        kind = segment.kind
        ex = {1: (0.0, 0.0), 2: (0.0, 1.0), 3: (1.0, 0.0)}[kind]
        e, ks = self.sensing.est, self._ks
        # the holding finger is anchored by its fingertip point (encoders), not by the sensed
        # contact: the contact estimate jumps when the tactile centroid or the centre
        # estimate changes, and a stiff anchor on it dragged the held object
        holder = 0 if kind == 2 else 1
        ks[ck.K_KIND], ks[ck.K_SOURCE] = kind, SOURCES[{1: "auto", 2: "pad", 3: "palm"}[kind]]
        ks[ck.K_HOLDER], ks[ck.K_EX0], ks[ck.K_EX1] = holder, ex[0], ex[1]
        ks[ck.K_GRASP] = 1.0 if kind == 1 else 0.0
        ks[ck.K_THETA0] = ks[ck.S_THETA] = segment.theta0
        ks[ck.K_DURATION] = segment.duration
        # phase 1's rolling reference (S_U0, S_BETA0) is taken by the kernel at the phase's
        # first touching reading, not from the last estimate: phase 3's pad ends with its
        # centroid wherever its stroke left it (on a ridge at the array's edge: 8.75 mm),
        # phase 1's squeeze moves it onto the ball's contact (1.9 mm), and a reference from
        # before read that as 7.9 deg of rotation (ridge at 225 deg: the object impedance
        # chased it into the right finger's joint limit, three times, "no progress")
        ks[ck.S_REF] = 0.0
        ks[ck.S_HOLD : ck.S_HOLD + 2] = e.tips[holder]
        ks[ck.S_INT] = 0.0  # the internal-force PI restarts
        ks[ck.S_WEAK] = 0.0
        ks[ck.S_TRIG] = 0.0  # limit triggers, set from the phase's first joint reading
        ks[ck.S_DONE] = 0.0
        servo = segment.contact_target is not None and kind == 3
        ks[ck.K_USERVO] = 1.0 if servo else 0.0
        ks[ck.K_UTARGET] = float(segment.contact_target) if servo else 0.0
        ks[ck.S_UINT] = 0.0

    # ------------------------------------------------------------------ the step
    def __call__(self, t: float, obs) -> np.ndarray:
        tau_t0 = time.perf_counter()
        seg = self.segment
        tl = t - self.t0
        self._pack_sv(self._sv, 0, seg.hold_force(tl), *references(seg, tl), t, tl)
        tactile = obs.tactile
        image = tactile.get("left") if tactile is not None else None
        sensing = self.sensing
        code = gait_kernel(
            obs.q, obs.qd, obs.tip_forces, sensing._no_image if image is None else image,
            image is not None, sensing.geo, sensing.taxel_u, sensing.buffer, self._sv,
            self._ks, self._inputs, self._row, self._tau,
        )  # fmt: skip
        if self._python_step:
            tau = self.step()
            taus = tau.tolist()
            bound = self._tau_bound
            ok = math.isfinite(sum(taus)) and max(taus) <= bound and min(taus) >= -bound
            code |= 0 if ok else ck.REJECTED
        if code & ck.REJECTED:
            # a near-singular finger Jacobian or an infeasible QP gave a command of tens of
            # N m: saturated at the torque limits it threw the light fingers into the object
            # (simulator faults); hold the last good command, damped, for this step instead
            tau = self._last_tau - FALLBACK_DAMPING * np.asarray(obs.qd, float)
            self.fallbacks += 1
        else:
            tau = self._last_tau = self._tau.copy()
        self.trace.append(tuple(self._row.tolist()))
        if image is not None and len(self.trace) % 5 == 0:
            self.images.append((t, image.copy()))
        if code & 7:
            self._event(code & 7)
        self.step_times.append(time.perf_counter() - tau_t0)
        return tau

    def _event(self, code: int) -> None:
        """Record the event the kernel found (code of ``controller_kernel.EVENTS``)."""
        ks = self._ks
        kind = ck.EVENTS[code]
        if code == 1:
            hit = int(ks[ck.S_HIT])
            self._set(kind, joints=[j for j in range(6) if hit >> j & 1])
        elif code == 2:
            touching = {1: [0, 1], 2: [0], 3: [1]}[self.segment.kind]
            self._set(kind, fingers=touching)
        elif code == 3:
            self._set(kind, epsilon=float(ks[ck.S_EPS]))
        else:
            self._set(kind)

    def _set(self, kind: str, **data) -> None:
        self.event, self.event_data = kind, data
        self._ks[ck.S_DONE] = 1.0

    def stop(self, t: float, world) -> str | None:
        """The ``stop`` callback of ``world.run``: the event that ends the phase, if any."""
        return self.event

    def fast_loop_plugin(self, fast, stop):
        """The compiled phase loop (:class:`.gait_loop.GaitLoop`) for a run of the planar
        world's compiled loop ``fast`` with ``stop`` (a :class:`.gait_loop.PhaseStop` of
        this controller), or None (then the loop calls :meth:`__call__` and ``stop``)."""
        from planner.exploration.planar.gait_loop import GaitLoop

        return GaitLoop(fast, self, stop) if GaitLoop.usable(fast, self, stop) else None


def _constants(ctrl: GaitController, f_n_tip: int) -> np.ndarray:
    """The constant part of the kernel's ``ks`` array for ``ctrl``."""
    s, g, roll = ctrl.s, ctrl.pi.gains, ctrl.roll
    ks = np.zeros(ck.N_KS)
    ks[: ck.K_LIM_LO] = (
        ctrl.sensing.radius, ctrl.r, 1.0 / s.control_rate, g.kp, g.ki, g.max_correction,
        roll.kp, roll.kv, roll.max_moment, s.hold_kp, s.hold_kv, s.startup_time,
        s.lost_force, s.lost_time, s.mu, s.min_epsilon, s.joint_margin,
    )  # fmt: skip
    ks[ck.K_LIM_LO : ck.K_LIM_LO + 6] = ctrl.lim[:, 0]
    ks[ck.K_LIM_HI : ck.K_LIM_HI + 6] = ctrl.lim[:, 1]
    ks[ck.K_F_NT] = f_n_tip
    ks[ck.K_RTIP_L] = ctrl.sensing.r_left
    return ks


def limit_triggers(q, lim, margin: float) -> tuple[np.ndarray, np.ndarray]:
    """Joint angles [rad] beyond which a finger is at its workspace limit in this phase.

    A joint is at its limit within ``margin`` [rad] of it; a joint that STARTS the phase
    inside that band triggers only after moving a further ``margin`` toward the limit
    (a phase that starts next to a limit and moves away from it must not end at once: ending
    phases 2/3 right after their startup segment stalled the whole gait)."""
    q = np.asarray(q, float)
    lo = np.minimum(lim[:, 0] + margin, q - margin)
    hi = np.maximum(lim[:, 1] - margin, q + margin)
    return lo, hi


def trace_arrays(ctrl) -> dict:
    """The controller's sensed series as arrays (columns ``TRACE_NAMES``) and the tactile
    images it kept (``image_t`` (M,), ``images`` (M, 8, 8))."""
    n = len(TRACE_NAMES)
    tr = np.array(ctrl.trace, dtype=float) if ctrl.trace else np.zeros((0, n))
    out = {k: tr[:, i] for i, k in enumerate(TRACE_NAMES)}
    out["image_t"] = np.array([t for t, _ in ctrl.images])
    out["images"] = np.array([im for _, im in ctrl.images]) if ctrl.images else np.zeros((0, 8, 8))
    return out


__all__ = ["TRACE_NAMES", "GaitController", "Segment", "trace_arrays"]
