"""Planning each phase from the current estimate (§2.2.3: "The planning is done dynamically
at the start of each phase, using a current estimate of the object curvature and surface
orientation"): the planner of round nominal shapes, and the phase-1 pieces the posed-outline
planner (:mod:`.shape_planning`) shares with it.

Phase 1 is the rolling NLP on the local circle (:func:`fit_radius`), squeezed to carry the
object off the palm after a phase 1 that rolled it there (:func:`carry_squeeze`); phase 2
sends the right finger back to where it can hold the object on the palm
(:func:`right_hold_angle`); phase 3 sends the left pad to the §2.2.3 regrasp
(:func:`left_regrasp_angle`), after a back-stroke over a feature it slid across
(:func:`feature_behind`) or a corner probe beyond a wall it jumped (:mod:`.corner_probe`).
Every function takes the executor's runner (:class:`.machine._Runner`: its settings ``s``,
``hand``, ``ctrl``, ``start`` grasp, rotation estimate ``theta``, sensed features, phase
records and events).
"""

from __future__ import annotations

import math

import numpy as np

from planner.exploration.planar.carry_squeeze import phase1_squeeze
from planner.exploration.planar.controller import TRACE_NAMES
from planner.exploration.planar.corner_probe import (
    approach_segment,
    probe_segment,
    top_sweep_back,
    wall_ahead,
)
from planner.exploration.planar.heuristics import regrasp_left_angle, stable_pair
from planner.exploration.planar.segments import explore_segment, phase1_segment
from planner.exploration.planar.sensed_features import rotation_cap as _cap
from planner.exploration.planar.sensed_features import sensed_bump

#: contact travel [rad] expected in one phase 1 (the regrasp heuristics keep joint range for
#: it; the first rotation of the 10 cm ball moved the contacts 16-24 deg)
PHASE1_TRAVEL = math.radians(22.0)
#: how far the phase-1 pose reference lifts the object off the palm [m]
PHASE1_LIFT = 0.0015
#: range of the fitted local radius, in nominal radii [-]
RADIUS_FIT = (0.85, 1.2)
#: sensed features closer than this (object frame) are one [rad]
SAME_FEATURE = math.radians(15.0)


def plan(r, kind: int, est, q):
    """``(segment or None, planned rotation [rad], solve time [s], why no plan)`` of the
    next phase of a round nominal shape from the estimate ``est`` at joint angles ``q``."""
    s = r.s
    if kind == 1:
        tip = r.hand.params.right.tip_radius
        mu = s.planning_mu
        R = fit_radius(r, est, tip)
        r.ctrl.sensing.radius = R
        est = r.ctrl.sensing.update(r.world.observe(), "auto")
        p = r.nlp.solve(q, est.centre, R, tip, mu, est.beta, est.u, **nlp_options(r))
        return phase1_outcome(r, p, est, q, mu)
    if kind == 2:
        target = max(r.start["beta"][1], right_hold_angle(r))
        back = top_sweep(r, est, target)
        if back is not None:
            seg = explore_segment(2, est, q, target, r.theta, s, r.hand, PHASE1_TRAVEL,
                                  via=back)  # fmt: skip
            return seg, 0.0, 0.0, ""
    elif r._via is not None:  # the back-stroke: onto the feature's far side and back
        via, r._via, r._stroking = r._via, None, True
        seg = explore_segment(3, est, q, float(est.beta[0]), r.theta, s, r.hand,
                              PHASE1_TRAVEL, via=via)  # fmt: skip
        return seg, 0.0, 0.0, ""
    else:
        target = left_regrasp_angle(r, est)
        aim = corner_aim(r, est)
        if aim is not None:  # first the pad's end into the corner beyond a wall
            r._stroking = True
            seg = probe_segment(est, q, aim, target, r.theta, s, r.hand)
            return seg, 0.0, 0.0, ""
        seg = pad_stroke(r, est, q, target)
        if seg is not None:  # the pad's end first to a known wall, or back into its last stroke
            return seg, 0.0, 0.0, ""
    seg = explore_segment(kind, est, q, target, r.theta, s, r.hand, PHASE1_TRAVEL)
    return seg, 0.0, 0.0, ""


