"""Phase 1 of a posed polygon as a pivot about its palm corner, and the right finger's
regrasp chosen by the pivot it allows (the kinematics of :mod:`.pivot_reach`).

The circle NLP of :mod:`.shape_planning` plans a sharp square's phase 1 on the local circle
between the contacts; the square does not roll, it pivots about its palm corner, and the
plan's right-finger motion was not the pivot's (the start grasp's plan of 27.5 deg ended
after 16 deg with the right base joint at its limit). Here phase 1 is planned on the pivot
itself: the object turns about the rightmost of its lowest corners, the left pad sticks to
its face, the right tip rolls on its face along the path of :func:`.pivot_reach.
tip_rolling_path` that keeps every joint inside its limits and the links clear of the object;
the rotation is the smaller of the two fingers' reaches. The references the controller
tracks are the ones its sensing computes along that motion (the circle estimate's centre
``p_L - R n_L`` is a point of the object, so it turns about the corner too; the round
contact's arclength is the one the sensing's circle model gives at the planned tip), so the
plan and the controller agree without a change of the controller.

Phase 2 (the right tip explores) ends where the NEXT phase 1 can pivot furthest
(:func:`best_tip_regrasp`): candidate contacts along the right finger's face and tip
orientations, each scored by its rolling path's reach.
"""

from __future__ import annotations

import math
import time

import numpy as np

from planner.exploration.planar import pivot_reach as pr
from planner.trajectory.rolling_nlp import RollingPlan

#: largest rotation of one pivot phase [rad]
MAX_PIVOT = math.radians(40.0)
#: a pivot phase turns the object this much less than the fingers' reach [rad]
PIVOT_SLACK = math.radians(1.0)
#: the joint-limit margin of the pivot plans [rad] (the workspace event fires at the
#: settings' ``joint_margin``, 0.03 rad by default)
PIVOT_MARGIN = 0.045
#: candidate regrasp contacts along the face [m] and tip orientations [rad]
REGRASP_STEP = 0.01
REGRASP_PHI_STEP = math.radians(10.0)


def _deg(x: float) -> float:
    return math.degrees(x) + 0.0  # no "-0.0"


def tip_face(shape, est, geometric: bool = False):
    """``(Face, d0)``: the straight face of the posed outline under the round tip (world
    frame) and the contact's distance along it [m], or None (no tip contact, no face, or
    the outline rests on a rounded corner: it rolls there, it does not pivot);
    ``geometric``: contacts as in ``ShapeTracker.readings``."""
    from planner.exploration.planar.outline_pose import contacts

    rd = shape.readings(est, True, geometric)
    if rd.tip_centre is None:
        return None
    W = shape.outline.posed(shape.pose)
    if not pr.is_sharp(W, pr.palm_corner(W)):  # a rounded corner rolls: no pivot
        return None
    con = contacts(shape.outline, shape.pose, rd)
    f = _face_at(shape, W, con["tip"])
    if f is None:
        return None
    return f, float((con["tip"] - f.start) @ f.tangent)


def _face_at(shape, W, point):
    """The straight face (world frame) of the posed outline ``W`` through the world
    ``point`` (2,) [m] (:meth:`.ShapeTracker.face_at` in the object frame), or None."""
    x, y, a = shape.pose
    Rt = pr.rotation(-a)  # world -> object frame
    ends = shape.face_at(Rt @ (np.asarray(point, float) - (x, y)))
    if ends is None:
        return None
    A, B = (Rt.T @ p + (x, y) for p in ends)
    return pr.Face.between(A, B, W.mean(axis=0))


def next_face(shape, face):
    """The straight face of the posed outline (world frame) beyond the far end of ``face``
    (the end away from the palm corner, ``face.end``), or None (no straight face there).
    A square pivoted towards 45 deg is held next with the round tip on this face (the top
    face: it becomes the right face when the square lies on its next face;
    :mod:`.pivot_grasps`: the pad on the left face with the tip on the top face is stable
    from 0 to 90 deg for the 4 and 6 cm squares)."""
    from planner.exploration.planar.outline_segments import PolylinePath

    W = shape.outline.posed(shape.pose)
    path = PolylinePath(W)
    s = path.arclength_of(face.end)
    for ds in (NEXT_FACE_STEP, -NEXT_FACE_STEP):
        p = np.asarray(path.at(s + ds)[0])
        if abs(float((p - face.start) @ face.normal)) < 1e-5:  # still on ``face``
            continue
        return _face_at(shape, W, p)
    return None


#: how far beyond a face's end the next face is looked for [m]
NEXT_FACE_STEP = 0.003


