"""The exploration procedure of Fig. 4.1 as one motion program (search -> local -> global).

Search along the strategy's segments with online detection (§4.2); on a detection, identify
the feature's type with the crossings of the extended Fig. 4.7 (§4.4.1), trace its outline
(§4.4.2, both sides of an open ridge or ravine), remember its area and resume the search
past it. With ``identify="raster"`` the whole raster is scanned first and the curvature
regions are pattern-matched (§4.4.1's alternative), then each feature is traced.

Bug-2 leaves a traced feature on the m-line past its known area; when the goal lies inside
that area it leaves just past the feature's traced outline instead, and a bug-2 run whose
fingertip does not end within :data:`GOAL_TOLERANCE` of the goal ends with status "failed",
a ``goal_not_reached`` event and the distance in the reason.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from planner.exploration.surface.identify import END_FRACTION, Crossing, evidence, identify
from planner.exploration.surface.motions import approach, move_to, sweep
from planner.exploration.surface.online import OnlineDetector
from planner.exploration.surface.runtime import PHASE
from planner.exploration.surface.strategies import segments
from planner.exploration.surface.tracing import find_outline, trace_boundary

__all__ = [
    "FeatureRecord",
    "ProgramState",
    "exploration_program",
    "outline_rise",
    "relabel",
    "remember",
    "trace_feature",
    "traced_area",
    "traced_sides",
]


@dataclass
class FeatureRecord:
    """What the program learnt about one feature (turned into an ExploredFeature later)."""

    decision: object
    centre: np.ndarray
    across: np.ndarray
    sides: list = field(default_factory=list)  # recorder index arrays, one per traced side
    # recorder index arrays of every step on the outline while tracing (trace phase), kept
    # or not: where the finger went along the feature, for its known area
    traced: list = field(default_factory=list)
    closed: bool = False
    ends: int = 0  # ends of the feature reached along its length (0-2)
    detected_at: float = 0.0
    latency: float = float("nan")
    rise: float = 2.5e-4
    reasons: list = field(default_factory=list)


@dataclass
class ProgramState:
    """Shared between the program and :func:`explore_surface`."""

    features: list = field(default_factory=list)
    known: list = field(default_factory=list)  # shapely geometries of explored areas
    detector: object = None

    def is_known(self, p) -> bool:
        return _in_any(self.known, p)


def _in_any(areas, p) -> bool:
    """Whether the point ``p`` (2,) [m] lies in one of the shapely geometries ``areas``."""
    import shapely

    return any(g.contains(shapely.Point(float(p[0]), float(p[1]))) for g in areas)


def _axis_from_search(ex, det, r: float) -> np.ndarray:
    from planner.exploration.surface.identify import crossing_axis

    rec = ex.rec
    k0, k1 = max(det.k_start, det.k_first - 400), min(det.k_end, det.k_last + 400)
    d = rec.centre[k1 - 1, :2] - rec.centre[k0, :2]
    return crossing_axis(rec.normal[k0:k1], d if np.linalg.norm(d) > 1e-9 else (1.0, 0.0))


def _crossing(ex, cfg, c, v, half, role):
    """Sweep ``c - half v -> c + half v``, each end run out onto a plane
    (:func:`_run_out`); returns the evidence, the analysis and the recorder range."""
    a, limit = c - half * v, RUN_OUT * cfg.tip_radius
    yield from move_to(ex, a, cfg.speed)
    if float(np.hypot(*ex.est.normal[:2])) > LEVEL_TILT:  # the start rests on the feature
        k = ex.rec.n
        a = yield from _run_out(ex, cfg, a, -v, limit, k, 0.0, END_FRACTION * 2 * half)
    k0, k1, _ = yield from sweep(ex, a, c + half * v, cfg.speed, role)
    if k1 - k0 >= 20:
        yield from _run_out(ex, cfg, c, v, limit, k0, END_FRACTION, 0.0)
        k1 = ex.rec.n
    rec = ex.rec
    if k1 - k0 < 20:
        return Crossing("", role), None, (k0, k1)
    ev, an, _ = evidence(rec.centre[k0:k1], rec.normal[k0:k1], cfg.tip_radius, role)
    return ev, an, (k0, k1)


#: a contact tilted less than this (sine of the normal's tilt) rests on the bare plate [-]
LEVEL_TILT = math.sin(math.radians(5.0))
#: the contact normals over an end of a crossing lie on a plane (the bare plate, a step's
#: level, a cusp's flank) when none is farther than this from their mean [rad]; a ball
#: rolling over a narrow crest turns its normal by 1 / r_f per metre (0.6 rad over the 5
#: mm end of a 32 mm crossing for r_f = 8 mm), the filtered OWTS normal scatters by 0.01
PLANE_SPREAD = 0.05
#: a crossing runs out at most this many r_f past each planned end [-]: a ball of radius
#: r_f touches a feature no farther than r_f from it
RUN_OUT = 3.0


def _on_plane(rec, k_from: int, share: float, least: float) -> bool:
    """Whether the last ``max(share * arclength, least)`` [m] of the recorder rows from
    ``k_from`` on were travelled with the contact on a plane (:data:`PLANE_SPREAD`); False
    while less than that has been travelled."""
    P, N = rec.centre[k_from : rec.n, :2], rec.normal[k_from : rec.n]
    if len(P) < 2:
        return False
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(P, axis=0).T))])
    length = max(share * s[-1], least)
    if s[-1] < length or length <= 0.0:
        return False
    m = N[s >= s[-1] - length]
    mean = m.mean(axis=0)
    mean /= np.linalg.norm(mean)
    return bool(np.arccos(np.clip(m @ mean, -1.0, 1.0)).max() < PLANE_SPREAD)


def _run_out(ex, cfg, p, d, limit: float, k_from: int, share: float, least: float):
    """Slide on along the line through ``p`` (2,) [m] in the direction ``d`` (2,) until the
    end of the path recorded from ``k_from`` lies on a plane (:func:`_on_plane` with
    ``share`` and ``least``) or ``limit`` [m] has been travelled; returns where it stopped
    (2,) [m].

    A crossing's end levels are read on the plate next to the feature (§4.4.1, Fig. 4.7: a
    step changes level, a ridge comes back down): an end where the ball still rests on the
    feature (its contact normal turning as it rolls over the crest) reads a level change
    that is none. A crossing from outside a sharply bent ridge across its apex ended 2.5 mm
    from the far arm's crest, 1.7 mm up (``scenarios/curved_ridge.yaml``: a "step")."""
    from planner.exploration.surface.motions import GAIN

    d = np.asarray(d, float) / np.linalg.norm(d)
    du, dv, pu, pv = float(d[0]), float(d[1]), float(p[0]), float(p[1])
    start, speed, i = ex.est.uv.copy(), float(cfg.speed), 0
    while float(np.hypot(*(ex.est.uv - start))) < limit:
        if i % 20 == 0 and _on_plane(ex.rec, k_from, share, least):
            break
        cu, cv = float(ex.est.centre[0]), float(ex.est.centre[1])
        e = GAIN * ((cu - pu) * -dv + (cv - pv) * du)
        yield speed * du + e * dv, speed * dv - e * du
        i += 1
    return ex.est.uv.copy()


