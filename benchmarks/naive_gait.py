"""The gait controller call written the plain way (numpy + Pinocchio + qpsolvers): the
"naive" column of the gait-controller row of ``bench_control.py``.

Same laws, same inputs, same outputs as
:class:`planner.exploration.planar.controller.GaitController` (the replay test checks the
torques agree): the sensing reads the tactile image with ``TactileArray.read`` and works on
numpy arrays, the step's inputs are assembled with ``grasp_layout.pack`` from dicts, the
control step is :func:`planner.control.grasp_reference.reference_step` (numpy, Pinocchio,
``qpsolvers.solve_qp`` with DAQP) and the stability event uses the vectorized
``planner.grasp.epsilon_two_planar``. It is the controller as first written, before the
hot path was compiled.
"""

from __future__ import annotations

import math
import time

import numpy as np

from planner.control.grasp_layout import N_REF, PAR, REF, pack
from planner.control.grasp_reference import reference_step
from planner.control.internal_force import sensed_internal_force
from planner.control.rolling_pd import rolling_moment
from planner.exploration.planar.controller import (
    FALLBACK_DAMPING,
    FALLBACK_RATIO,
    GaitController,
    limit_triggers,
)
from planner.exploration.planar.sensing import TOUCH_FORCE, round_contact_arclength


def numpy_sensing(sensing, obs, source: str) -> None:
    """The update of ``sensing.est`` (a ``GraspSensing``) in numpy (see planar.sensing)."""
    e, q = sensing.est, obs.q
    if obs.tactile is not None and "left" in obs.tactile:
        reading = sensing.array.read(obs.tactile["left"])
        e.pad_touch = bool(reading.in_contact and reading.force > TOUCH_FORCE)
        if e.pad_touch:
            e.u = float(reading.centroid[0])
    phiL = float(q[0] + q[1] + q[2])
    cL, sL = math.cos(phiL), math.sin(phiL)
    tipL, tipR = sensing._tip(0, q), sensing._tip(1, q)
    e.p[0] = tipL + e.u * np.array([cL, sL])
    e.n[0] = (sL, -cL)
    e.tips[0], e.tips[1] = tipL, tipR
    R, r = sensing.radius, sensing.r
    if source == "pad" or (source == "auto" and e.pad_touch):
        e.centre[:] = e.p[0] - R * e.n[0]
    else:
        dy = R - tipR[1]
        e.centre[:] = (tipR[0] - math.sqrt(max((R + r) ** 2 - dy * dy, 0.0)), R)
    d = e.centre - tipR
    d /= max(float(np.hypot(d[0], d[1])), 1e-12)
    e.p[1] = tipR + r * d
    e.n[1] = -d
    for k in range(2):
        v = e.p[k] - e.centre
        e.beta[k] = math.atan2(v[1], v[0])
    e.forces[:] = obs.tip_forces
    e.normal_force[:] = -np.sum(e.forces * e.n, axis=1)
    phiR = float(q[3] + q[4] + q[5])
    e.phi[:] = (phiL, phiR)
    cR, sR = math.cos(phiR), math.sin(phiR)
    dt = (cR * d[0] + sR * d[1], -sR * d[0] + cR * d[1])
    e.offsets[:] = (e.u, 0.0, r * dt[0], r * dt[1])
    e.tip_normals[:] = (0.0, 1.0, dt[0], dt[1])


