"""The phase machine's planning of a non-round object (its :class:`.shape_tracking.ShapeTracker`).

Kept out of :mod:`.machine` (one concept: what changes when the planner's model is a posed
outline instead of a circle):

* phase 1: with :data:`PLAN_PIVOT`, on an outline resting on a sharp corner with the round
  tip on a straight face, the pivot about that corner (:mod:`.pivot_planning`); else the
  circle NLP on the local circle between the two sensed contacts
  (:meth:`.ShapeTracker.local_circle`), with the posed outline's palm clearance
  (``RollingNLP(palm_points=K)``: the outline pivots on its lowest corner instead of sinking
  into the palm); either way the estimate's radius is set to the local circle's so that the
  controller's per-step centre and the plan agree; or, with :data:`PLAN_ON_OUTLINE`, the
  polygon NLP (:class:`planner.trajectory.OutlineNLP`);
* phases 2/3: the explorer's contact along the posed outline
  (:func:`.outline_segments.outline_explore_segment`) to the prior's handoff
  (``settings.follow_prior``) or back to the start grasp's world angle, moved by up to
  :data:`STABLE_WINDOW` into the planning friction cones (:func:`_stable_target`), the round
  tip turning to the §2.2.3 orientation for the next phase 1 (:data:`TIP_ORIENTATION`);
  with :data:`PLAN_PIVOT` the right tip's phase 2 ends where the next pivot reaches
  furthest (or does not run when no pivot can follow it), on the face under it or, with
  :data:`NEXT_FACE_REGRASP`, over the far corner on the next face.
"""

from __future__ import annotations

import math

import numpy as np

from planner.exploration.planar import heuristics, phase_planning, pivot_planning

#: largest travel of the planned centre in phase 1 on a posed outline [m] (a square pivoting
#: on its corner lifts its centre up to 23 mm)
SHAPE_TRAVEL = 0.03
#: the round tip's phase-2 regrasp on a posed outline ends at the §2.2.3 preferred
#: orientation for the next phase 1 (:func:`_regrasp_tip_orientation`; False: it keeps its
#: orientation)
TIP_ORIENTATION = True
#: how far from the tip's axis that orientation may put the contact [rad] (the circle
#: heuristic's window, :data:`.heuristics.TIP_SPREAD`)
TIP_SPREAD = heuristics.TIP_SPREAD
#: the explorer's regrasp target moves up to this far (world polar angle about the posed
#: centre) to where the contact line of the next grasp lies inside the planning cones with
#: the NLP's margin (:func:`_stable_target`; 0: not moved) [rad]
STABLE_WINDOW = math.radians(8.0)
#: the regrasp's contact normals on the posed outline are smoothed over this fraction of
#: the pad's half-width [-] (:func:`_outline_contact`)
NORMAL_SMOOTHING = 0.25
#: plan phase 1 of a posed polygon with ``planner.trajectory.OutlineNLP`` (its contacts'
#: modes) instead of the local circle. Off: the controller (its object impedance and
#: rolling PD) tracks a circle about the pad-based centre, and the polygon plans it executed
#: turned the 11 cm and 8 cm squares the wrong way (+30 and +41 deg where -25 were planned;
#: measured 2026-11-23, 10 s simulated, seed 0)
PLAN_ON_OUTLINE = False
#: plan the FIRST phase 1 of a posed outline from the start grasp's contacts by geometry
#: (``ShapeTracker.readings(geometric=True)``): the fingers are placed on the object at
#: rest and sense no force yet, and the circle NLP planned without them flicked the 6 cm
#: and 10 cm sharp squares over their corners (-42 / -68 deg where -10.7 / -27.5 were
#: planned). Off: planned as a pivot from there, the squares slid on the palm instead
#: (bench_gait, 30 s, clockwise turn of the sharp squares 4/6/8 cm: 0.9 / 0 / -14.2 deg
#: where the circle NLP gave 0 / 42 / 21; the 12 cm one turned 82 deg the wrong way;
#: measured 2026-11-23)
START_BY_GEOMETRY = False
#: the right tip's phase-2 regrasp may go over the far corner onto the next face (the top
#: face of a square), when the next pivot reaches further from there
NEXT_FACE_REGRASP = True
#: plan phase 1 of a posed polygon as its pivot about the palm corner and end phase 2 where
#: the next pivot reaches furthest (:mod:`.pivot_planning`)
PLAN_PIVOT = True