def top_sweep(r, est, target: float) -> float | None:
    """The world angle [rad] this phase 2's round tip first sweeps back to over a ridge's
    top (:func:`.corner_probe.top_sweep_back`; ``top_sweep`` on, round nominal shapes
    only), or None."""
    if not r.s.top_sweep or r.corner is None or r.shape is not None:
        return None
    beta = float(est.beta[1])
    back = top_sweep_back(r.corner.walls, r.theta, beta, float(target))
    if back is not None:
        gap = math.degrees(abs(math.remainder(back - beta, 2 * math.pi)))
        msg = f"the right tip sweeps back {gap:.1f} deg over the ridge's top towards its wall"
        r.events.append({"t": r.world.time, "kind": "top_sweep", "message": msg})
    return back


def corner_aim(r, est) -> float | None:
    """The world angle [rad] a corner probe aims the pad's end at in this phase 3, or None
    (:meth:`.corner_probe.CornerProbe.aim`; round nominal shapes only)."""
    if r.corner is None or r.shape is not None:
        return None
    aim = r.corner.aim(r.theta, float(est.beta[0]))
    if aim is not None:
        msg = f"probe the corner beyond the wall at {math.degrees(aim):.0f} deg (world)"
        r.events.append({"t": r.world.time, "kind": "corner_probe", "message": msg})
    return aim


def pad_stroke(r, est, q, target: float):
    """A phase 3 other than the plain stroke to ``target`` (world polar angle [rad]), or
    None: with ``wall_approach`` the pad's end first towards a wall it stalled at before
    (:func:`.corner_probe.approach_segment`, a back-stroke record: its rows beside the
    wall are no ridge), else a stroke that first goes back into the pad's previous one
    (:func:`overlap_back`; its contact centred on the pad). Round nominal shapes only."""
    s = r.s
    if r.shape is not None:
        return None
    if s.wall_approach and r.corner is not None:
        wall = wall_ahead(r.corner.walls, r.theta, float(est.beta[0]), target)
        if wall is not None:
            r._stroking = True
            msg = f"the pad's end first towards the wall at {math.degrees(wall):.0f} deg"
            r.events.append({"t": r.world.time, "kind": "wall_approach", "message": msg})
            return approach_segment(est, q, target, r.theta, s, r.hand)
    back = overlap_back(r, est, target)
    if back is None:
        return None
    return explore_segment(3, est, q, target, r.theta, s, r.hand, PHASE1_TRAVEL, via=back,
                           edge=False)  # fmt: skip


def overlap_back(r, est, target: float) -> float | None:
    """The world angle [rad] this phase 3's pad first goes back to, so that its stroke
    overlaps its previous one (:meth:`.stroke_overlap.ExploredOutline.back_to`; round
    nominal shapes only), or None."""
    if r.explored is None or r.shape is not None:
        return None
    walls = [w for w, _ in r.corner.walls] if r.corner is not None else []
    beta = float(est.beta[0])
    back = r.explored.back_to(beta, float(target), r.theta, (*r.sensed_features, *walls))
    if back is not None:
        gap = math.degrees(abs(math.remainder(back - beta, 2 * math.pi)))
        msg = f"the pad goes back {gap:.1f} deg into its previous stroke"
        r.events.append({"t": r.world.time, "kind": "stroke_overlap", "message": msg})
    return back


def nlp_options(r) -> dict:
    """The phase-1 NLP's margins, home and rotation cap (keyword arguments of ``solve``)."""
    s = r.s
    return {
        "margin": s.nlp_margin,
        "joint_margin": s.joint_margin + 0.02,
        "home_x": r.start["rest"][0],
        "max_rotation": rotation_cap(r),
    }


def phase1_outcome(r, p, est, q, mu: float):
    """``(segment or None, planned rotation [rad], solve time [s], why no plan)`` of the
    phase-1 plan ``p`` from the estimate ``est`` at joint angles ``q`` [rad]."""
    miss = phase1_miss(r)  # of the previous phase 1 (before ``r._plan1`` becomes ``p``)
    r._plan1 = p
    if not p.success or abs(p.rotation) < math.radians(1.0):
        why = blocking(r, est, q, mu)
        return None, 0.0, p.solve_time_s, f"phase-1 NLP: {p.stop}; {why}"
    squeeze = carry_squeeze(r, p, miss)
    seg = phase1_segment(p, est, q, r.theta, r.s, r.hand, lift=PHASE1_LIFT, squeeze=squeeze)
    return seg, p.rotation, p.solve_time_s, ""