def plan_pivot(hand, W, face, d0: float, est, q, theta_cap: float, knots: int) -> RollingPlan:
    """The pivot of the posed outline ``W`` (M, 2) [m] from joint angles ``q`` (6,) [rad]
    with the round tip on ``face`` at ``d0`` [m] and the estimate ``est`` (its centre,
    contact angles and pad contact; the controller's radius already set), at most
    ``theta_cap`` [rad], sampled at ``knots + 1`` knots: a
    :class:`~planner.trajectory.rolling_nlp.RollingPlan` whose ``centre`` is the controller's
    centre estimate along the pivot (a point of the object, turning about the palm corner)
    and ``beta`` the contacts' polar angles about it; ``stop`` names the finger whose reach
    ends it."""
    t0, c0 = time.perf_counter(), time.process_time()
    q = np.asarray(q, float)
    path = pr.tip_rolling_path(hand, W, face, d0, float(q[3:].sum()), max_turn=theta_cap,
                               margin=PIVOT_MARGIN, start_margin=0.0)  # fmt: skip
    reach_l, qL = pr.pad_reach(hand, W, est.tips[0], float(q[:3].sum()), max_turn=theta_cap,
                               margin=PIVOT_MARGIN, start_margin=0.0)  # fmt: skip
    rot = min(path.reach, reach_l) - PIVOT_SLACK
    stop = (f"pivot about the palm corner: the right tip reaches {_deg(path.reach):.1f} deg, "
            f"the left pad {_deg(reach_l):.1f} deg")  # fmt: skip
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    if rot < math.radians(1.0) or len(qL) == 0:
        K = np.zeros(1)
        return RollingPlan(K, est.centre[None].copy(), q[None].copy(), est.beta[None].copy(),
                         np.array([est.u]), 0.0, False, wall, stop, cpu)  # fmt: skip
    th = -np.linspace(0.0, rot, knots + 1)
    grid = -path.theta
    d = np.interp(-th, grid, path.d)
    phi = np.interp(-th, grid, path.phi)
    qR = np.column_stack([np.interp(-th, grid, path.q[:, j]) for j in range(3)])
    gl = np.arange(len(qL)) * math.radians(1.0)
    qLk = np.column_stack([np.interp(-th, gl, qL[:, j]) for j in range(3)])
    k = pr.palm_corner(W)
    centre = np.array([pr.pivoted(est.centre, k, t) for t in th])
    r = float(hand.params.right.tip_radius)
    T = face.tip_centre(k, th, d, r)
    bR = np.unwrap(np.arctan2(T[:, 1] - centre[:, 1], T[:, 0] - centre[:, 0]))
    bR += 2 * math.pi * round((float(est.beta[1]) - bR[0]) / (2 * math.pi))
    beta = np.column_stack([float(est.beta[0]) + th, bR])
    del phi  # the orientation is in qR (its sum)
    return RollingPlan(th, centre, np.column_stack([qLk, qR]), beta, np.full(th.size, float(est.u)),
                     float(th[-1]), True, wall, stop, cpu)  # fmt: skip


def pad_reach_now(hand, W, est, q) -> float:
    """How far [rad] the left pad, stuck where it is (``est.tips[0]``, orientation the sum
    of ``q[:3]``), can follow a pivot of the posed outline ``W`` from here."""
    reach, _ = pr.pad_reach(hand, W, est.tips[0], float(np.sum(q[:3])), max_turn=MAX_PIVOT,
                            margin=PIVOT_MARGIN, start_margin=0.0)  # fmt: skip
    return reach


def best_tip_regrasp(hand, W, face, theta_cap: float = MAX_PIVOT, q_right=None, via=None):
    """Where on ``face`` the round tip should regrasp: ``(d0 [m], phi0 [rad], reach [rad])``
    of the candidate (every :data:`REGRASP_STEP` along the face, every
    :data:`REGRASP_PHI_STEP` of orientation) whose rolling path pivots the object (world
    polygon ``W``) furthest, ties broken by the path's smallest joint margin; None when no
    candidate is reachable. With the right finger's joints ``q_right`` (3,) [rad], only
    candidates the phase-2 move reaches from there are kept (:func:`_move_ok`; a regrasp
    chosen without it hit the base joint's limit on the way and the held square fell back
    10 deg). ``via = (corner (2,), normal (2,))``: the tip comes from the face with that
    outward normal over ``corner`` (:func:`_move_ok`'s path goes around it)."""
    lim = hand.finger_limits("right")
    best, key = None, (-1.0, -math.inf)
    lo = float(lim[:, 0].sum())  # orientations a turn apart are one (the IK wraps)
    phis = np.arange(lo, min(float(lim[:, 1].sum()), lo + 2 * math.pi), REGRASP_PHI_STEP)
    for d0 in np.arange(REGRASP_STEP, face.length - pr.FACE_END, REGRASP_STEP):
        for phi0 in phis:
            p = pr.tip_rolling_path(hand, W, face, float(d0), float(phi0),
                                    max_turn=theta_cap, margin=PIVOT_MARGIN)  # fmt: skip
            if not np.isfinite(p.margin[0]):
                continue
            phi = float(p.q[0].sum())  # the orientation as the joints' sum (the IK wrapped it)
            if q_right is not None and not _move_ok(hand, W, face, q_right, (float(d0), phi),
                                                    via=via):  # fmt: skip
                continue
            kk = (round(p.reach, 6), float(p.margin.min()))
            if kk > key:
                best, key = (float(d0), phi, p.reach), kk
    return best