def set_radius(ctrl, R: float) -> None:
    """The estimate's radius [m] everywhere the controller ``ctrl`` uses it (per-step
    sensing, rolling integration, object model)."""
    ctrl.set_radius(R)


def posed_estimate(est, local):
    """A copy of the ``GraspEstimate`` ``est`` with the centre, contact angles and pad
    contact of ``local`` (``ShapeTracker.local_circle``'s ``(centre, R, beta, u)``)."""
    from planner.exploration.planar.sensing import GraspEstimate

    e = GraspEstimate(est.buffer.copy())
    e.centre[:] = local[0]
    e.beta[:] = local[2]
    e.u = local[3]
    return e


def _nlp(runner, name: str):
    """The runner's NLP ``name`` ("circle": palm clearance; "outline"), built at first use."""
    if name not in runner.nlps:
        from planner.exploration.planar.shape_tracking import PALM_POINTS
        from planner.trajectory import OutlineNLP, RollingNLP

        knots = runner.s.nlp_knots
        runner.nlps[name] = (
            RollingNLP(runner.hand, knots=knots, travel=SHAPE_TRAVEL, palm_points=PALM_POINTS)
            if name == "circle"
            else OutlineNLP(runner.hand, PALM_POINTS, knots=knots)
        )
    return runner.nlps[name]


def plan_phase1(runner, q, mu: float):
    """Phase 1 of the posed outline from joint angles ``q`` [rad] with the friction
    coefficient ``mu`` [-] (module docstring): ``(segment or None, planned rotation [rad],
    solve time [s], why no plan)``."""
    shape, ctrl = runner.shape, runner.ctrl
    r = runner.hand.params.right.tip_radius
    set_radius(ctrl, runner.R_nominal)
    est = ctrl.sensing.update(runner.world.observe(), "auto")
    common = phase_planning.nlp_options(runner)
    # the start grasp touches the object at rest before any squeeze: its contacts by geometry
    first = START_BY_GEOMETRY and not runner.records
    modes = shape.contact_modes(est) if PLAN_ON_OUTLINE else None
    local = None if modes is not None else shape.local_circle(est, r, runner.R_nominal,
                                                              geometric=first)  # fmt: skip
    if modes is not None:
        plan = _nlp(runner, "outline").solve(q, shape.pose, modes, shape.hull_points(), r, mu,
                                             radius=runner.R_nominal, u_sensed=float(est.u),
                                             **common)  # fmt: skip
    elif local is not None and PLAN_PIVOT and pivot_planning.tip_face(shape, est, first):
        return _pivot_phase1(runner, q, est, local, first)
    elif local is not None:
        set_radius(ctrl, local[1])
        est = posed_estimate(est, local)
        pts = shape.palm_points(local[0])
        plan = _nlp(runner, "circle").solve(q, est.centre, local[1], r, mu, est.beta, est.u,
                                            palm_points=pts, **common)  # fmt: skip
    else:  # no pad or tip contact to pose the outline by: the circle fitted to both
        R = phase_planning.fit_radius(runner, est, r)
        ctrl.sensing.radius = R
        plan = runner.nlp.solve(q, est.centre, R, r, mu, est.beta, est.u, **common)
    return phase_planning.phase1_outcome(runner, plan, est, q, mu)


def _pivot_phase1(runner, q, est, local, geometric: bool = False):
    """Phase 1 planned as the pivot about the palm corner (:func:`.pivot_planning.plan_pivot`)
    from the local circle's estimate (the controller's centre is a point of the object)."""
    from planner.exploration.planar.segments import phase1_segment

    shape, s = runner.shape, runner.s
    face, d0 = pivot_planning.tip_face(shape, est, geometric)
    set_radius(runner.ctrl, local[1])
    est = posed_estimate(est, local)
    W = shape.outline.posed(shape.pose)
    cap = min(pivot_planning.MAX_PIVOT, phase_planning.rotation_cap(runner))
    plan = pivot_planning.plan_pivot(runner.hand, W, face, d0, est, q, cap, s.nlp_knots)
    runner._plan1 = plan
    if not plan.success:
        return None, 0.0, plan.solve_time_s, f"{plan.stop} ({phase_planning.BLOCKING}workspace)"
    seg = phase1_segment(plan, est, q, runner.theta, s, runner.hand, lift=0.0)
    return seg, plan.rotation, plan.solve_time_s, ""