def carry_squeeze(r, plan, miss: float | None) -> float | None:
    """The raised phase-1 squeeze [N] of ``plan`` (:func:`.carry_squeeze.phase1_squeeze`)
    when the previous phase 1 rolled the object along the palm into a workspace limit,
    else None (the commanded squeeze).

    The NLP moves the object's centre freely; on the palm it rolls instead (``R theta`` to
    the right per clockwise turn), and the right finger runs into its base joint's stop.
    A previous phase 1 that ended at a workspace limit with its sensed centre ``miss`` [m]
    (:func:`phase1_miss`) more than the NLP's whole travel (``r.nlp.travel``) from its
    plan's end did that: this one carries the object (an event says so). Round nominal
    shapes only (the posed outlines' planner keeps the commanded squeeze).
    """
    if not r.s.carry_weight or r.shape is not None or miss is None:
        return None
    last = next((p for p in reversed(r.records) if p.phase == 1), None)
    if last is None or last.event != "workspace limit" or miss <= r.nlp.travel:
        return None
    f = phase1_squeeze(plan.beta, r.s, PHASE1_LIFT)
    msg = (f"the last phase 1 ended at a workspace limit {1e3 * miss:.1f} mm from its "
           f"plan (rolled on the palm): squeeze {f:.2f} N to carry the object")  # fmt: skip
    r.events.append({"t": r.world.time, "kind": "carry", "phase": 1, "message": msg})
    return f


def phase1_miss(r) -> float | None:
    """Horizontal distance [m] between where the last phase 1 left the object's sensed
    centre and where its plan (``r._plan1``) put it; None before the first phase 1."""
    plan = r._plan1
    if plan is None or not plan.success or not r.ctrl.trace:
        return None
    trace, kind, cx = r.ctrl.trace, TRACE_NAMES.index("kind"), TRACE_NAMES.index("cx")
    for row in reversed(trace):
        if row[kind] == 1:
            return abs(float(row[cx]) - float(plan.centre[-1, 0]))
    return None


def rotation_cap(r) -> float:
    """The phase-1 rotation cap [rad] that keeps sensed features off the palm."""
    return _cap(r.sensed_features, r.theta)


def feature_behind(r, event: str) -> float | None:
    """Records a feature the last phase 3 met (object frame, for :func:`rotation_cap`) and
    returns its world angle [rad] when the pad slid over it (a back-stroke follows), else
    None."""
    if event not in ("path finished", "workspace limit"):
        return None
    bump = sensed_bump(np.asarray(r.ctrl.trace[r._rows[0] : r._rows[1]]))
    if bump is None:
        return None
    f = math.remainder(bump[0] - r.theta, 2 * math.pi)
    if all(abs(math.remainder(f - g, 2 * math.pi)) > SAME_FEATURE for g in r.sensed_features):
        r.sensed_features.append(f)
    return bump[0] if bump[1] else None


#: the prefix of the phrase naming what blocks the gait in a planner's reason
BLOCKING = "blocking: "
#: :func:`blocking`'s verdict when none of the three constraints blocks the sensed grasp
NOT_BLOCKED = BLOCKING + "none of force closure / workspace / reach at the start (IPOPT failed)"


def blocking_phrase(why: str) -> str:
    """The ``blocking: ...`` phrase of a planner's reason ``why`` ("" when it names no
    constraint, or only :data:`NOT_BLOCKED`). The planners write it last, either bare
    (``"phase-1 NLP: ...; blocking: force closure (...)"``, :func:`blocking`) or in
    parentheses (``"... (blocking: workspace)"``, the posed-outline planner's); the
    phrase itself may hold parentheses."""
    i = why.find(BLOCKING)
    if i < 0 or NOT_BLOCKED in why:
        return ""
    return why[i:-1] if why[i - 1 : i] == "(" and why.endswith(")") else why[i:]


def blocking(r, est, q, mu: float) -> str:
    """Which constraint blocks phase 1 at the sensed grasp (the issue's three): force
    closure (the contact line outside the friction cones), workspace (a joint at its limit)
    or reach (no stable left grasp within the left finger's reach)."""
    stab = stable_pair(float(est.beta[0]), float(est.beta[1]), mu, 0.0)
    if stab < 0:
        return (f"{BLOCKING}force closure (contact line {math.degrees(-stab):.0f} deg "
                "outside the friction cones)")  # fmt: skip
    lim = r.hand.joint_limits
    margin = np.minimum(np.asarray(q) - lim[:, 0], lim[:, 1] - np.asarray(q))
    j = int(np.argmin(margin))
    if margin[j] < r.s.joint_margin + 0.02:
        return f"{BLOCKING}workspace ({joint_at_limit(q, lim, j)})"
    off = tip_contact_angle(r.hand, q, float(est.beta[1]))
    if abs(off) > r.nlp.max_tip_angle:
        return (f"{BLOCKING}workspace (the right tip touches {math.degrees(abs(off)):.1f} deg "
                f"from its axis; phase 1 rolls it within {math.degrees(r.nlp.max_tip_angle):.0f}"
                " deg)")  # fmt: skip
    if left_regrasp_angle(r, est, fallback=False) is None:
        return BLOCKING + "reach (no stable left grasp within the left finger's reach)"
    return NOT_BLOCKED