#: joint-limit margin of the phase-2 move to a regrasp [rad]
MOVE_MARGIN = 0.035


def _around(T0, T1, via, normal, r: float, n: int):
    """``(T (n-1, 2), t (n-1,))``: points of the tip centre's path from ``T0`` to ``T1``
    [m] around the corner of ``via = (corner, normal_from)`` (to ``corner + r
    normal_from``, on the circle of radius ``r`` about the corner to ``corner + r
    normal``, then straight on), at the fractions ``t`` of its length after the start."""
    c, m0 = np.asarray(via[0], float), np.asarray(via[1], float)
    a0 = math.atan2(m0[1], m0[0])
    turn = math.remainder(math.atan2(normal[1], normal[0]) - a0, 2 * math.pi)
    a = a0 + np.linspace(0.0, turn, 7)
    P = np.vstack([T0, c + r * np.column_stack([np.cos(a), np.sin(a)]), T1])
    cum = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(P, axis=0).T))])
    t = np.linspace(0.0, 1.0, n)[1:]
    at = t * cum[-1]
    return np.column_stack([np.interp(at, cum, P[:, 0]), np.interp(at, cum, P[:, 1])]), t


def _move_ok(hand, W, face, q_right, end, n: int = 12, via=None) -> bool:
    """Whether the round tip's move from the right finger's joints ``q_right`` (3,) [rad]
    to the contact ``end = (d, phi)`` [m, rad] on ``face`` (its centre on the straight
    line between, or with ``via = (corner, normal)`` around that corner from the face with
    that outward normal: to ``corner + r normal``, on the circle of radius r about the
    corner, then to the end; the orientation interpolated) keeps the finger's joints
    :data:`MOVE_MARGIN` inside their limits (or, from a start nearer than twice that, no
    nearer than the start less :data:`MOVE_MARGIN`; the object held where ``W`` is)."""
    from robots.planar_hand import kinematics as kin

    f = hand.params.right
    r = float(f.tip_radius)
    q0 = np.asarray(q_right, float)
    T0, _ = kin.fingertip(np.array(f.base), np.array(f.lengths), q0[None])
    T1 = face.tip_centre(pr.palm_corner(W), 0.0, end[0], r)
    if via is None:
        t = np.linspace(0.0, 1.0, n)[1:]
        T = T0[0] + t[:, None] * (T1 - T0[0])
    else:
        T, t = _around(T0[0], T1, via, face.normal, r, 3 * n)
    phi = float(q0.sum()) + t * (end[1] - float(q0.sum()))
    lim = hand.finger_limits("right")
    sols, ok = hand.ik_candidates("right", T, phi)
    m = np.where(ok, np.minimum(sols - lim[:, 0], lim[:, 1] - sols).min(axis=-1), -np.inf)
    m0 = float(np.minimum(q0 - lim[:, 0], lim[:, 1] - q0).min())
    # a finger that starts nearer to a limit (a phase 1 ended there) may stay as near: the
    # workspace event fires a further ``MOVE_MARGIN`` toward it (controller.limit_triggers);
    # around a corner it may not come nearer than it starts (the 11 cm square's tip, sent
    # over its top corner with that allowance, hit the right base joint's limit on the way
    # and the held square fell back 4-6 deg)
    floor = min(MOVE_MARGIN, m0 - MOVE_MARGIN) if via is None else min(MOVE_MARGIN, m0)
    return bool(np.all(m.max(axis=1) >= floor))


__all__ = [
    "MAX_PIVOT",
    "best_tip_regrasp",
    "next_face",
    "pad_reach_now",
    "plan_pivot",
    "tip_face",
]