class NaiveGaitController(GaitController):
    """:class:`GaitController` with the plain per-call path (see the module docstring)."""

    def __init__(self, hand, settings, radius, gravity) -> None:
        super().__init__(hand, settings, radius, gravity)
        self._data = hand.model.createData()
        self._f_n_tip = PAR["f_n_tip"].start
        self._theta = 0.0

    @property
    def theta(self) -> float:
        return self._theta

    def start(self, segment, t: float) -> None:
        super().start(segment, t)
        e = self.sensing.est
        self._theta = segment.theta0
        self._ref = False  # phase 1's rolling reference: its own first touching reading
        self._holder = 0 if segment.kind == 2 else 1
        self._hold_tip = e.tips[self._holder].copy()
        self._weak, self._trigger = 0.0, None
        self.pi.reset()

    def __call__(self, t: float, obs) -> np.ndarray:  # noqa: C901 (the plain version)
        seg, s, st = self.segment, self.s, self.step
        t_start = time.perf_counter()
        source = {1: "auto", 2: "pad", 3: "palm"}[seg.kind]
        numpy_sensing(self.sensing, obs, source)
        e = self.sensing.est
        tl, R = t - self.t0, self.sensing.radius
        if seg.kind == 1 and e.pad_touch:
            if not self._ref:
                self._u0, self._beta0, self._ref = e.u, e.beta[0], True
            self._theta = seg.theta0 + (e.beta[0] - self._beta0) - (e.u - self._u0) / R
        f_des = seg.hold_force(tl)
        if seg.kind == 1:
            sensed = sensed_internal_force(e.p[0], e.p[1], e.forces[0], e.forces[1])
        else:
            h = 0 if seg.kind == 2 else 1
            palm = np.array([e.centre[0], 0.0])
            sensed = sensed_internal_force(e.p[h], palm, e.forces[h], -e.forces[h])
        f_cmd = self.pi.command(f_des, sensed, 1.0 / s.control_rate)
        pose_now = seg.pose(tl) if seg.pose is not None else None
        m_roll, roll_cmd = [0.0, 0.0], (math.nan, math.nan, math.nan)
        if seg.rolling is not None:
            u_des, sR_des, phi_ref, phid_ref = seg.rolling(tl)
            phiR = float(obs.q[3] + obs.q[4] + obs.q[5])
            sR = round_contact_arclength(e.beta[1], phiR, self.r)
            roll_cmd = (u_des, sR, sR_des)
            w_des = float(pose_now[1][2]) if pose_now is not None else 0.0
            qd = obs.qd
            sdL = -R * (qd[0] + qd[1] + qd[2] - w_des)
            sdR = -(self.r * R / (self.r + R)) * (qd[3] + qd[4] + qd[5] - w_des)
            if seg.kind == 1:
                m_roll = [rolling_moment(-e.u, sdL, -u_des, 0.0, self.roll),
                          rolling_moment(sR, sdR, sR_des, 0.0, self.roll)]  # fmt: skip
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
        ex = {1: (0.0, 0.0), 2: (0.0, 1.0), 3: (1.0, 0.0)}[seg.kind]
        holder = self._holder
        ref = pack(
            {
                "x_des": x_des, "xd_des": xd_des, "theta_est": self.theta, "rho": (R, R),
                "f_int": f_cmd, "m_roll": m_roll, "p_des": p_des, "v_des": v_des,
                "phi_des": [phi_des if ex[0] else 0.0, phi_des if ex[1] else 0.0],
                "palm": (e.centre[0], 0.0), "flags": (1.0 if seg.kind == 1 else 0.0, *ex),
                "p_hold": np.asarray(self._hold_tip) + (e.p[holder] - e.tips[holder]),
            },
            REF, N_REF,
        )  # fmt: skip
        if seg.explore_force is not None:
            st.par[self._f_n_tip] = seg.explore_force(tl)
        geo = np.r_[e.offsets, e.tip_normals]
        if seg.kind == 3:
            geo[0:2] = 0.0
        out = reference_step(self.hand.model, self._data, np.asarray(obs.q, float),
                             np.asarray(obs.qd, float), geo, ref, st.par.copy())  # fmt: skip
        tau = np.asarray(out["tau"], float)
        if not np.all(np.isfinite(tau)) or np.max(np.abs(tau)) > FALLBACK_RATIO * s.torque_limit:
            tau = self._last_tau - FALLBACK_DAMPING * np.asarray(obs.qd, float)
            self.fallbacks += 1
        else:
            self._last_tau = tau
        self.trace.append(
            (t, seg.kind, e.u, e.pad_touch, *e.p.ravel(), *e.n.ravel(), *e.centre, self.theta,
             *e.normal_force, f_cmd, sensed, *p_des, *roll_cmd, f_des, *e.forces.ravel())
        )  # fmt: skip
        if obs.tactile is not None and len(self.trace) % 5 == 0 and "left" in obs.tactile:
            self.images.append((t, obs.tactile["left"].copy()))
        self._naive_events(tl, obs, e)
        self.step_times.append(time.perf_counter() - t_start)
        return tau

    def _set(self, kind: str, **data) -> None:
        self.event, self.event_data = kind, data

    def _naive_events(self, tl, obs, e) -> None:
        if self.event is not None:
            return
        from planner.grasp import epsilon_two_planar

        s, seg, q = self.s, self.segment, obs.q
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
            self._set("contact lost", fingers=list(touching))
            return
        if seg.kind == 1 and tl > s.startup_time:
            eps = float(epsilon_two_planar(e.p[0], -e.n[0], e.p[1], -e.n[1], s.mu))
            if eps < s.min_epsilon:
                self._set("grasp stability lost", epsilon=eps)
                return
        if tl >= seg.duration:
            self._set("path finished")


__all__ = ["NaiveGaitController", "numpy_sensing"]