def plan_explore(runner, kind: int, est, q):
    """The phase-2/3 segment on the posed outline: to the prior's handoff at the sensed
    rotation (``settings.follow_prior``, :mod:`.prior_track`), else back to the start
    grasp's world angle (a grasp that was stable and reachable with the object resting on
    the palm); with
    :data:`PLAN_PIVOT` the right tip goes where the next pivot reaches furthest, and there
    is no phase 2 (None and why) when that pivot could not turn the object (the stuck left
    pad or every regrasp of the right tip at the end of the workspace: a phase 2 there only
    let the held square fall back, +10 deg). Returns ``(segment or None, 0.0, 0.0, why)``
    (the planner's outcome as for phase 1)."""
    from planner.exploration.planar.outline_segments import PolylinePath, outline_explore_segment

    target = runner.start["beta"][1 if kind == 2 else 0]
    if runner.s.follow_prior and runner.prior is not None:
        # the prior's handoff at the sensed rotation: map space found it stable and
        # reachable on this outline (settings.follow_prior)
        st = runner.prior.step(kind, runner.theta)
        if st is not None and math.isfinite(st.end[1 if kind == 2 else 0]):
            target = st.end[1 if kind == 2 else 0]
    point = phi = None
    # the next phase 1 pivots only from a pad contact the tactile array senses (the posed
    # outline's local circle needs it)
    pivot = kind == 2 and PLAN_PIVOT and est.pad_touch
    tf = pivot_planning.tip_face(runner.shape, est) if pivot else None
    if tf is not None:
        W = runner.shape.outline.posed(runner.shape.pose)
        pad = pivot_planning.pad_reach_now(runner.hand, W, est, q)
        face, best = _best_regrasp(runner, W, tf[0], q)
        tip = 0.0 if best is None else best[2]
        if min(pad, tip) < pivot_planning.PIVOT_SLACK + math.radians(1.0):
            why = (
                f"pivot about the palm corner: from a regrasp the right tip reaches "
                f"{math.degrees(tip):.1f} deg, the left pad {math.degrees(pad):.1f} deg "
                f"({phase_planning.BLOCKING}workspace)"
            )
            return None, 0.0, 0.0, why
        point = face.start + best[0] * face.tangent
        phi = best[1]
    elif STABLE_WINDOW > 0 or (kind == 2 and TIP_ORIENTATION):
        # (a pivot's regrasp point above overrides the target)
        path = PolylinePath(runner.shape.outline.posed(runner.shape.pose))
        if STABLE_WINDOW > 0:
            target = _stable_target(runner, path, kind, target, est)
        if kind == 2 and TIP_ORIENTATION:
            phi = _regrasp_tip_orientation(runner, path, target, q)
    seg = outline_explore_segment(kind, est, q, runner.shape, target, runner.theta, runner.s,
                                  runner.hand, target_point=point, phi_end=phi)  # fmt: skip
    return seg, 0.0, 0.0, ""


def _outline_contact(runner, path, arclength: float):
    """The posed outline's (``path``, a :class:`.outline_segments.PolylinePath`) point at
    ``arclength`` [m] (world, [m]) and its outward normal angle [rad], the normal smoothed
    over :data:`NORMAL_SMOOTHING` times the pad's half-width (a corner's normal turns
    gradually, as a fingertip rolling over it sees it)."""
    width = NORMAL_SMOOTHING * runner.hand.params.left.pad_half_width
    return path.at(arclength)[0], path.normal_angle(arclength, width)


