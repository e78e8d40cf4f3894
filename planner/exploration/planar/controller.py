"""The gait's controller: one callable ``controller(t, obs) -> tau`` for every phase (§2.2).

Per control step it (1) updates the sensed grasp (:mod:`.sensing`), (2) evaluates the
phase's references (plan of phase 1, or the exploring finger's path of phases 2/3, with the
startup ramps of §2.2.3), (3) runs the internal-force PI and the rolling PD (eq. 2.8) in
Python scalars, (4) runs the compiled step (:class:`planner.control.grasp_step.GraspStep`:
kinematics, Jacobians, object impedance eq. 2.7, fingertip impedance and the QP), and
(5) checks the events that end a phase: workspace limit, grasp stability lost, contact
lost, path finished. The first event is kept in :attr:`GaitController.event`; the world's
``stop`` callback returns it.
"""

from __future__ import annotations

import math
import struct
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from planner.control.grasp_layout import N_PAR, PAR, pack
from planner.control.grasp_stability import epsilon_two_contacts
from planner.control.internal_force import InternalForcePI, sensed_internal_force
from planner.control.rolling_pd import RollingGains, rolling_moment
from planner.exploration.planar.sensing import SOURCES, GraspSensing, round_contact_arclength
from planner.exploration.planar.settings import GaitSettings


@dataclass
class Segment:
    """The references of one phase (all callables of the time since the phase start [s]).

    Attributes:
        kind: 1, 2 or 3 (Fig. 2.3).
        duration: planned duration [s] ("path finished" after it).
        pose: ``t -> (x, y, theta), (vx, vy, omega)`` object references (phase 1).
        rolling: ``t -> (u_des, s_right_des, phi_des (2,), phid_des (2,))``: fingertip
            contact locations [m] and orientations [rad, rad/s] (phase 1 and the holding
            finger).
        explore: ``t -> (p_des (2,), v_des (2,), phi_des)`` of the exploring finger.
        hold_force: ``t -> internal / holding force [N]``.
        explore_force: ``t -> exploring normal force [N]``.
        theta0: object rotation estimate at the phase start [rad].
    """

    kind: int
    duration: float
    pose: Callable | None = None
    rolling: Callable | None = None
    explore: Callable | None = None
    hold_force: Callable | None = None
    explore_force: Callable | None = None
    theta0: float = 0.0


#: columns of :attr:`GaitController.trace` (sensed and commanded series, one row per call)
TRACE_NAMES = (
    "t", "kind", "u", "pad_touch", "pLx", "pLy", "pRx", "pRy", "nLx", "nLy", "nRx", "nRy",
    "cx", "cy", "theta", "fnL", "fnR", "f_cmd", "f_int", "pdx", "pdy", "u_des", "sR",
    "sR_des", "f_des", "fLx", "fLy", "fRx", "fRy",
)  # fmt: skip


class _Mode(NamedTuple):
    """What a phase kind fixes for every control step (looked up once per phase)."""

    kind: int
    source: int  # centre estimate of the sensing (planar.sensing.SOURCES)
    grasp: float  # the control step's grasp flag
    explorer: tuple[float, float]  # exploring flags of the left and right finger
    holder: int  # the finger anchored by its fingertip (phases 2/3)
    moving: tuple[int, ...]  # joints whose limits end the phase
    touching: tuple[int, ...]  # fingers whose contact loss ends the phase