def tip_contact_angle(hand, q, beta_right: float) -> float:
    """Angle [rad] of the round right contact from its tip's axis (the tip frame's +y), the
    quantity the phase-1 NLP bounds by ``max_tip_angle``: ``beta_R + pi/2 - phi_R`` wrapped
    to (-pi, pi], with ``beta_R`` the contact's world polar angle about the object centre
    [rad] and ``phi_R`` the tip's orientation at joint angles ``q`` (6,) [rad]."""
    phi = hand.fingertip_pose(q, "right").angle
    return math.remainder(beta_right + 0.5 * math.pi - phi, 2 * math.pi)


def joint_at_limit(q, limits, j: int) -> str:
    """``"the right finger's joint 1 0.2 deg from its lower limit"``: joint ``j`` of the hand's
    joint vector ``q`` [rad] (left finger 0-2, right 3-5, base joint first) with its
    ``limits`` ((6, 2) [rad])."""
    q = np.asarray(q, float)
    lo, hi = q[j] - limits[j, 0], limits[j, 1] - q[j]
    side = "lower" if lo <= hi else "upper"
    finger = ("left", "right")[j // 3]
    return (f"the {finger} finger's joint {j % 3 + 1} {math.degrees(min(lo, hi)):.1f} deg from "
            f"its {side} limit")  # fmt: skip


def fit_radius(r, est, tip_radius: float) -> float:
    """The local radius [m] of the object between the two fingers (§2.2.3: "planning is done
    ... using a current estimate of the object curvature"): the circle tangent to the left
    pad at its sensed contact and touching the round right tip, ``|T - p + R n| = R + r``
    solved for ``R`` (``T`` tip centre, ``p``, ``n`` the pad's contact point and outward
    normal, ``r`` the tip radius), clamped to ``RADIUS_FIT`` times the nominal one; the
    nominal radius with a round left tip (a circle of any radius touches both tips). On a
    non-circular object the nominal circle put the NLP's start out of reach of the fingers
    (solver failed at the start of the ellipse)."""
    R0 = r.R_nominal
    if r.ctrl.sensing.r_left:  # two round tips: one circle per radius touches both
        return R0
    d = est.tips[1] - est.p[0]
    den = 2.0 * (float(d @ est.n[0]) - tip_radius)
    if abs(den) < 1e-9 or not est.pad_touch:
        return R0
    R = (tip_radius * tip_radius - float(d @ d)) / den
    lo, hi = RADIUS_FIT
    return float(min(max(R, lo * R0), hi * R0))


def left_regrasp_angle(r, est, fallback: bool = True):
    """Where the left pad goes in phase 3 (world polar angle [rad]): the §2.2.3 choice of
    :func:`.heuristics.regrasp_left_angle` for the right contact it will grasp with; the
    start grasp's angle when none is stable and reachable (phase 1 then reports it)."""
    s = r.s
    mu = s.planning_mu
    b = regrasp_left_angle(r.hand, est.centre, r.ctrl.sensing.radius, float(est.beta[1]),
                           mu, s.nlp_margin, PHASE1_TRAVEL)  # fmt: skip
    if b is None and fallback:
        return r.start["beta"][0]
    return b


def right_hold_angle(r) -> float:
    """Lowest polar angle [rad] of the right contact from which the right finger can press
    the object against the palm in phase 3: the chord to the palm contact makes
    (pi/2 - beta) / 2 with the contact normal and must lie inside the friction cone (with a
    0.2 rad reserve). Below it the holder's cone-limited push rolled the object backwards
    along the palm (+10-18 deg per phase 3 with beta = 5 deg)."""
    mu = r.s.planning_mu
    return 0.5 * math.pi - 2 * math.atan(mu) + 0.2