def _regrasp_tip_orientation(runner, path, target: float, q) -> float:
    """Orientation [rad] of the round right tip at the end of its phase-2 regrasp to the
    posed outline's (``path``, its :class:`.outline_segments.PolylinePath`) point at world
    polar angle ``target`` [rad] about its centre: the
    §2.2.3 heuristic (:func:`.heuristics.tip_orientation`) at that point and where the next
    phase 1 takes it (the point turned ``PHASE1_TRAVEL`` clockwise about the centre), the
    change from the tip's orientation now at most ``segments.MAX_REORIENT``. Keeping the
    orientation instead left the 8 cm rounded square's contact 97-106 deg from the tip's
    axis after the regrasp, beyond its 69 deg rolling range, and phase 1 had no plan."""
    from planner.exploration.planar.heuristics import tip_orientation
    from planner.exploration.planar.segments import MAX_REORIENT
    from planner.grasp.workspace import rotation

    c = np.asarray(runner.shape.pose[:2], float)
    point, n = _outline_contact(runner, path, path.point_at_angle(c, target))
    r = runner.hand.params.right.tip_radius
    tip = np.asarray(point) + r * np.array([math.cos(n), math.sin(n)])
    turned = c + rotation(-phase_planning.PHASE1_TRAVEL) @ (tip - c)
    phi1 = tip_orientation(runner.hand, [tip, turned], n + 0.5 * math.pi, TIP_SPREAD)
    phi0 = float(q[3:6].sum())
    return phi0 + float(np.clip(math.remainder(phi1 - phi0, 2 * math.pi), -MAX_REORIENT,
                                MAX_REORIENT))  # fmt: skip


def _stable_target(runner, path, kind: int, target: float, est) -> float:
    """The explorer's regrasp target [rad] (world polar angle about the posed centre) within
    :data:`STABLE_WINDOW` of ``target`` nearest to it (1 deg steps) whose grasp with the
    holding finger's sensed contact, both on the posed outline ``path`` (its
    :class:`.outline_segments.PolylinePath`), has a Yoshikawa-Nagai margin
    (:func:`planner.grasp.two_contact_stability`, eq. 2.9) of at least
    ``settings.nlp_margin`` at the planning friction (``settings.planning_mu``), else the
    one with the largest margin. The prior's handoffs are stable at the map's mu (1.0) but
    1-11 deg outside the executor's mu-0.8 cones, and the next phase-1 NLP found no plan
    there."""
    from planner.grasp.stability import two_contact_stability

    s = runner.s
    c = runner.shape.pose[:2]

    def contact(arclength):  # the outline point and its inward unit normal
        point, n = _outline_contact(runner, path, arclength)
        return point, [-math.cos(n), -math.sin(n)]

    hold = contact(path.arclength_of(est.p[0 if kind == 2 else 1]))
    best, out = -math.inf, target
    steps = int(round(math.degrees(STABLE_WINDOW)))
    for d in sorted(np.radians(np.arange(-steps, steps + 1)), key=abs):
        p, n = contact(path.point_at_angle(c, target + d))
        m = min(two_contact_stability([hold[0], p], [hold[1], n], s.planning_mu).margin,
                s.nlp_margin)  # fmt: skip
        if m > best + 1e-12:
            best, out = m, target + float(d)
    return out


def _best_regrasp(runner, W, face, q):
    """``(face, (d0, phi0, reach))`` of the right tip's regrasp on ``face`` or, with
    :data:`NEXT_FACE_REGRASP`, on the face beyond its far end (:func:`.pivot_planning.
    next_face`), whichever lets the next pivot turn the object further (``None`` for no
    reachable regrasp)."""
    faces = [(face, None)]
    if NEXT_FACE_REGRASP:
        nxt = pivot_planning.next_face(runner.shape, face)
        if nxt is not None:  # the tip goes around the far corner
            faces.append((nxt, (face.end, face.normal)))
    out = (face, None)
    for f, via in faces:
        b = pivot_planning.best_tip_regrasp(runner.hand, W, f, q_right=q[3:], via=via)
        if b is not None and (out[1] is None or b[2] > out[1][2] + math.radians(1.0)):
            out = (f, b)
    return out


__all__ = [
    "PLAN_ON_OUTLINE",
    "NEXT_FACE_REGRASP",
    "NORMAL_SMOOTHING",
    "PLAN_PIVOT",
    "SHAPE_TRAVEL",
    "STABLE_WINDOW",
    "START_BY_GEOMETRY",
    "TIP_ORIENTATION",
    "TIP_SPREAD",
    "plan_explore",
    "plan_phase1",
    "set_radius",
]