_MODES = {
    1: _Mode(1, SOURCES["auto"], 1.0, (0.0, 0.0), 1, tuple(range(6)), (0, 1)),
    2: _Mode(2, SOURCES["pad"], 0.0, (0.0, 1.0), 0, tuple(range(3, 6)), (0,)),
    3: _Mode(3, SOURCES["palm"], 0.0, (1.0, 0.0), 1, tuple(range(3)), (1,)),
}

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
            control laws, the compiled step with its QP, the trace and the event checks).
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
                "mu": s.mu * (1 - s.friction_margin), "f_min": s.min_force,
                "tau_max": s.torque_limit, "kp_tip": s.tip_kp, "kv_tip": s.tip_kv,
                "f_n_tip": s.explore_force, "k_phi": s.phi_kp, "d_phi": s.phi_kv,
                "w_wrench": 1.0, "w_int": 1.0, "w_track": 1.0, "w_reg": 1e-4,
                "kp_hold": s.hold_stiffness, "kv_hold": s.hold_damping,
            },
            PAR, N_PAR,
        )  # fmt: skip
        self._pack = struct.Struct(f"{STEP_INPUTS}d").pack_into
        self._inputs, self._par = self.step.inputs, self.step.par
        self._f_n_tip = PAR["f_n_tip"].start
        self._dt = 1.0 / s.control_rate
        self._tau_bound = FALLBACK_RATIO * s.torque_limit
        self.segment: Segment | None = None
        self.t0 = 0.0
        self.event: str | None = None
        self.event_data: dict = {}
        self.theta = 0.0
        self._mode = _MODES[1]
        self._u0 = 0.0
        self._beta0 = 0.0
        self._weak = 0.0
        self._holder = 0
        self._hold_tip = (0.0, 0.0)
        self._trigger: tuple[list, list] | None = None
        self.step_times: list[float] = []
        self.fallbacks = 0  # control steps that used the safe fallback command
        self._last_tau = np.zeros(6)
        self.trace: list[tuple] = []
        self.images: list[tuple[float, np.ndarray]] = []

    # ------------------------------------------------------------------ phases
    def start(self, segment: Segment, t: float) -> None:
        """Begin ``segment`` at world time ``t`` [s]."""
        self.segment, self.t0 = segment, t
        self.event, self.event_data = None, {}
        self.theta = segment.theta0
        self._mode = _MODES[segment.kind]
        self._weak = 0.0
        e = self.sensing.est
        self._u0, self._beta0 = e.u, float(e.beta[0])
        # the holding finger is anchored by its fingertip point (encoders), not by the sensed
        # contact: the contact estimate jumps when the tactile centroid or the centre
        # estimate changes, and a stiff anchor on it dragged the held object
        self._holder = self._mode.holder
        self._hold_tip = tuple(e.tips[self._holder].tolist())
        self.pi.reset()
        self._trigger = None  # limit triggers, set from the phase's first joint reading

    # ------------------------------------------------------------------ the step
    def __call__(self, t: float, obs) -> np.ndarray:
        tau_t0 = time.perf_counter()
        seg, mode = self.segment, self._mode
        b = self.sensing.update_raw(obs, mode.source).tolist()  # layout B_* of .sensing
        q, qd = obs.q.tolist(), obs.qd.tolist()
        tl = t - self.t0
        R = self.sensing.radius
        kind = mode.kind
        u, cx = b[0], b[10]
        if kind == 1 and b[1]:  # rolling integration (eq. 2.4)
            self.theta = seg.theta0 + (b[12] - self._beta0) - (u - self._u0) / R
        f_des = seg.hold_force(tl)
        if kind == 1:
            sensed = sensed_internal_force(b[2:4], b[4:6], b[14:16], b[16:18])
        else:
            h = 2 * mode.holder
            fx, fy = b[14 + h], b[15 + h]
            sensed = sensed_internal_force(b[2 + h : 4 + h], (cx, 0.0), (fx, fy), (-fx, -fy))
        f_cmd = self.pi.command(f_des, sensed, self._dt)
        pose_now = seg.pose(tl) if seg.pose is not None else None
        m_roll = [0.0, 0.0]
        roll_cmd = (math.nan, math.nan, math.nan)
        if seg.rolling is not None:
            m_roll, roll_cmd = self._rolling(seg.rolling(tl), pose_now, b, qd)
        if pose_now is not None:
            (xx, xy, xt), (vx, vy, vt) = pose_now[0], pose_now[1]
        else:
            xx, xy, xt, vx, vy, vt = cx, b[11], 0.0, 0.0, 0.0, 0.0
        if seg.explore is not None:
            (pdx, pdy), (vdx, vdy), phi_des = seg.explore(tl)
        else:
            pdx, pdy, vdx, vdy, phi_des = 0.0, 0.0, 0.0, 0.0, 0.0
        ex = mode.explorer
        h = 2 * self._holder
        hx, hy = self._hold_tip
        geo = b[20:28]
        if kind == 3:  # the exploring pad is steered by its centre (it slides)
            geo[0] = geo[1] = 0.0
        self._pack(
            self._inputs, 0, *q, *qd, *geo,
            xx, xy, xt, vx, vy, vt, 0.0, 0.0, 0.0, self.theta, R, R, f_cmd, m_roll[0],
            m_roll[1], pdx, pdy, vdx, vdy, phi_des if ex[0] else 0.0,
            phi_des if ex[1] else 0.0, cx, 0.0, mode.grasp, ex[0], ex[1],
            hx + (b[2 + h] - b[28 + h]), hy + (b[3 + h] - b[29 + h]),
        )  # fmt: skip
        if seg.explore_force is not None:
            self._par[self._f_n_tip] = seg.explore_force(tl)
        tau = self.step()
        taus = tau.tolist()
        bound = self._tau_bound
        if math.isfinite(sum(taus)) and max(taus) <= bound and min(taus) >= -bound:
            tau = self._last_tau = tau.copy()
        else:
            # a near-singular finger Jacobian or an infeasible QP gave a command of tens of
            # N m: saturated at the torque limits it threw the light fingers into the object
            # (simulator faults); hold the last good command, damped, for this step instead
            tau = self._last_tau - FALLBACK_DAMPING * np.asarray(obs.qd, float)
            self.fallbacks += 1
        self.trace.append(
            (t, kind, *b[0:12], self.theta, b[18], b[19], f_cmd, sensed, pdx, pdy, *roll_cmd,
             f_des, *b[14:18])
        )  # fmt: skip
        if obs.tactile is not None and len(self.trace) % 5 == 0 and "left" in obs.tactile:
            self.images.append((t, obs.tactile["left"].copy()))
        if self.event is None:
            self._check_events(tl, q, b)
        self.step_times.append(time.perf_counter() - tau_t0)
        return tau

    def _rolling(self, refs, pose_now, b, qd) -> tuple[list, tuple]:
        """Distal moments of the grasping/holding fingers [N m] (rolling PD of eq. 2.8 in
        phase 1, orientation along the planned path) and the trace's rolling columns."""
        s, R, r = self.s, self.sensing.radius, self.r
        u_des, sR_des, phi_ref, phid_ref = refs
        sR = round_contact_arclength(b[13], b[33], r)
        m_roll = [0.0, 0.0]
        if self._mode.kind == 1:
            w_des = float(pose_now[1][2]) if pose_now is not None else 0.0
            # contact rates from pure rolling (eq. 2.4): ds = -d(phi - theta) / (k_f + k_o)
            sdL = -R * (qd[0] + qd[1] + qd[2] - w_des)
            sdR = -(r * R / (r + R)) * (qd[3] + qd[4] + qd[5] - w_des)
            m_roll = [rolling_moment(-b[0], sdL, -u_des, 0.0, self.roll),
                      rolling_moment(sR, sdR, sR_des, 0.0, self.roll)]  # fmt: skip
            kp = s.hold_kp
        else:
            # the holder of phases 2/3 gets no rolling PD: on a round tip its distal
            # moment becomes a tangential contact force (moment / tip radius) that
            # rolled the held object away along the palm
            kp = 0.0
        # orientation of each grasping/holding fingertip along its planned path
        for k in range(2):
            phid = qd[3 * k] + qd[3 * k + 1] + qd[3 * k + 2]
            m_roll[k] += kp * (phi_ref[k] - b[32 + k]) - s.hold_kv * (phid - phid_ref[k])
        return m_roll, (u_des, sR, sR_des)

    # ------------------------------------------------------------------ events
    def _check_events(self, tl: float, q: list, b: list) -> None:
        s, mode = self.s, self._mode
        if self._trigger is None:
            lo, hi = limit_triggers(q, self.lim, s.joint_margin)
            self._trigger = (lo.tolist(), hi.tolist())
        lo, hi = self._trigger
        started = tl > s.startup_time
        hit = [j for j in mode.moving if q[j] < lo[j] or q[j] > hi[j]]
        if hit and started:
            self._set("workspace limit", joints=hit)
            return
        weak = any(b[18 + k] < s.lost_force for k in mode.touching)
        self._weak = self._weak + 1.0 / s.control_rate if weak else 0.0
        if self._weak > s.lost_time and started:
            self._set("contact lost", fingers=list(mode.touching))
            return
        if mode.kind == 1 and started:
            e = self.sensing.est
            eps = epsilon_two_contacts(e.p, e.n, s.mu, -1.0)
            if eps < s.min_epsilon:
                self._set("grasp stability lost", epsilon=eps)
                return
        if tl >= self.segment.duration:
            self._set("path finished")

    def _set(self, kind: str, **data) -> None:
        self.event, self.event_data = kind, data

    def stop(self, t: float, world) -> str | None:
        """The ``stop`` callback of ``world.run``: the event that ends the phase, if any."""
        return self.event


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


__all__ = ["TRACE_NAMES", "GaitController", "Segment"]
