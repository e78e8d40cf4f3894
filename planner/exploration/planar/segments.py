"""Planning of one phase into a :class:`~.controller.Segment` (re-done at every phase start
from the current sensed estimate; §2.2.2-2.2.3).

* phase 1: the rolling NLP (:class:`planner.trajectory.RollingNLP`) from the sensed state;
  object pose and fingertip contact locations are interpolated between its knots; a startup
  segment ramps the internal force and lifts the object off the palm;
* phases 2/3: the exploring finger's contact runs along the estimated outline (the nominal
  circle about the estimated centre) from where it is to its next grasp angle, on a quintic
  (startup) profile; its orientation is interpolated to the four-region preference (round
  tip) or follows the surface (flat pad, which slides); the holding finger keeps its contact
  and ramps to the holding force, the explorer's normal force ramps to 0.3 N.
"""

from __future__ import annotations

import math

import numpy as np

from planner.exploration.planar.controller import Segment
from planner.exploration.planar.heuristics import pad_angle, preferred_orientation
from planner.exploration.planar.sensing import round_contact_arclength
from planner.trajectory import ForceRamp, QuinticSpline

#: largest change of the round exploring tip's orientation in one phase [rad] (0: the tip
#: slides without re-orienting; 0.15 still ended runs in simulator faults, see the report)
MAX_REORIENT = 0.0


def _interp(times: np.ndarray, values: np.ndarray):
    """Piecewise-linear ``t -> (value, rate)`` through knots (held outside)."""

    def f(t: float):
        k = int(np.clip(np.searchsorted(times, t) - 1, 0, len(times) - 2))
        h = times[k + 1] - times[k]
        w = min(max((t - times[k]) / h, 0.0), 1.0)
        rate = (values[k + 1] - values[k]) / h if times[0] <= t <= times[-1] else 0 * values[0]
        return values[k] + w * (values[k + 1] - values[k]), rate

    return f


def phase1_segment(plan, est, q, theta0: float, settings, hand, lift: float) -> Segment:
    """The phase-1 segment following ``plan`` (a :class:`RollingPlan`) from the sensed
    estimate ``est`` and joint angles ``q`` [rad]; ``theta0`` is the rotation estimate."""
    s = settings
    rot = abs(plan.rotation)
    T_move = max(rot / s.rotation_speed, 0.1)
    ts = s.startup_time + np.linspace(0.0, T_move, len(plan.theta))
    ts = np.concatenate([[0.0], ts])
    pose = np.column_stack([plan.centre, theta0 + plan.theta])
    pose = np.vstack([[est.centre[0], est.centre[1], theta0], pose])
    pose[1:, 1] += lift
    pose_f = _interp(ts, pose)
    r = hand.params.right.tip_radius
    phiR = plan.q[:, 3:6].sum(axis=1)
    sR = np.array(
        [round_contact_arclength(b, p, r) for b, p in zip(plan.beta[:, 1], phiR, strict=True)]
    )
    phis = np.column_stack([plan.q[:, 0:3].sum(axis=1), phiR])
    roll = np.column_stack([plan.u, sR, phis])
    roll = np.vstack([roll[0], roll])
    roll_f = _interp(ts, roll)

    def rolling(t):
        v, rate = roll_f(t)
        return v[0], v[1], v[2:4], rate[2:4]

    f0 = float(max(min(est.normal_force), 0.0))
    ramp = ForceRamp(f0, s.internal_force, s.startup_time)
    return Segment(
        kind=1,
        duration=float(ts[-1]) + 0.05,
        pose=pose_f,
        rolling=rolling,
        hold_force=lambda t: float(ramp(t)),
        theta0=theta0,
    )


def explore_segment(kind: int, est, q, target_beta: float, theta0: float, settings, hand):
    """The phase-2 (``kind`` 2: right explores) or phase-3 (left explores) segment that
    moves the explorer's contact from its sensed angle to ``target_beta`` [rad]."""
    s = settings
    k = 1 if kind == 2 else 0
    radius = float(np.linalg.norm(est.p[k] - est.centre))
    b0 = float(est.beta[k])
    b1 = b0 + math.atan2(math.sin(target_beta - b0), math.cos(target_beta - b0))
    T_move = max(abs(b1 - b0) * radius / s.explore_speed, 0.05)
    T = s.startup_time + T_move
    spline = QuinticSpline.between([b0], [b1], T_move)
    c = est.centre.copy()
    r = hand.params.right.tip_radius
    if k == 1:
        phi0 = float(q[3:6].sum())
        end = c + (radius + r) * np.array([math.cos(b1), math.sin(b1)])
        apex = b1 + 0.5 * math.pi
        pref = preferred_orientation(hand, "right", end)
        lim = 0.5  # keep the contact within 0.5 rad of the apex
        phi1 = apex + float(np.clip(pref - apex, -lim, lim))
        # turn the tip towards that orientation by at most MAX_REORIENT per phase: on a
        # 10 cm ball the full turn twisted the finger into its joint-2 stop, phase 2 ended
        # at the workspace limit and the gait stalled (transition 4 on every cycle)
        phi1 = phi0 + float(np.clip(phi1 - phi0, -MAX_REORIENT, MAX_REORIENT))

        def phi_of(t, b):
            w = min(max((t - s.startup_time) / T_move, 0.0), 1.0)
            return phi0 + w * (phi1 - phi0)
    else:
        phi0 = float(q[0:3].sum())

        def phi_of(t, b):
            return pad_angle(b, phi0)

    def explore(t: float):
        (b,), (bd,), _ = spline(t - s.startup_time)
        n = np.array([math.cos(b), math.sin(b)])
        tang = np.array([-math.sin(b), math.cos(b)])
        p = c + radius * n
        v = radius * bd * tang
        return (p[0], p[1]), (v[0], v[1]), phi_of(t, b)

    holder = 0 if kind == 2 else 1
    f_hold0 = float(max(est.normal_force[holder], 0.0))
    hold = ForceRamp(f_hold0, s.internal_force, s.startup_time)
    f_exp0 = float(max(est.normal_force[k], 0.0))
    fexp = ForceRamp(f_exp0, s.explore_force, s.startup_time)
    phiR = float(q[3:6].sum())
    keep = (est.u, round_contact_arclength(est.beta[1], phiR, r),
            np.array([q[0:3].sum(), phiR]), np.zeros(2))  # fmt: skip
    return Segment(
        kind=kind,
        duration=T + 0.02,
        explore=explore,
        rolling=lambda t: keep,
        hold_force=lambda t: float(hold(t)),
        explore_force=lambda t: float(fexp(t)),
        theta0=theta0,
    )


__all__ = ["explore_segment", "phase1_segment"]