def _peak(ex, k0: int, k1: int) -> np.ndarray:
    """(2,) where the centre path of a crossing departs most from the line through its ends."""
    P = ex.rec.centre[k0:k1]
    n = max(2, len(P) // 7)
    w0, w1 = P[:n, 2].mean(), P[-n:, 2].mean()
    base = np.linspace(w0, w1, len(P))
    return P[int(np.argmax(np.abs(P[:, 2] - base))), :2].copy()


def _met_at(ex, det, r: float) -> np.ndarray:
    """(2,) where the search met the feature of ``det`` [m]: at the sample of its window
    (:func:`_axis_from_search`'s range) whose centre departs most from the line through
    the window's ends, the contact point when the centre is raised there, the centre when
    it is sunken. On a raised feature the centre is highest with the contact on its top,
    and the centre lies ``r_f`` times the tilt's sine beside the contact; a ball narrower
    features are sunken into (a pit, a ravine) straddles them, its centre over their axis.
    A search line 1.6 mm beside a 1 mm bump (w 1.8 mm) had its curvature features' middle
    2.8 mm from the top and the across crossing through it missed the bump ("unknown")."""
    k0, k1 = max(det.k_start, det.k_first - 400), min(det.k_end, det.k_last + 400)
    if k1 - k0 < 20:
        return np.asarray(det.centre, float)
    P = ex.rec.centre[k0:k1]
    n = max(2, len(P) // 7)
    dev = P[:, 2] - np.linspace(P[:n, 2].mean(), P[-n:, 2].mean(), len(P))
    i = int(np.argmax(np.abs(dev)))
    return (ex.rec.contact[k0 + i, :2] if dev[i] > 0 else P[i, :2]).copy()


def _extent(ex, k0: int, k1: int, c, across, r: float) -> float:
    """Half-width [m] of the part of a crossing that is tilted (the feature), about ``c``."""
    N = ex.rec.normal[k0:k1]
    P = ex.rec.centre[k0:k1, :2]
    tilted = np.hypot(N[:, 0], N[:, 1]) > 0.5 * np.sin(np.radians(5.0))
    if not tilted.any():
        return r
    return float(np.max(np.abs((P[tilted] - c) @ across)))


def identify_feature(ex, cfg, det, search_ev):
    """Across and along crossings of a detection; returns the decision, centre, across, the
    half-width of the feature along ``across`` [m] and the across crossing's relief [m].

    The centre is where the across crossing peaks; for a bump or a pit (a point-like
    medial axis) also where the along crossing, at right angles through that point, peaks:
    the across direction comes from the search's contact normals, and an across crossing
    along it passed 3.4 mm beside the top of a 3 mm wide bump met 3 mm off its centre
    (reported 4.6 mm off; the along crossing runs over the top)."""
    r = cfg.tip_radius
    across = _axis_from_search(ex, det, r)
    c = _met_at(ex, det, r)
    half = max(float(np.ptp(det.points, axis=0).max()) / 2, 0.5 * r) + 1.5 * r
    ev1, _, (k0, k1) = yield from _crossing(ex, cfg, c, across, half, "across")
    if k1 - k0 > 20:
        c = _peak(ex, k0, k1)
    width = _extent(ex, k0, k1, c, across, r) if k1 - k0 > 20 else half
    axis = np.array([-across[1], across[0]])
    ev2, _, (k2, k3) = yield from _crossing(ex, cfg, c, axis, half, "along")
    dec = identify([search_ev, ev1, ev2])
    if dec.kind in ("bump", "pit") and k3 - k2 > 20:
        c = c + float((_peak(ex, k2, k3) - c) @ axis) * axis
    return dec, c, across, min(width, half), abs(ev1.relief)


#: the side of the plate each identified kind stands out to (+1 raised, -1 sunken)
SENSE = {"bump": 1, "ridge": 1, "pit": -1, "ravine": -1}
#: share of the across crossing's relief at which the outline is traced (its level above or
#: below the plate level). The plate level next to a wide feature is lifted (lowered) by its
#: flanks or tails by some ``dw`` that no measurement inside the region removes, and the
#: traced line moves by ``dw / slope``; a bell-shaped raised cross-section is steepest about
#: half-way up (a Lorentzian ``h/(1+x^2)`` has slope ``2 h x f^2 / w`` at the level ``f h``:
#: 0.28 h/w at f = 0.3, 0.5 h/w at f = 0.5), so a raised feature (bump, ridge: its traced
#: cross-section, the dilation of a convex top by the ball, is smooth) is traced at half its
#: relief. A sunken one (pit, ravine) narrower than the fingertip is bridged by the ball: its
#: traced cross-section ends in a crease (interference, §3.2.1) where the contact normal
#: jumps from flank to flank and cannot steer the lateral servo, so it keeps the lower level
#: of the open features (steps, cusps)
OUTLINE_SHARE = {"bump": 0.5, "ridge": 0.5}
OUTLINE_SHARE_OTHER = 0.3


def outline_rise(kind: str, relief: float, least: float) -> float:
    """Level [m] of the traced outline above (below) the plate for a feature of ``kind``
    whose across crossing had ``relief`` [m] (:data:`OUTLINE_SHARE`), at least ``least``."""
    share = OUTLINE_SHARE.get(kind, OUTLINE_SHARE_OTHER)
    return max(least, share * abs(relief))


#: the finger rests this long where the crest search of a cusp starts [s]: it lags the
#: desired position of eq. 4.9 and runs on past the start in the direction it came from.
#: The crest search (``tracing.find_crest``) stops once the centre has come down by half the
#: rise from the highest it met, taking that for the far flank; on a cusp's flank, reached
#: downhill from the raster's last line, the run-on lowered the centre that much at once,
#: and a level line 10 mm down the flank was traced (audit finding 6). The outline search
#: of the other kinds reads the plate level over its first 30 steps and needs no rest.
SETTLE_TIME = 0.1


def _come_to_rest(ex, cfg, p):
    """Slide to ``p`` (2,) [m] and hold still there for :data:`SETTLE_TIME` (phase "move":
    the finger stays in contact)."""
    yield from move_to(ex, p, cfg.speed)
    for _ in range(max(1, round(SETTLE_TIME * ex.ctl.settings.rate))):
        yield np.zeros(2)


def trace_feature(ex, cfg, rec_f: FeatureRecord, region, half: float):
    """Trace one side (closed or open), then the other side of an open ridge or ravine (a
    cusp's crest searched for from rest: :data:`SETTLE_TIME`)."""
    sides_todo = [1.0]
    kind = rec_f.decision.kind
    if kind in ("ridge", "ravine"):
        sides_todo.append(-1.0)
    for side in sides_todo:
        start = rec_f.centre + side * (half + 0.25 * cfg.tip_radius) * rec_f.across
        inward = -side * rec_f.across
        limit = 2 * half + cfg.tip_radius
        sense = SENSE.get(kind, 0)
        if kind == "cusp":
            yield from _come_to_rest(ex, cfg, start)
        outline = yield from find_outline(
            ex, cfg, start, inward, limit, rec_f.rise, crest=kind == "cusp", sense=sense
        )
        if outline is None:
            rec_f.reasons.append("outline not found")
            continue
        k0 = ex.rec.n
        res = yield from trace_boundary(ex, cfg, region, outline)
        rec_f.sides.append(res.samples)
        rec_f.traced.append(k0 + np.flatnonzero(ex.rec.phase[k0 : ex.rec.n] == PHASE["trace"]))
        rec_f.closed = rec_f.closed or res.closed
        # both sides' outlines run between the same two ends of the feature: the feature's
        # ends reached are the most one side reached (0-2), not their sum
        rec_f.ends = max(rec_f.ends, res.ends)
        rec_f.reasons.append(res.reason)
        if res.closed:
            break


def traced_sides(rec, rec_f: FeatureRecord) -> tuple[list[np.ndarray], np.ndarray]:
    """The kept boundary samples of ``rec_f`` in the recorder ``rec``: one (N_i, 2) array
    of fingertip centres [m, plate frame] per traced side, and all of them stacked (N, 2)."""
    sides = [rec.centre[s, :2] for s in rec_f.sides if len(s)]
    return sides, (np.vstack(sides) if sides else np.zeros((0, 2)))


def relabel(ex, rec_f: FeatureRecord) -> None:
    """After tracing, the outline's shape refines the kind
    (:func:`~planner.exploration.surface.identify.refine_with_outline`); a changed kind is a
    ``feature_relabelled`` event (old and new kind, confidence and the cue), so the events
    and the result's kind agree."""
    from planner.exploration.surface.identify import refine_with_outline

    _, boundary = traced_sides(ex.rec, rec_f)
    old = rec_f.decision
    new = refine_with_outline(old, boundary, rec_f.closed)
    if new.kind != old.kind:
        cue = new.path[-1] if new.path else ""
        ex.event(
            "feature_relabelled",
            f"{old.kind} ({old.confidence:.2f}) -> {new.kind} ({new.confidence:.2f}): {cue}",
            kind=new.kind,
            was=old.kind,
        )
    rec_f.decision = new


def remember(ex, state: ProgramState, rec_f: FeatureRecord, r: float) -> None:
    """Add the area of the traced feature ``rec_f`` (:func:`traced_area` grown by ``1.5 r``
    [m]) to the areas the search skips (``state.known``)."""
    state.known.append(traced_area(ex, rec_f, 1.5 * r))


def traced_area(ex, rec_f: FeatureRecord, grow: float):
    """The hull of the traced centres of ``rec_f`` (its centre alone when nothing was
    traced) grown by ``grow`` [m], a shapely geometry in the plate frame.

    The centres are every step of the trace on the outline (:attr:`FeatureRecord.traced`),
    not only the kept boundary samples: a step traced from end to end kept 9 samples at
    one end, and the search met it again 20 mm farther on and traced it twice."""
    import shapely

    pts = [ex.rec.centre[s, :2] for s in [*rec_f.sides, *rec_f.traced] if len(s)]
    geo = shapely.MultiPoint(np.vstack(pts)) if pts else shapely.Point(*rec_f.centre)
    return geo.convex_hull.buffer(grow)


def exploration_program(ex, cfg, region: np.ndarray, rng, state: ProgramState):
    """The generator driving :class:`ExplorerController` with the flow chart of Fig. 4.7
    (see the module doc; ``identify="raster"`` runs
    :func:`~planner.exploration.surface.raster_program.raster_program` instead, chosen by
    :func:`~planner.exploration.surface.explorer.explore_surface`)."""
    r = cfg.tip_radius
    yield from approach(ex)
    detector = OnlineDetector(ex, r, cfg.window, state.is_known)
    state.detector = detector
    gen, _ = segments(cfg, region, rng)
    every = max(1, round(cfg.detect_every * ex.ctl.settings.rate))  # detection period [steps]
    for a, b in gen:
        while True:
            k0, k1, det = yield from sweep(ex, a, b, cfg.speed, "search", detector, every)
            if det is None:
                break
            ex.feature = len(state.features)
            ex.event("feature_detected", f"pattern {det.pattern}", latency=det.latency)
            search_ev, _, _ = evidence(
                ex.rec.centre[det.k_start : det.k_end],
                ex.rec.normal[det.k_start : det.k_end],
                r,
                "search",
            )
            dec, c, across, half, relief = yield from identify_feature(ex, cfg, det, search_ev)
            rec_f = FeatureRecord(dec, c, across, detected_at=det.t, latency=det.latency)
            rec_f.rise = outline_rise(dec.kind, relief, cfg.boundary_rise)
            ex.event("feature_identified", f"{dec.kind} ({dec.confidence:.2f})", kind=dec.kind)
            if dec.kind != "unknown":
                yield from trace_feature(ex, cfg, rec_f, region, half)
            relabel(ex, rec_f)
            state.features.append(rec_f)
            remember(ex, state, rec_f, r)
            ex.feature = -1
            d = (b - a) / max(float(np.linalg.norm(b - a)), 1e-12)
            resume = a + max(float((ex.rec.centre[k1 - 1, :2] - a) @ d), 0.0) * d
            a = _past_known(state.known, resume, d, b)
            if float((b - a) @ d) <= 0:
                if cfg.strategy != "bug2":
                    break
                # the goal lies in the area the search skips (the feature grown by 1.5 r_f):
                # leave the feature just past its own traced outline, towards the goal
                a = _past_known([traced_area(ex, rec_f, 0.25 * r)], resume, d, b)
    ex.phase = PHASE["idle"]
    if cfg.strategy == "bug2":
        _check_goal(ex, cfg.goal)


#: the bug-2 goal counts as reached when the fingertip centre ends this close to it [m]
GOAL_TOLERANCE = 1e-3


def _check_goal(ex, goal) -> None:
    """End a bug-2 run that did not reach its ``goal`` (2,) [m] with status "failed": an event
    ``goal_not_reached`` and the reason (how far from the goal the finger stopped)."""
    gap = float(np.hypot(*(ex.est.uv - np.asarray(goal, float))))
    if gap > GOAL_TOLERANCE:
        msg = (
            f"goal not reached: the fingertip stopped {gap * 1e3:.1f} mm from the goal "
            f"{np.round(np.asarray(goal) * 1e3, 1).tolist()} mm (tolerance "
            f"{GOAL_TOLERANCE * 1e3:g} mm)"
        )
        ex.event("goal_not_reached", msg, gap=gap)
        ex.failed = msg


def _past_known(areas, p, d, b, step: float = 5e-4):
    """First point from ``p`` along ``d`` outside every shapely geometry of ``areas`` (the
    search's known areas, or one feature's traced area), not beyond ``b``."""
    q = np.asarray(p, float).copy()
    while float((b - q) @ d) > 0 and _in_any(areas, q):
        q = q + step * d
    return np.asarray(b, float).copy() if float((b - q) @ d) < 0 else q
