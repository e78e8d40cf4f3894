"""Boundary tracing (thesis §4.4.2, Fig. 4.8) and the continue-or-move-on parameter (§4.5.2).

The direction of travel is the intersection of the plane parallel to the nominal surface (the
plate) and the plane orthogonal to the contact normal: ``t ∝ z_plate × n``, the level line of
the flank under the contact. What keeps the finger on the outline is a lateral correction. The
contact *tilt* cannot be servoed: in the concave foot of a feature sharper than the fingertip
the ball touches either the plate (tilt 0) or the flank (tilt ~30°) - an interference point,
§3.2.1 - and the tilt jumps. The fingertip centre's height above the plate is continuous (the
traced surface): the finger keeps its centre ``boundary_rise`` above (or below, for a pit or a
ravine) the plate level where it started, so the outline traced is a level line of the traced
surface, and the feature's skeleton (the medial axis is shared by the offset curves) is
unchanged. Samples far from that level (re-approach after losing the feature) are dropped.

The plate level is read where the finger meets the feature's foot (:func:`find_outline`,
:func:`~planner.exploration.surface.plates.foot_levels`): the true outline of the metrics is
the same level line.

Tracing ends when the loop closes, when both ends of an open feature are reached (the contact
leaves the region: the finger returns to the start and traces the other way), or when the
decision parameter of §4.5.2 turns negative: ``D = w_info g - w_cost t/T`` with ``g`` the share
of recent boundary samples that are new (farther than 1 mm from the older ones) and ``t/T``
the share of the tracing budget spent; coming back onto traced boundary makes ``g`` drop to 0.
A decision stop closes the outline only once the finger has come back round to where tracing
began; stretches it went round unsettled there are filled from the traced path
(:func:`trace_boundary`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner.exploration.surface.motions import move_to
from planner.exploration.surface.plates import FOOT_TILT
from planner.exploration.surface.runtime import PHASE

__all__ = [
    "Outline",
    "TraceResult",
    "find_outline",
    "level_distance",
    "plate_level",
    "trace_boundary",
]


@dataclass(frozen=True)
class TraceResult:
    """Outcome of tracing one side of a feature.

    Attributes:
        samples: recorder indices of the boundary samples (re-approach dropped).
        closed: the loop closed; ends: ends of an open outline reached (0-2).
        reason: why tracing stopped.
    """

    samples: np.ndarray
    closed: bool
    ends: int
    reason: str


@dataclass(frozen=True)
class Outline:
    """Where the approach met the feature.

    Attributes:
        level: centre height to keep [m]; sigma: +1 raised from this side, -1 sunken.
        rise: distance of ``level`` from the plate level [m].
        inward: (2,) direction of the approach [-].
    """

    level: float
    sigma: float
    inward: np.ndarray
    rise: float = 2.5e-4


def plate_level(ex, local: float, rise: float, ends: int = 40, sense: int = 0) -> float:
    """The plate level [m] (centre height on the bare plate) next to the feature, when
    :func:`find_outline` cannot read it at the feature's foot (the finger still tilted
    after backing out).

    ``local`` [m] is the height where the approach starts, a few millimetres from the
    feature: on the long tails of a wide bump or pit it is off the plate by a good part of
    ``rise``, which would move the traced level line. The last across crossing ran through
    the feature about twice as far out; the level at its end nearer to the finger (the same
    side: a step's other level is never mixed in) is used when it is within ``rise`` of
    ``local`` (raster identification has no across crossing: ``local``).

    ``sense`` is the side of the plate the feature stands out to (+1 raised: bump, ridge;
    -1 sunken: pit, ravine; 0: a step, unknown). For a raised feature the plate level is the
    *lower* of the two heights, for a sunken one the higher: the one farther from the
    feature's side is the one less lifted by its flank or its tails (the across crossing's
    end is where the ball still rests on a wide ridge's flank: 0.4 mm up on a 5 mm ridge).
    """
    rec = ex.rec
    idx = np.flatnonzero(rec.phase[: rec.n] == PHASE["across"])
    if idx.size < 4 * ends:
        return local
    cut = np.flatnonzero(np.diff(idx) > 1)
    run = idx[cut[-1] + 1 :] if cut.size else idx
    if run.size < 4 * ends:
        return local
    here = ex.est.uv
    heads = (run[:ends], run[-ends:])
    near = min(heads, key=lambda k: float(np.hypot(*(rec.centre[k, :2].mean(axis=0) - here))))
    w = float(np.mean(rec.centre[near, 2]))
    if sense > 0:
        return min(w, local)
    if sense < 0:
        return max(w, local)
    return w if abs(w - local) < rise else local


def find_outline(
    ex,
    cfg,
    start,
    inward,
    limit: float,
    rise: float | None = None,
    crest: bool = False,
    sense: int = 0,
):
    """Slide from ``start`` along ``inward`` over the feature's foot until the centre leaves
    the plate level there by ``rise`` (default ``boundary_rise``); returns an
    :class:`Outline` or None (not met within ``limit`` [m]).

    The plate level is the centre's height at the feature's foot
    (:func:`~planner.exploration.surface.plates.foot_levels`, the plate level of the true
    outline; §4.4.2, "the plane of travel before the feature was encountered"): where the
    contact tilt rises past :data:`~planner.exploration.surface.plates.FOOT_TILT`, the tilt
    and the height filtered alike (:class:`_FootFilter`). When the start already rests on
    the flank (tilted past it) the finger first backs out by up to ``r_f``; when it is
    still tilted there (a plate crowded with features) the level is :func:`plate_level`'s.

    Once the contact is tilted (on the feature's flank) the finger slides along the slope
    (up a raised feature, down a sunken one: the sense that agrees with ``inward``), so it
    meets the outline even when ``inward`` misses the feature's centre. ``crest``: the
    feature has no plate level (a cusp: the plate falls away on both sides); the finger
    climbs over the crest and the outline is ``rise`` below it (:func:`find_crest`).
    ``sense``: the identified side of the feature (:func:`plate_level`)."""
    if crest:
        return (yield from find_crest(ex, cfg, start, inward, limit, rise))
    yield from move_to(ex, start, cfg.speed)
    ex.phase = PHASE["reapproach"]
    inward = np.asarray(inward, float) / np.linalg.norm(inward)
    ref, tilts = [], []
    for _ in range(30):  # the plate level here
        ref.append(ex.est.centre[2])
        tilts.append(ex.est.tilt)
        yield np.zeros(2)
    rise = cfg.boundary_rise if rise is None else rise
    foot = _FootFilter(ex, float(np.mean(tilts)), float(np.mean(ref)))
    if foot.tilt > FOOT_TILT:  # on the flank already: back out onto the plate
        p1 = ex.est.uv.copy()
        while foot.tilt > FOOT_TILT and float(np.hypot(*(ex.est.uv - p1))) < cfg.tip_radius:
            yield -cfg.trace_speed * inward
            foot.update(ex)
    # the plate level: None until the foot is met (the finger rests on the plate here)
    w0 = plate_level(ex, float(np.mean(ref)), rise, sense=sense) if foot.tilt > FOOT_TILT else None
    p0 = ex.est.uv.copy()
    heading = inward
    while w0 is None or abs(ex.est.centre[2] - w0) < rise:
        if float(np.hypot(*(ex.est.uv - p0))) > limit:
            return None
        n = ex.est.normal
        tilt = float(np.hypot(n[0], n[1]))
        if tilt > 0.03:  # the slope's direction (2,), in the sense of the approach
            g = np.array([n[0], n[1]]) / tilt
            heading = g if float(g @ inward) > 0 else -g
        yield cfg.trace_speed * heading
        if w0 is None:
            w0 = foot.update(ex)
    sigma = 1.0 if ex.est.centre[2] > w0 else -1.0
    return Outline(w0 + sigma * rise, sigma, heading, rise)


class _FootFilter:
    """The contact tilt and the centre height low-pass filtered alike, and where the tilt
    rises past :data:`~planner.exploration.surface.plates.FOOT_TILT` (the feature's foot).

    The estimate's normal is already filtered by the hybrid law (eq. 4.2, weight ``alpha``
    a servo step); the height goes through the same filter first, then both through
    :data:`SMOOTH` steps, so the two lag alike and the height read at the crossing is the
    one at the foot (with the height unfiltered the foot of a 3 mm step's upper side was
    read 0.05 mm low, on the flank).

    Attributes:
        tilt: the filtered tilt [-]; height: the filtered centre height [m].
    """

    def __init__(self, ex, tilt: float, height: float) -> None:
        settings = getattr(ex.ctl, "settings", None)
        self.alpha = float(getattr(settings, "alpha", 1.0))
        self.tilt, self.height, self._z = tilt, height, height

    def update(self, ex) -> float | None:
        """Filter the current estimate in; the height at the foot [m] (interpolated to the
        crossing) when the tilt has just risen past ``FOOT_TILT``, else None."""
        self._z += self.alpha * (float(ex.est.centre[2]) - self._z)
        t_new = self.tilt + (ex.est.tilt - self.tilt) / SMOOTH
        w_new = self.height + (self._z - self.height) / SMOOTH
        crossed = self.tilt <= FOOT_TILT < t_new
        a = (FOOT_TILT - self.tilt) / max(t_new - self.tilt, 1e-12)
        at = self.height + a * (w_new - self.height)
        self.tilt, self.height = t_new, w_new
        return at if crossed else None


def find_crest(ex, cfg, start, inward, limit: float, rise: float | None = None):
    """Climb from ``start`` along ``inward`` (then up the slope) over a crest; the outline is
    the level ``rise`` below the highest centre height met, on the far flank. None when the
    centre has not come down by ``rise / 2`` from its highest within ``limit`` [m]."""
    yield from move_to(ex, start, cfg.speed)
    ex.phase = PHASE["reapproach"]
    rise = cfg.boundary_rise if rise is None else rise
    heading = np.asarray(inward, float) / np.linalg.norm(inward)
    p0 = ex.est.uv.copy()
    top = float(ex.est.centre[2])
    while float(ex.est.centre[2]) > top - 0.5 * rise:
        if float(np.hypot(*(ex.est.uv - p0))) > limit:
            return None
        top = max(top, float(ex.est.centre[2]))
        n = ex.est.normal
        tilt = float(np.hypot(n[0], n[1]))
        if tilt > 0.03 and float(ex.est.centre[2]) >= top - 1e-5:  # still climbing: uphill
            g = np.array([n[0], n[1]]) / tilt
            heading = -g if float(-g @ heading) > 0 else heading
        yield cfg.trace_speed * heading
    return Outline(top - rise, 1.0, -heading, rise)


#: a sample is kept when the centre is within this distance of the level line [m] (the
#: height error over the flank slope under the contact: a first-order distance) ...
ACCEPT_LATERAL = 1.5e-4
#: ... and has stayed within ``SETTLED_LATERAL`` [m] of it for ``SETTLE`` servo steps (the
#: approach overshoot and the servo's transient after a re-approach are dropped)
SETTLE, SETTLED_LATERAL = 60, 3e-4
#: the height error is low-pass filtered over this many servo steps (the encoders' height
#: noise, ~15 um, over a flank slope of 0.1 is 0.15 mm of distance) [-]
SMOOTH = 20
#: lateral servo gains on the distance to the level line, proportional [1/s] and integral
#: [1/s^2]: on a curved outline the finger's lag makes it drift outwards, which a purely
#: proportional servo would balance with a steady offset from the level line
LATERAL_GAIN, LATERAL_INTEGRAL = 10.0, 100.0
#: the explorer's servo period (the 1 kHz control rate) [s]
SERVO_DT = 1e-3
#: flattest flank slope used to turn a height error into a distance [-]
MIN_SLOPE = 0.05


def level_distance(ex, outline: Outline, w: float | None = None) -> tuple[float, float]:
    """``(err, dist)``: the height error ``sigma (level - w)`` [m] (``w``: the centre height,
    default the current one) and its first-order distance to the level line, ``err /
    slope`` with the slope of the traced surface under the contact (tan of the contact
    normal's tilt, at least :data:`MIN_SLOPE`) [m]; positive towards the feature."""
    n = ex.est.normal
    tilt = float(np.hypot(n[0], n[1]))
    slope = max(tilt / max(float(n[2]), 1e-6), MIN_SLOPE)
    w = float(ex.est.centre[2]) if w is None else w
    err = outline.sigma * (outline.level - w)
    return err, err / slope


def trace_boundary(ex, cfg, region: np.ndarray, outline: Outline, orient: float = 1.0):
    """Trace the level line ``outline.level`` of the centre from where the finger is.

    The lateral servo drives the first-order distance to the level line
    (:func:`level_distance`) to zero; a sample is kept once it has settled (module constants
    ``ACCEPT_LATERAL``, ``SETTLE``, ``SETTLED_LATERAL``); the loop closes when the finger
    comes back to the first kept sample, so the outline is made of settled samples only.

    When the decision parameter (§4.5.2) stops the tracing first, the outline counts as
    closed only if the finger has come back within ``r / 4`` of where tracing began (else
    a stretch traced to and fro would pass for a loop). Its kept samples may still leave
    holes (:data:`HOLE`): on the inside of a bend the ball rests on both arms' flanks, the
    servo overshoots by up to 0.8 mm of height and settles only 3-8 mm later, on every lap
    alike (another lap of the bent ridge below left the same 2.7 mm hole; tracing back
    the other way cut the bend elsewhere and ran out of the 12 s budget). A hole makes a
    Voronoi branch of the medial axis run into it, so the holes left after
    :func:`_fill_holes` are filled from the traced path (:func:`_fill_from_path`; the
    reason then says how large they were) rather than the trace going on or the outline
    being reported open: an open outline would make the skeleton code pair it with a
    second traced side and the identification keep the open kinds. Measured (skeleton's
    farthest point from the crest line): ``scenarios/curved_ridge.yaml`` 2.83 -> 0.94 mm
    (a 1.3 mm hole filled), the bent ridge ``(-9, 6), (1, -2), (9, 1)`` mm (2 mm high,
    1.8 mm wide, seed 1) 1.68 -> 1.40 mm (a 2.1 mm hole; what is left comes from the
    unsettled stretch's own lateral error), tracing time unchanged (9.3 s, 6.5 s).

    Returns:
        :class:`TraceResult`.
    """
    r = cfg.tip_radius
    k_start, t_start = ex.rec.n, ex.est.t
    su, sv = float(ex.est.centre[0]), float(ex.est.centre[1])  # where tracing began
    first_uv = None  # where the first settled sample was taken
    near = None  # closest approach to it once back within 0.1 r
    returned = False  # the finger has come back to where tracing began
    steady, w, held = 0, float(ex.est.centre[2]), 0.0  # held: the integral term [-]
    samples: list[int] = []
    loose: list[int] = []  # on the outline within SETTLED_LATERAL, not kept (holes' filling)
    turned = False  # a tangent has been chosen since (re)starting
    tu = tv = 0.0  # the tangent of the previous step (2,)
    iu, iv = float(outline.inward[0]), float(outline.inward[1])  # towards the feature
    sig, level, lost_err = float(outline.sigma), float(outline.level), 2.0 * outline.rise
    speed, trace_time = float(cfg.trace_speed), float(cfg.trace_time)
    # an end is reached where the outline *leaves* the region (an outline inside it, however
    # near its edge, is followed round: a closed one is closed); when tracing begins outside
    # it (a feature next to the region's edge), only farther out than that by r / 10
    u0, u1 = float(region[0, 0]), float(region[0, 1])
    v0, v1 = float(region[1, 0]), float(region[1, 1])
    beyond0 = max(u0 - su, su - u1, v0 - sv, sv - v1, 0.0)
    out_limit = beyond0 + 0.1 * r if beyond0 > 0.0 else 0.0
    ends, travelled, farthest = 0, 0.0, 0.0
    pu, pv = su, sv
    reason = "trace budget spent"
    trace, reapproach = PHASE["trace"], PHASE["reapproach"]
    # the loop runs once per servo period: Python floats, no small numpy arrays
    while ex.est.t - t_start < trace_time:
        est = ex.est
        n, C = est.normal, est.centre
        nx, ny, nz = float(n[0]), float(n[1]), float(n[2])
        cu, cv = float(C[0]), float(C[1])
        tilt = math.hypot(nx, ny)
        travelled += math.hypot(cu - pu, cv - pv)
        pu, pv = cu, cv
        if tilt > 0.03:  # the contact is on the feature: the uphill direction is known
            iu, iv = -sig * nx / tilt, -sig * ny / tilt
        ttu, ttv = -orient * iv, orient * iu
        if turned and ttu * tu + ttv * tv < -0.2:
            ttu, ttv = -ttu, -ttv  # keep the sense of travel through saddles of the tilt field
        tu, tv, turned = ttu, ttv, True
        w += (float(C[2]) - w) / SMOOTH
        err = sig * (level - w)  # level_distance() with the smoothed height, inlined
        dist = err / max(tilt / max(nz, 1e-6), MIN_SLOPE)
        steady = steady + 1 if abs(dist) < SETTLED_LATERAL else 0
        lost = abs(err) > lost_err
        ex.phase = reapproach if lost else trace
        if steady >= SETTLE and abs(dist) < ACCEPT_LATERAL:
            samples.append(ex.rec.n - 1)
            if first_uv is None:
                first_uv = (cu, cv)
        elif not lost and abs(dist) < SETTLED_LATERAL:
            loose.append(ex.rec.n - 1)
        if not lost:
            held = min(max(held + LATERAL_INTEGRAL * dist * SERVO_DT / speed, -0.5), 0.5)
        lateral = min(max(LATERAL_GAIN * dist / speed + held, -0.7), 0.7)
        along = 0.3 if lost else 1.0
        farthest = max(farthest, math.hypot(cu - su, cv - sv))
        if max(u0 - cu, cu - u1, v0 - cv, cv - v1) > out_limit:
            ends += 1
            ex.event("end_reached", "the outline leaves the region", point=[cu, cv])
            if ends == 2:
                reason = "both ends reached"
                break
            # back past the first kept sample by the settling distance, then the other way:
            # the samples of both ways meet without a gap; with no sample kept yet, back to
            # where tracing began (not ``ex.rec.centre[k_start]``: that row is written only
            # after the first servo step, and before it holds zeros, the plate's origin)
            if samples:
                k_back = samples[min(len(samples) - 1, SETTLE)]
                goal = (float(ex.rec.centre[k_back, 0]), float(ex.rec.centre[k_back, 1]))
            else:
                goal = (su, sv)
            yield from move_to(ex, goal, cfg.speed)
            orient, turned, steady = -orient, False, 0
            # the way back is no to-and-fro: the come-back test (and so the decision and
            # the closing) measures the trace from here on, the other way (counted from the
            # start, the return made travelled > 2.5 farthest on arrival, where the recent
            # samples overlap the first ones: a decision stop with one end reached)
            su, sv = goal
            pu, pv = float(ex.est.centre[0]), float(ex.est.centre[1])
            travelled, farthest, returned, near = 0.0, 0.0, False, None
            continue
        if farthest > 0.2 * r and travelled > max(2.5 * farthest, 0.5 * r):
            # back past where tracing began (the unsettled stretch before the first kept
            # sample is traced again, settled), then closed at the first kept sample
            returned = returned or math.hypot(cu - su, cv - sv) < 0.25 * r
            home = (su, sv) if first_uv is None else first_uv
            near = _closing(cu, cv, home, 0.1 * r, near) if returned else None
            if near is not None and near < 0:
                if _covered(ex, samples, k_start):
                    reason = "loop closed"
                    break
                near = None  # a stretch traced unsettled: once more around

            if near is None and est.k % 100 == 0 and _decision(ex, cfg, samples, t_start) < 0:
                reason = "decision parameter < 0 (no new boundary)"
                break
        yield speed * (along * tu + lateral * iu), speed * (along * tv + lateral * iv)
    # a decision stop closes the outline only once the finger has come back round to where
    # tracing began (not a stretch traced to and fro); holes it left are filled
    closed = ends == 0 and (reason == "loop closed" or (reason.startswith("decision") and returned))
    if not closed:
        return TraceResult(np.array(samples, int), closed, ends, reason)
    kept = _fill_holes(ex, samples, loose)
    if samples and not _covered(ex, list(kept), k_start):
        kept, gap = _fill_from_path(ex, kept, samples[0])
        if gap > 0.0:
            reason += f"; holes up to {gap * 1e3:.1f} mm filled from the traced path"
    return TraceResult(kept, closed, ends, reason)


#: a stretch of the traced outline farther than this from every kept sample is a hole [m]
HOLE = 5e-4


def _fill_holes(ex, samples: list[int], loose: list[int]) -> np.ndarray:
    """The kept samples of a closed outline plus, where they leave a hole (:data:`HOLE`), the
    trace samples within ``SETTLED_LATERAL`` of the level line there (recorder indices in
    trace order).

    Where the outline turns sharply (the end cap of a narrow ravine or a small ridge) the
    lateral servo never settles to ``ACCEPT_LATERAL`` and the kept samples leave a gap of a
    millimetre or more; a Voronoi branch of the medial axis then runs into the gap (a
    skeleton 2-3 mm off the crest line, where the true outline's own medial axis, pruned at
    the same significance, stays within 0.3 mm of it). These samples are on the outline -
    not the re-approach of §4.4.2, which is dropped - with a larger lateral error, at most
    ``SETTLED_LATERAL``. A sample counts as in a hole when its nearest kept sample is
    farther than ``HOLE + SETTLED_LATERAL`` (a lateral offset alone cannot put it there: on
    a small, tight outline the loose samples lie beside the kept ones, not in a gap); only
    runs of at least ``SMOOTH`` consecutive servo steps are added
    (a stray sample inside the outline would grow a loop in the medial axis). Open outlines
    (steps, cusps: their pseudo-skeleton is the samples themselves) are left as kept."""
    if len(samples) < 10 or not loose:
        return np.array(samples, int)
    return _fill_runs(ex, np.asarray(samples, int), np.asarray(loose, int))[0]


def _fill_from_path(ex, kept: np.ndarray, first: int) -> tuple[np.ndarray, float]:
    """``(kept', gap)``: the samples of a closed outline plus, where they still leave a hole
    (:data:`HOLE`, as in :func:`_fill_holes`), the traced centres there (trace phase: the
    finger on the outline, not lost), from the first kept sample ``first`` on (the approach
    transient before it is traced again settled when the loop closes); ``gap`` [m] is the
    farthest an added centre lies from the kept samples (0: nothing added)."""
    rec = ex.rec
    kept = np.asarray(kept, int)
    if len(kept) < 10:
        return kept, 0.0
    cand = first + np.flatnonzero(rec.phase[first : rec.n] == PHASE["trace"])
    return _fill_runs(ex, kept, np.setdiff1d(cand, kept))


def _fill_runs(ex, kept: np.ndarray, cand: np.ndarray) -> tuple[np.ndarray, float]:
    """``(kept', gap)``: ``kept`` plus the candidate recorder rows ``cand`` (sorted) that lie
    farther than ``HOLE + SETTLED_LATERAL`` from every kept sample (a lateral offset alone
    cannot put them there) in runs of at least ``SMOOTH`` consecutive rows (a stretch of
    outline, not a stray sample); ``gap`` [m]: the farthest an added row lies from the kept
    samples (0: nothing added). The fill of :func:`_fill_holes` and
    :func:`_fill_from_path`."""
    from scipy.spatial import cKDTree

    if cand.size == 0:
        return kept, 0.0
    rec = ex.rec
    d, _ = cKDTree(rec.centre[kept, :2]).query(rec.centre[cand, :2])
    far = d > HOLE + SETTLED_LATERAL
    add, dist = cand[far], d[far]
    cut = np.flatnonzero(np.diff(add) > 1) + 1
    pieces = zip(np.split(add, cut), np.split(dist, cut), strict=True)
    runs = [(a, b) for a, b in pieces if len(a) >= SMOOTH]
    if not runs:
        return kept, 0.0
    gap = max(float(b.max()) for _, b in runs)
    return np.union1d(kept, np.concatenate([a for a, _ in runs])), gap


def _covered(ex, samples: list[int], k_start: int, gap: float = HOLE) -> bool:
    """Whether every point the finger traced since ``k_start`` is within ``gap`` [m] of a
    kept sample (a stretch it went round unsettled, at a sharp end cap on the first lap
    say, leaves a hole in the outline until it is traced again)."""
    from scipy.spatial import cKDTree

    rec = ex.rec
    if len(samples) < 10:
        return False
    path = rec.centre[k_start : rec.n : 10, :2][rec.phase[k_start : rec.n : 10] == PHASE["trace"]]
    if len(path) == 0:
        return True
    d, _ = cKDTree(rec.centre[np.asarray(samples), :2]).query(path)
    return bool(d.max() < gap)


def _closing(cu: float, cv: float, home, zone: float, near: float | None, slack: float = 2e-4):
    """Closest distance [m] of the centre ``(cu, cv)`` to ``home`` since entering the
    ``zone`` around it (None: not in it yet); -1 once the finger has passed its closest
    approach (or is on ``home``): the loop closes with the first samples overlapped, not a
    ``zone``-wide gap."""
    d = math.hypot(cu - home[0], cv - home[1])
    if d >= zone and near is None:
        return None
    near = d if near is None else min(near, d)
    return -1.0 if d > near + slack or d < 1e-4 else near


def _decision(ex, cfg, samples: list[int], t_start: float) -> float:
    """§4.5.2: ``D = w_info g - w_cost (t - t0)/T`` (recorded in ``ex.rec.decision``)."""
    from scipy.spatial import cKDTree

    rec = ex.rec
    if len(samples) < 80:
        return 1.0
    recent = np.array(samples[-40:])
    s = np.asarray(samples)
    old = s[rec.t[s] < rec.t[recent[0]] - 0.5]
    if len(old) < 10:
        return 1.0
    d, _ = cKDTree(rec.centre[old, :2]).query(rec.centre[recent, :2])
    gain = float(np.mean(d > 1e-3))
    D = cfg.info_weight * gain - cfg.cost_weight * (ex.est.t - t_start) / cfg.trace_time
    rec.decision[max(rec.n - 1, 0)] = D
    return D
