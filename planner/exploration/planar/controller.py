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
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from planner.control.grasp_layout import N_PAR, N_REF, PAR, REF, pack
from planner.control.internal_force import InternalForcePI, sensed_internal_force
from planner.control.rolling_pd import RollingGains, rolling_moment
from planner.exploration.planar.sensing import GraspSensing, round_contact_arclength
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


#: a command beyond this many torque limits is rejected (safe fallback) [-]
FALLBACK_RATIO = 5.0
#: joint damping of the fallback command [N m s/rad]
FALLBACK_DAMPING = 0.02


class GaitController:
    """The controller of the whole gait; :meth:`start` switches it to a new phase.

    Args:
        hand: the ``PlanarHand``; settings: :class:`GaitSettings`; radius: the estimate's
            radius [m]; gravity: (2,) [m/s^2].
    """

    def __init__(self, hand, settings: GaitSettings, radius: float, gravity) -> None:
        from planner.control.grasp_step import GraspStep

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
        self.segment: Segment | None = None
        self.t0 = 0.0
        self.event: str | None = None
        self.event_data: dict = {}
        self.theta = 0.0
        self._u0 = 0.0
        self._beta0 = 0.0
        self._weak = 0.0
        self._holder = 0
        self._hold_tip = np.zeros(2)
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
        self._weak = 0.0
        e = self.sensing.est
        self._u0, self._beta0 = e.u, e.beta[0]
        holder = 0 if segment.kind == 2 else 1
        # the holding finger is anchored by its fingertip point (encoders), not by the sensed
        # contact: the contact estimate jumps when the tactile centroid or the centre
        # estimate changes, and a stiff anchor on it dragged the held object
        self._holder = holder
        self._hold_tip = e.tips[holder].copy()
        self.pi.reset()
        self._trigger = None  # limit triggers, set from the phase's first joint reading

    # ------------------------------------------------------------------ the step
    def __call__(self, t: float, obs) -> np.ndarray:
        seg, s, st = self.segment, self.s, self.step
        tau_t0 = time.perf_counter()
        e = self.sensing.update(obs, {1: "auto", 2: "pad", 3: "palm"}[seg.kind])
        tl = t - self.t0
        R = self.sensing.radius
        ref = st.ref
        if seg.kind == 1 and e.pad_touch:  # rolling integration (eq. 2.4)
            self.theta = seg.theta0 + (e.beta[0] - self._beta0) - (e.u - self._u0) / R
        f_des = seg.hold_force(tl)
        if seg.kind == 1:
            sensed = sensed_internal_force(e.p[0], e.p[1], e.forces[0], e.forces[1])
        else:
            holder = 0 if seg.kind == 2 else 1
            palm = np.array([e.centre[0], 0.0])
            sensed = sensed_internal_force(e.p[holder], palm, e.forces[holder], -e.forces[holder])
        f_cmd = self.pi.command(f_des, sensed, 1.0 / s.control_rate)
        pose_now = seg.pose(tl) if seg.pose is not None else None
        m_roll = [0.0, 0.0]
        self._roll_cmd = (math.nan, math.nan, math.nan)
        if seg.rolling is not None:
            u_des, sR_des, phi_ref, phid_ref = seg.rolling(tl)
            phiR = float(obs.q[3] + obs.q[4] + obs.q[5])
            sR = round_contact_arclength(e.beta[1], phiR, self.r)
            self._roll_cmd = (u_des, sR, sR_des)
            w_des = float(pose_now[1][2]) if pose_now is not None else 0.0
            qd = obs.qd
            # contact rates from pure rolling (eq. 2.4): ds = -d(phi - theta) / (k_f + k_o)
            sdL = -R * (qd[0] + qd[1] + qd[2] - w_des)
            sdR = -(self.r * R / (self.r + R)) * (qd[3] + qd[4] + qd[5] - w_des)
            m_roll = [rolling_moment(-e.u, sdL, -u_des, 0.0, self.roll),
                      rolling_moment(sR, sdR, sR_des, 0.0, self.roll)]  # fmt: skip
            if seg.kind != 1:
                # the holder of phases 2/3 gets no rolling PD: on a round tip its distal
                # moment becomes a tangential contact force (moment / tip radius) that
                # rolled the held object away along the palm
                m_roll = [0.0, 0.0]
            # orientation of each grasping/holding fingertip along its planned path
            for k in range(2):
                phi = float(obs.q[3 * k] + obs.q[3 * k + 1] + obs.q[3 * k + 2])
                phid = float(qd[3 * k] + qd[3 * k + 1] + qd[3 * k + 2])
                kp = s.hold_kp if seg.kind == 1 else 0.0
                m_roll[k] += kp * (phi_ref[k] - phi) - s.hold_kv * (phid - phid_ref[k])
        x_des, xd_des = (
            pose_now if pose_now is not None else ((e.centre[0], e.centre[1], 0.0), (0, 0, 0))
        )
        p_des, v_des, phi_des = (
            seg.explore(tl) if seg.explore is not None else ((0.0, 0.0), (0.0, 0.0), 0.0)
        )
        explorer = {1: (0.0, 0.0), 2: (0.0, 1.0), 3: (1.0, 0.0)}[seg.kind]
        phis = [phi_des if explorer[0] else 0.0, phi_des if explorer[1] else 0.0]
        ref[:] = pack(
            {
                "x_des": x_des, "xd_des": xd_des, "theta_est": self.theta, "rho": (R, R),
                "f_int": f_cmd, "m_roll": m_roll, "p_des": p_des, "v_des": v_des,
                "phi_des": phis, "palm": (e.centre[0], 0.0),
                "flags": (1.0 if seg.kind == 1 else 0.0, explorer[0], explorer[1]),
                "p_hold": self._hold_tip + (e.p[self._holder] - e.tips[self._holder]),
            },
            REF, N_REF,
        )  # fmt: skip
        if seg.explore_force is not None:
            st.par[PAR["f_n_tip"]] = seg.explore_force(tl)
        st.q[:], st.qd[:] = obs.q, obs.qd
        st.geo[:4], st.geo[4:] = e.offsets, e.tip_normals
        if seg.kind == 3:  # the exploring pad is steered by its centre (it slides)
            st.geo[0:2] = 0.0
        tau = st().copy()
        if not np.all(np.isfinite(tau)) or np.max(np.abs(tau)) > FALLBACK_RATIO * s.torque_limit:
            # a near-singular finger Jacobian or an infeasible QP gave a command of tens of
            # N m: saturated at the torque limits it threw the light fingers into the object
            # (simulator faults); hold the last good command, damped, for this step instead
            tau = self._last_tau - FALLBACK_DAMPING * np.asarray(obs.qd, float)
            self.fallbacks += 1
        else:
            self._last_tau = tau
        self.step_times.append(time.perf_counter() - tau_t0)
        self.trace.append(
            (t, seg.kind, e.u, e.pad_touch, *e.p.ravel(), *e.n.ravel(), *e.centre, self.theta,
             *e.normal_force, f_cmd, sensed, *p_des, *self._roll_cmd, f_des,
             *e.forces.ravel())
        )  # fmt: skip
        if obs.tactile is not None and len(self.trace) % 5 == 0 and "left" in obs.tactile:
            self.images.append((t, obs.tactile["left"].copy()))
        self._check_events(t, tl, obs, e)
        return tau

    # ------------------------------------------------------------------ events
    def _check_events(self, t, tl, obs, e) -> None:
        if self.event is not None:
            return
        s, seg = self.s, self.segment
        q = obs.q
        if self._trigger is None:
            self._trigger = limit_triggers(q, self.lim, s.joint_margin)
        lo, hi = self._trigger
        near = np.flatnonzero((q < lo) | (q > hi))
        moving = {1: range(6), 2: range(3, 6), 3: range(0, 3)}[seg.kind]
        hit = [int(j) for j in near if j in moving]
        if hit and tl > s.startup_time:
            self._set("workspace limit", joints=hit)
            return
        touching = {1: (0, 1), 2: (0,), 3: (1,)}[seg.kind]
        weak = any(e.normal_force[k] < s.lost_force for k in touching)
        self._weak = self._weak + 1.0 / s.control_rate if weak else 0.0
        if self._weak > s.lost_time and tl > s.startup_time:
            self._set("contact lost", fingers=[k for k in touching])
            return
        if seg.kind == 1 and tl > s.startup_time:
            from planner.grasp import epsilon_two_planar

            eps = float(epsilon_two_planar(e.p[0], -e.n[0], e.p[1], -e.n[1], s.mu))
            if eps < s.min_epsilon:
                self._set("grasp stability lost", epsilon=eps)
                return
        if tl >= seg.duration:
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
