"""Measures of an exploration: outline coverage and the exploring pad's features."""

from __future__ import annotations

import math

import numpy as np

from planner.exploration.planar.pad_trace import VIRTUAL_RADIUS, phase_runs
from planner.exploration.planar.result import DetectedFeature
from robots.sensors import TactileArray


def coverage_of(log, body: str, profile, cells: int = 360, phases=None) -> float:
    """Fraction of the outline's polar-angle cells touched by a fingertip (true contacts;
    with ``phases``, by the exploring fingertip of each phase only): the mean of
    :func:`coverage_mask`."""
    return float(coverage_mask(log, body, profile, cells, phases).mean())


def coverage_mask(log, body: str, profile, cells: int = 360, phases=None) -> np.ndarray:
    """(cells,) whether each polar-angle cell of the outline (object frame, cell ``k``
    spans ``[k, k + 1) 360 / cells`` deg) holds a true contact point of a fingertip
    (``*.left`` / ``*.right``) with a positive normal force.

    With ``phases`` (the result's :class:`~.result.PhaseRecord` list) only the exploring
    finger's contacts count: the right finger's in phases 2, the left finger's in phases 3
    (the strict reading of "touched by an exploring fingertip"); without, every fingertip
    contact counts (phase-1 rolling and the holder sense the outline too)."""
    hit = np.zeros(cells, dtype=bool)
    pose = log.poses[body]
    when = {}  # phase kind -> (T,) rows inside a phase of that kind
    for ph in phases or ():
        rows = (log.t >= ph.start) & (log.t <= ph.end)
        when[ph.phase] = when[ph.phase] | rows if ph.phase in when else rows
    for j, pair in enumerate(log.pairs):
        a, b = pair.split("|")
        if body not in (a, b) or not any(x.endswith((".left", ".right")) for x in (a, b)):
            continue
        touch = (log.contact_pair == j) & (log.normal_force > 0)
        if phases is not None:  # the right finger explores in phases 2, the left in 3
            kind = 2 if any(x.endswith(".right") for x in (a, b)) else 3
            touch &= when.get(kind, np.zeros(len(log.t), dtype=bool))[:, None]
        rows, slots = np.nonzero(touch)
        if rows.size == 0:
            continue
        P = log.contact_point[rows, slots]
        x, y, ang = pose[rows, 0], pose[rows, 1], pose[rows, 2]
        dx, dy = P[:, 0] - x, P[:, 1] - y
        c, s = np.cos(ang), np.sin(ang)
        ox, oy = c * dx + s * dy, -s * dx + c * dy
        k = (np.floor(np.mod(np.arctan2(oy, ox), 2 * np.pi) / (2 * np.pi) * cells)).astype(int)
        hit[np.clip(k, 0, cells - 1)] = True
    return hit


def ridge_coverage(mask: np.ndarray, ridge_angle: float, half_angle: float, shadow: float) -> dict:
    """Coverage beside a ridge: the cells (``mask`` of :func:`coverage_mask`) left
    untouched, and the coverage of the cells outside the ridge's shadows.

    Args:
        mask: (cells,) touched cells.
        ridge_angle: the ridge's middle (object frame) [rad]; half_angle: half its width as
            a polar angle [rad] (its walls at ``ridge_angle +- half_angle``).
        shadow: polar angle beside each wall that the fingertips cannot touch [rad]
            (:func:`round_tip_shadow`, :func:`pad_shadow`).

    Returns:
        ``{"uncovered_deg": [[from, to], ...], "shadow_deg": ..., "shadow_cells": n,
        "coverage_outside_shadow": ...}`` (runs of untouched cells, in degrees).
    """
    cells = mask.size
    mid = (np.arange(cells) + 0.5) * 2 * math.pi / cells
    off = np.abs(np.remainder(mid - ridge_angle + math.pi, 2 * math.pi) - math.pi)
    shade = (off > half_angle) & (off < half_angle + shadow)
    outside = ~shade
    runs, start = [], None
    for k in range(cells + 1):
        free = k < cells and not mask[k]
        if free and start is None:
            start = k
        elif not free and start is not None:
            runs.append([round(start * 360.0 / cells, 2), round(k * 360.0 / cells, 2)])
            start = None
    return {
        "uncovered_deg": runs,
        "shadow_deg": math.degrees(shadow),
        "shadow_cells": int(shade.sum()),
        "coverage_outside_shadow": float(mask[outside].mean()) if outside.any() else float("nan"),
    }


def _detect(points: np.ndarray, normals: np.ndarray) -> list[tuple[np.ndarray, int]]:
    """THE adapter to ``planner.detection`` (its types are being unified elsewhere).

    Args:
        points: (N, 2) sensed contact points of the pad in the object frame [m].
        normals: (N, 2) outward object normals there.

    Returns:
        ``[(position (2,), sign), ...]`` of the curvature features found.
    """
    from planner.detection import detect_features

    centres = points + VIRTUAL_RADIUS * normals
    feats = detect_features(centres, VIRTUAL_RADIUS, algorithm=1, normals=normals,
                            contacts=points)  # fmt: skip
    return [(np.asarray(f.position, float), int(f.sign)) for f in feats]


#: steady sliding: skip this long after the pad starts exploring (startup ramps) [s]
SETTLE_TIME = 0.1
#: steady sliding: the pad's normal force within these multiples of the commanded one [-]
FORCE_BAND = (0.5, 3.0)
#: steady sliding: the contact moves over the object at least this fast [m/s]
MIN_SLIDE_SPEED = 0.002
#: detections of one feature on repeated passes closer than this are merged [rad]
MERGE_ANGLE = math.radians(3.0)


#: rows at the start of a phase 1 that :func:`object_rotation` does not read: the first
#: row's sensed centre is still the one of the phase before (the controller switches its
#: source with the phase; on 48 recorded ``ball_with_ridge`` runs, ridge at 0-315 deg,
#: seeds 0-5, the centre's error at a phase 1's first row: median 0.31 mm, 90th
#: percentile 3.1 mm; at its second and third: 0.25 / 0.39 mm), and the rolling of both
#: fingertips read from that centre put a jump of up to 5 deg into the phase
PHASE1_SKIP = 1


def object_rotation(trace: dict, radius: float) -> np.ndarray:
    """The sensed object rotation [rad] of every trace row, chained over the phases from
    the first row's estimate; each phase adds its own sensed increment, from its first row:

    * phase 1: the rolling of both fingertips (eq. 2.4), averaged: the flat pad's
      ``d(beta_L) - d(u) / R`` (:func:`pad_rolling`) and the round tip's
      ``d(beta_R) + d(s_R) / R`` (:func:`tip_rolling`);
    * phase 2: the ball held on the palm by the pad rolls on the pad,
      :func:`held_pad_rolling` (the pad's rolling, and past the tactile array's edge the
      same relation on the centre from the palm and the pad's line);
    * phase 3: the ball lies on the palm and rolls on it, ``-(c_x - c_x0) / R`` from the
      phase's first row (the holder is the round right tip, whose contact says little),
      with the centre from the holding tip and the palm corrected where a bump under the
      tip lifts it (:func:`held_tip_centre_x`).

    Phase 1 is read from its second row on (:data:`PHASE1_SKIP`). A trace without the
    fingertips' columns keeps the controller's estimate in phase 1, from its first row.
    This is the mapping estimate: every sensed angle on the object (features, coverage of
    the sensed outline) uses it. The controller integrates its own causal estimate, the
    pad's rolling only (``trace["theta"]``), for the object impedance and the planning.

    Why both fingertips in phase 1: with the ridge under the pad, the tactile centroid jumps
    onto the ridge and the pad's rolling reads it as rotation; the tip's rolling, built on
    the pad-based centre, errs the other way. Per phase 1 of ``ball_with_ridge`` with the
    ridge at 0-315 deg (seeds 0-1, 308 phases), error RMS / max: pad 2.6 / 31 deg, tip 1.6 /
    14 deg, their mean 0.84 / 8.5 deg. Why :func:`held_pad_rolling` in phase 2: when the
    sliding right tip drags the ball over the ridge (``"object moved"``), the ball slides on
    the palm while it turns (the palm's ``-dx / R`` read +19.4 deg of turning as -10.6 deg)
    and the contact runs off the array; 311 phases: RMS 2.2 -> 0.75 deg. Together
    (``bench_gait_ridge.py``, ridge at 0-315 deg, seeds 0-1): ridges within 5 deg 2 -> 8/16
    with the scenario's settings, 12 -> 11/16 with the defaults of then (a 60 N/m exploring
    tip); ``ball_with_ridge`` seeds 0-3: 3.6/1.1/1.4/0.9 -> 2.7/0.1/0.1/0.0 deg. Not used
    (measured): phase 3's end corrected by the centre from the exploring pad's line (per
    phase RMS 0.89 -> 0.55 deg; defaults 11 -> 13/16 within 5 deg, but a phantom concave
    feature on ``ball_with_ridge`` seed 0).
    """
    th = np.array(trace["theta"], float)
    kind = np.asarray(trace["kind"])
    if th.size == 0:
        return th
    out = np.empty_like(th)
    acc = th[0]
    cols = ("u", "pad_touch", "pLx", "pLy", "nLx", "nLy", "pRx", "pRy", "cx", "cy", "sR")
    line = line_like_rows(trace)
    tips = all(c in trace for c in cols)
    for run in phase_runs(kind):
        k = kind[run[0]]
        # each phase from its own first reading (the last phase's centre and centroid came
        # from another source: the palm, an array edge); phase 1 from its second, as its
        # first row still holds the centre of the phase before (:data:`PHASE1_SKIP`)
        skip = PHASE1_SKIP if k == 1 and tips and run.size > PHASE1_SKIP + 1 else 0
        sub = {c: np.asarray(trace[c], float)[run[skip:]] for c in cols if c in trace}
        if k == 3:
            cx = sub["cx"]
            if line is not None and all(c in sub for c in cols[:6]):
                cx = held_tip_centre_x(sub, radius, line[run])
            inc = -(cx - cx[0]) / radius
        elif k not in (1, 2):
            inc = np.zeros(run.size)
        elif k == 1 and not tips:  # no fingertip readings
            inc = th[run] - th[run[0]]
        else:
            if k == 2:
                inc = held_pad_rolling(sub, radius)
            else:
                inc = 0.5 * (pad_rolling(sub, radius) + tip_rolling(sub, radius))
            inc = inc - inc[0]
        inc = np.concatenate([np.zeros(skip), inc])
        out[run] = acc + inc
        acc = out[run[-1]]
    return out


#: a phase-3 centre from the holding tip this far [m] off its usual offset from the
#: exploring pad's centre is lifted by a bump under the tip (:func:`held_tip_centre_x`)
TIP_LIFT = 0.8e-3


def line_like_rows(trace: dict) -> np.ndarray | None:
    """(N,) whether the left pad's tactile image nearest each trace row (``image_t``,
    ``images``) is line-like (:data:`.sensed_features.LINE_ELONGATION`: an edge or a ridge
    under the pad); None without images."""
    from planner.exploration.planar.sensed_features import LINE_ELONGATION, image_shape

    ti = np.asarray(trace.get("image_t", ()), float)
    t = np.asarray(trace.get("t", ()), float)
    if ti.size == 0 or t.size == 0:
        return None
    elong, _ = image_shape(trace["images"])
    near = np.searchsorted(ti, t).clip(0, ti.size - 1)
    prev = (near - 1).clip(0)
    near = np.where(np.abs(ti[prev] - t) < np.abs(ti[near] - t), prev, near)
    return np.nan_to_num(elong[near], nan=1.0) >= LINE_ELONGATION


def held_tip_centre_x(trace: dict, radius: float, line_like, lift: float = TIP_LIFT):
    """Phase 3's centre abscissa [m] per row of one phase: the trace's (the ball on the
    palm touching the holding round tip, ``c_x``), corrected by the exploring pad where a
    bump under the tip lifts it.

    The pad gives a second centre, ``p_L - R n_L`` (its tactile contact), wherever it
    touches cleanly: centroid within :data:`PAD_CENTROID_EDGE` of its middle and a round
    image (``line_like`` (N,) false). Their difference keeps an offset over a phase (the
    median over the clean rows); where it departs from it by more than ``lift`` [m], the
    tip's centre is moved by the departure. Why: a ridge under the holding tip lifts it by
    up to its height, and the centre ``c_x = t_x - sqrt((R + r)^2 - (R - t_y)^2)`` comes out
    up to 3.5 mm off while the pad's stays within 0.4 mm (16 recorded ridge-ball runs,
    ``explore_object`` defaults, ridge at 0-315 deg: per phase 3 the end error's RMS 1.54
    -> 1.40 deg, the phases more than 1.5 deg off 33 -> 20 of 284, the mean 0.165 ->
    0.015 deg). The ridge under the pad instead shows in its image or its centroid, and
    those rows keep the tip's centre."""
    cx = np.asarray(trace["cx"], float)
    cp = np.asarray(trace["pLx"], float) - radius * np.asarray(trace["nLx"], float)
    u = np.asarray(trace["u"], float)
    ok = (np.asarray(trace["pad_touch"]) > 0) & (np.abs(u) <= PAD_CENTROID_EDGE)
    ok &= ~np.asarray(line_like, bool)
    if ok.sum() < 10:
        return cx
    depart = (cx - cp) - float(np.median((cx - cp)[ok]))
    fix = ok & (np.abs(depart) > lift)
    return np.where(fix, cx - depart, cx)


def tip_rolling(trace: dict, radius: float) -> np.ndarray:
    """The rotation [rad] of an object of ``radius`` [m] rolling on the round right tip, up
    to a constant, per trace row: ``beta_R + s_R / R`` (eq. 2.4 for two circles: the
    contact's polar angle about the sensed centre and its arclength on the tip from the
    apex, ``trace["sR"]``); rows without ``s_R`` (no rolling reference) hold the last
    value."""
    b = np.unwrap(np.arctan2(trace["pRy"] - trace["cy"], trace["pRx"] - trace["cx"]))
    val = b + np.asarray(trace["sR"], float) / radius
    return _held(val, np.isfinite(val))


#: largest tactile centroid [m] across the pad that :func:`held_pad_rolling` reads as the
#: contact: 0.8 of the pad array's outermost taxel centre (``robots.sensors.TactileArray``:
#: 8.75 mm for 8 columns at 2.5 mm pitch, so 7 mm). Beyond it the contact patch runs off
#: the array, the centroid sticks at the outer taxel and the centre ``p_L - R n_L`` built
#: on it is millimetres off (a ball dragged 23 deg along the palm read 10.6 deg)
PAD_CENTROID_EDGE = 0.8 * float(np.abs(TactileArray().u).max())


def held_pad_rolling(trace: dict, radius: float, edge: float = PAD_CENTROID_EDGE) -> np.ndarray:
    """The rotation [rad] of an object of ``radius`` [m] held by the flat left pad against
    the palm (phase 2), up to a constant, per trace row: rolling on the pad (eq. 2.4,
    ``beta_L - u / R`` with ``beta_L`` the polar angle of the pad's outward normal ``n_L``),
    with the contact ``u`` from the tactile centroid while it lies within ``edge`` [m] of
    the pad's middle (the increments of :func:`pad_rolling`), and otherwise from the palm
    and the pad's line: the centre ``c = (c_x, R)`` at ``R`` from the line,
    ``c_x = (p_L . n_L - R - R n_Ly) / n_Lx``, touches the pad at ``c + R n_L``, whose
    place along the pad's axis ``(-n_Ly, n_Lx)`` is the contact. Rows where the pad does
    not touch hold the last touching value.

    Why: the right tip sliding over the ridge drags the held ball 16-26 deg along the palm
    (``"object moved"``); the contact then runs off the array's edge, the centroid sticks
    at its outermost taxel and the pad-only estimate read 3-17 deg too little. On 311
    phases 2 of ``ball_with_ridge`` with the ridge at 0-315 deg (seeds 0-1) the error's
    RMS went from 2.2 to 0.75 deg. The palm's contact alone is 3 deg off at a phase's start,
    where the ball still drops onto the palm from phase 1's lift; hence the centroid
    wherever it can be read."""
    u = np.asarray(trace["u"], float)
    touch = np.asarray(trace["pad_touch"]) > 0
    if not touch.any():
        return np.zeros_like(u)
    R = radius
    nx, ny = np.asarray(trace["nLx"], float), np.asarray(trace["nLy"], float)
    px, py = np.asarray(trace["pLx"], float), np.asarray(trace["pLy"], float)
    with np.errstate(divide="ignore", invalid="ignore"):
        cx = (px * nx + py * ny - R - R * ny) / nx
    # the palm's contact along the pad: u + (foot - p_L) . axis, foot = c + R n_L
    u_palm = u + (cx + R * nx - px) * -ny + (R + R * ny - py) * nx
    normal = np.unwrap(np.arctan2(ny, nx))
    rows = np.flatnonzero(touch)
    inside = np.abs(u[rows]) <= edge
    use_tactile = inside[1:] & inside[:-1]
    inc = np.where(use_tactile, -np.diff(u[rows]), -np.diff(u_palm[rows])) / R
    inc = np.diff(normal[rows]) + np.where(np.isfinite(inc), inc, 0.0)
    val = np.zeros_like(u)
    val[rows] = np.concatenate([[0.0], np.cumsum(inc)]) + normal[rows[0]] - u[rows[0]] / R
    return _held(val, touch)


def pad_rolling(trace: dict, radius: float, round_tip: bool = False) -> np.ndarray:
    """The rotation [rad] of an object of ``radius`` [m] rolling on the flat left pad, up to a
    constant, per trace row: ``beta_L - u / R`` (eq. 2.4; ``beta_L`` the unwrapped polar
    angle of the pad's contact about the sensed centre, ``u`` the contact's place on the
    pad [m]; with ``round_tip`` a round left tip, ``u`` its contact's arclength from the
    apex: ``beta_L + u / R``); rows where the tip does not touch hold the last touching
    value."""
    b = np.unwrap(np.arctan2(trace["pLy"] - trace["cy"], trace["pLx"] - trace["cx"]))
    s = np.asarray(trace["u"], float) * (1.0 if round_tip else -1.0)
    return _held(b + s / radius, np.asarray(trace["pad_touch"]) > 0)


def _held(val: np.ndarray, ok: np.ndarray) -> np.ndarray:
    """``val`` where ``ok``; elsewhere the last ``ok`` value (before the first: the first
    one); all zeros when no row is ``ok``."""
    if not ok.any():
        return np.zeros_like(val)
    last = np.maximum.accumulate(np.where(ok, np.arange(val.size), -1))
    return val[np.where(last >= 0, last, int(np.flatnonzero(ok)[0]))]


def steady_sliding(trace: dict, explore_force: float = 0.3) -> np.ndarray:
    """Rows of ``trace`` where the left pad explores in steady sliding contact (phase 3,
    touching, past the startup ramps, normal force near ``explore_force`` [N], contact
    moving over the object): the only rows the detector sees (the rest gave spurious
    features: startup transients, pressing and sticking)."""
    t, kind = trace["t"], trace["kind"]
    sel = (kind == 3) & (trace["pad_touch"] > 0)
    start = np.full(len(t), np.inf)
    idx = np.flatnonzero(kind == 3)
    if idx.size:
        runs = np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1)
        for run in runs:
            start[run] = t[run[0]]
    sel &= t >= start + SETTLE_TIME
    fn = trace["fnL"]
    sel &= (fn >= FORCE_BAND[0] * explore_force) & (fn <= FORCE_BAND[1] * explore_force)
    if len(t) > 2:
        th = trace["theta"]
        px, py = trace["pLx"] - trace["cx"], trace["pLy"] - trace["cy"]
        ang = np.unwrap(np.arctan2(py, px) - th)  # polar angle of the contact on the object
        speed = np.abs(np.gradient(ang, t)) * np.hypot(px, py)
        n = min(9, len(t))  # a 9-row moving average ('same' keeps the length only if n <= rows)
        sel &= np.convolve(speed, np.ones(n) / n, mode="same") >= MIN_SLIDE_SPEED
    return sel


#: the curvature detector uses a phase 3 only while the held object's sensed centre stays
#: within this distance of its place at the phase's start [m]. The 10 mm hold check ends a
#: phase in which the object is dragged ("object moved", excluded everywhere); below it,
#: 28 explore_object runs of the ridge ball (ridge at 10-340 deg) had six phantom convex /
#: concave features, each from a phase 3 whose centre moved 8.9-10 mm, and a phantom concave
#: on ``ball_with_ridge`` seed 1 came from one that moved 4.5 mm (the median phase 3 moves
#: 2.1 mm; 31 % move more than 4 mm). Macro features keep every phase (their own checks).
CURVATURE_HOLD = 0.004


def held_still(trace: dict, limit: float) -> np.ndarray:
    """Rows of ``trace`` in a phase 3 (``kind`` 3) whose sensed object centre stayed within
    ``limit`` [m] of the phase's first row over the whole phase (other rows: False)."""
    kind = np.asarray(trace["kind"])
    out = np.zeros(kind.size, dtype=bool)
    if kind.size == 0:
        return out
    cx, cy = np.asarray(trace["cx"], float), np.asarray(trace["cy"], float)
    for run in phase_runs(kind):
        if kind[run[0]] == 3:
            moved = np.hypot(cx[run] - cx[run[0]], cy[run] - cy[run[0]]).max()
            out[run] = moved <= limit
    return out


#: a pass of the pad continues over this many unselected trace rows (20 ms at 500 Hz)
MAX_GAP_ROWS = 10
#: angular bin of the sensed outline a pass is resampled on before detection [rad]
BIN_ANGLE = math.radians(0.25)


def outline_bins(points: np.ndarray, normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One pass of the pad as an outline: its object-frame points (N, 2) [m] and normals
    (N, 2) resampled on :data:`BIN_ANGLE` polar-angle bins (median radius, mean normal per
    occupied bin), in increasing angle.

    The sliding pad sticks and slips (it stalls, then jumps 1-2 deg, and creeps back under
    the holder's compliance): in time order that trace folds back on itself, and the
    detector read every fold as a convex/concave pair (one spurious pair per phase 3).
    Binning by polar angle keeps the shape and drops the time order."""
    from planner.exploration.planar.macro import binned_median

    a = np.unwrap(np.arctan2(points[:, 1], points[:, 0]))
    r = np.hypot(points[:, 0], points[:, 1])
    k = np.floor((a - a.min()) / BIN_ANGLE).astype(int)
    occupied, rad = binned_median(k, r)
    order = np.argsort(k, kind="stable")  # each bin's rows in their original order
    start = np.searchsorted(k[order], occupied)
    count = np.diff(np.r_[start, k.size])
    ang = np.add.reduceat(a[order], start) / count
    nrm = np.add.reduceat(normals[order], start, axis=0) / count[:, None]
    nrm /= np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-12)
    return np.column_stack([rad * np.cos(ang), rad * np.sin(ang)]), nrm


def detect_pad_features(
    trace: dict,
    profile,
    rest,
    radius: float,
    explore_force: float = 0.3,
    tip_radius: float = 0.025,
    exclude=(),
    keep_images=(),
) -> list[DetectedFeature]:
    """Features in the left pad's sensed trace while it explores (phase 3).

    Only rows of steady sliding contact are used (:func:`steady_sliding`). Points are
    mapped to the object frame with the *estimated* pose (centre and rotation from the
    sensors), detected per contiguous run, reported as polar angles on the object (one per
    feature: repeated detections within :data:`MERGE_ANGLE` are merged) and matched to the
    nearest true curvature feature of ``profile``. Macro features (ridges, grooves) come
    from :mod:`.macro` (the contact trace's heights above the model, fused with the tactile
    images' line-like pattern over a ridge, :func:`.sensed_features.image_ridges`).
    ``exclude``: ``(t0, t1)`` windows [s] left out (phases that ended
    with "object moved": the held object moved, so the sensed pose there is wrong - each
    gave a phantom ridge or groove next to the true ridge). ``keep_images``: ``(t0, t1)``
    windows [s] whose tactile images count for the image ridges although their contact
    trace is excluded (back-strokes: the pad touches with its end, which made a phantom
    groove in the trace, but its end meeting the far wall of the feature it returns to is
    what places the feature between its walls, :func:`.sensed_features.image_ridges`).
    """
    if len(trace.get("t", ())) == 0:
        return []
    trace = {**trace, "theta": object_rotation(trace, radius)}
    image_kind = _without(trace, exclude)
    trace["kind"] = _without(trace, [*exclude, *keep_images])
    from planner.exploration.planar.macro import detect_macro_features

    band = (FORCE_BAND[0] * explore_force, FORCE_BAND[1] * explore_force)
    macro = detect_macro_features(trace, trace["theta"], profile, radius, tip_radius, band,
                                  image_kind=image_kind)  # fmt: skip
    sel = steady_sliding(trace, explore_force) & held_still(trace, CURVATURE_HOLD)
    truth = [math.atan2(f.position[1], f.position[0])
             for f in profile.curvature_features(VIRTUAL_RADIUS)]  # fmt: skip
    out = []
    idx = np.flatnonzero(sel)
    if idx.size == 0:
        return macro
    # a pass is split only at gaps longer than MAX_GAP_ROWS: the pad bounces off for single
    # control steps (touch flicker), which cut every pass into 0.1 s pieces of 1-2 deg
    runs = np.split(idx, np.flatnonzero(np.diff(idx) > MAX_GAP_ROWS) + 1)
    for run in runs:
        if run.size < 20:
            continue
        th = trace["theta"][run]
        c, s = np.cos(-th), np.sin(-th)
        px, py = trace["pLx"][run] - trace["cx"][run], trace["pLy"][run] - trace["cy"][run]
        nx, ny = trace["nLx"][run], trace["nLy"][run]
        P = np.column_stack([c * px - s * py, s * px + c * py])
        N = np.column_stack([c * nx - s * ny, s * nx + c * ny])
        P, N = outline_bins(P, N)
        if len(P) < 10:
            continue
        try:
            found = _detect(P, N)
        except Exception:  # noqa: BLE001 - a trace the detector cannot use adds nothing
            continue
        for pos, sign in inside_pass(found, P):
            a = math.atan2(pos[1], pos[0])
            if truth:
                err = [math.atan2(math.sin(a - b), math.cos(a - b)) for b in truth]
                j = int(np.argmin(np.abs(err)))
                out.append(
                    DetectedFeature(a, "convex" if sign > 0 else "concave", truth[j], err[j])
                )
            else:
                out.append(DetectedFeature(a, "convex" if sign > 0 else "concave"))
    return macro + _merge(out)


def _without(trace: dict, windows) -> np.ndarray:
    """The trace's ``kind`` column with the rows in the ``(t0, t1)`` ``windows`` [s] set to
    0 (no phase: left out)."""
    kind = np.array(trace["kind"], float)
    for t0, t1 in windows:
        kind[(trace["t"] >= t0) & (trace["t"] <= t1)] = 0.0
    return kind


#: a curvature feature needs this much of the pass on each side [m]: three of the
#: detector's largest smoothing scale (``VIRTUAL_RADIUS / 4`` for the tactile algorithm 1,
#: ``planner.detection.signals.default_scale``), the reach of its Gaussian derivatives;
#: nearer an end they see the padding. On ball_with_ridge (merged with main 243732f) seeds
#: 0 and 2 reported a convex (21.1 deg) and a convex/concave pair (27.7/28.9 deg) 1.2-2.4 deg
#: from the first sample of a pass, where the ball has no feature.
EDGE_ARC = 3.0 * VIRTUAL_RADIUS / 4.0


def inside_pass(found: list, points: np.ndarray) -> list:
    """The detections ``[(position (2,), sign), ...]`` at least :data:`EDGE_ARC` (straight
    distance: the binned outline's radial noise lengthens its arclength) from both ends of
    the outline ``points`` (N, 2) [m]."""
    out = []
    for pos, sign in found:
        p = np.asarray(pos, float)
        if min(np.hypot(*(p - points[0])), np.hypot(*(p - points[-1]))) >= EDGE_ARC:
            out.append((pos, sign))
    return out


def _merge(found: list[DetectedFeature]) -> list[DetectedFeature]:
    """One detection per feature and kind (the first of those within MERGE_ANGLE)."""
    kept: list[DetectedFeature] = []
    for f in found:
        if not any(
            g.kind == f.kind
            and abs(math.atan2(math.sin(f.angle - g.angle), math.cos(f.angle - g.angle)))
            < MERGE_ANGLE
            for g in kept
        ):
            kept.append(f)
    return kept


def _rms(x) -> float:
    x = np.asarray(x, float)
    return float(np.sqrt(np.mean(x * x))) if x.size else float("nan")


def _median(x) -> float:
    x = np.asarray(x, float)
    return float(np.median(x)) if x.size else float("nan")


def slip_distance(log) -> float:
    """Total sliding distance of the fingertips over objects [m] (integrated slip speed)."""
    total = 0.0
    dt = np.diff(log.t, prepend=log.t[0]) if len(log.t) else np.zeros(0)
    for j, pair in enumerate(log.pairs):
        if not any(x.endswith((".left", ".right")) for x in pair.split("|")):
            continue
        m = (log.contact_pair == j) & (log.normal_force > 0)
        v = np.abs(np.where(m, log.slip_velocity, 0.0))
        total += float(np.sum(v * dt[:, None]))
    return total


def summary_metrics(res, ridge_angle, explore_force: float, internal_force: float) -> dict:
    """The metrics of the ``gait`` scenario kind (see its docstring)."""
    tr = res.trace
    t = tr["t"]
    kind = tr["kind"]
    wall = res.timings.get("wall_s", float("nan"))
    sim_t = float(res.log.t[-1]) if len(res.log.t) else 0.0
    settled = np.zeros(len(t), dtype=bool)
    for ph in res.phases:
        settled |= (t >= ph.start + 0.1) & (t <= ph.end)
    exp = np.where(kind == 2, tr["fnR"], tr["fnL"])
    sel = settled & (kind > 1)
    steps = np.asarray(res.timings.get("control_step_us", []), float)
    nlp = np.asarray(res.timings.get("nlp_solve_ms", []), float)
    out = {
        "status": res.status,
        "phases": len(res.phases),
        "transitions_4": res.transitions4,
        "rotation_deg": math.degrees(res.rotation),
        "coverage": res.coverage,
        "coverage_any_contact": res.contact_coverage,
        "min_epsilon": res.min_epsilon,
        "slip_distance_m": slip_distance(res.log),
        "explore_force_rms_error_N": _rms(exp[sel] - explore_force),
        "internal_force_rms_error_N": _rms((tr["f_int"] - tr["f_des"])[settled & (kind >= 1)]),
        "features_found": len(res.features),
        "real_time_factor": sim_t / wall if wall > 0 else float("nan"),
        "wall_s": wall,
        "nlp_build_s": res.timings.get("nlp_build_s", float("nan")),
        "nlp_solve_median_ms": float(np.median(nlp)) if nlp.size else float("nan"),
        "nlp_solve_cpu_median_ms": _median(res.timings.get("nlp_solve_cpu_ms", [])),
        "nlp_iterations_median": _median(res.timings.get("nlp_iterations", [])),
        "controller_call_median_us": float(np.median(steps)) if steps.size else float("nan"),
        # in the compiled phase loop a call is timed with its simulator step (chunk / calls)
        "controller_call_includes_sim_step": bool(
            steps.size and res.timings.get("control_steps_compiled", 0) >= 0.5 * steps.size
        ),
        "end_event": res.phases[-1].event if res.phases else "",
    }
    feats = [{"angle_deg": math.degrees(f.angle), "kind": f.kind,
              "error_deg": math.degrees(f.error) if np.isfinite(f.error) else None}
             for f in res.features]  # fmt: skip
    out["features"] = feats[:50]
    if ridge_angle is not None:
        errs = [abs(math.atan2(math.sin(f.angle - ridge_angle), math.cos(f.angle - ridge_angle)))
                for f in res.features]  # fmt: skip
        best = min(errs) if errs else float("nan")
        out["ridge_error_deg"] = math.degrees(best) if errs else None
        out["ridge_found"] = bool(errs) and math.degrees(best) <= 5.0
    return out


def round_tip_shadow(radius: float, height: float, tip_radius: float) -> float:
    """Polar angle [rad] beside a radial step of ``height`` [m] on a circle of ``radius``
    [m] (a ridge's side wall) that a round fingertip of ``tip_radius`` [m] cannot touch: the
    tip touching the circle and the step's top corner has its centre at ``R + r`` from the
    circle's centre and ``r`` from the corner (at ``R + h``), so the angle between the wall
    and the tip's contact on the circle is::

        arccos(((R + h)^2 + (R + r)^2 - r^2) / (2 (R + h) (R + r)))

    The 25 mm right tip beside the 3 mm ridge of the 10 cm ball: 10.8 deg per side.
    """
    R, h, r = float(radius), float(height), float(tip_radius)
    c = ((R + h) ** 2 + (R + r) ** 2 - r * r) / (2.0 * (R + h) * (R + r))
    return math.acos(min(max(c, -1.0), 1.0))


def pad_shadow(radius: float, height: float, reach: float) -> float:
    """Polar angle [rad] beside a radial step of ``height`` [m] on a circle of ``radius``
    [m] that a flat pad tangent to the circle cannot touch when its end lies ``reach`` [m]
    ahead of its contact (along the pad, towards the step): the pad stops when its end
    meets the wall (``atan(reach / R)``) or, if its face passes above the wall's foot, when
    the face meets the step's corner (``atan(sqrt((R + h)^2 - R^2) / R)``), whichever is
    nearer. A 20 mm pad touching with its middle (reach 10 mm) at the 3 mm ridge of the
    10 cm ball: 11.3 deg; touching 2.5 mm from its end (the corner probe,
    :mod:`.corner_probe`): 2.9 deg."""
    R, h = float(radius), float(height)
    corner = math.sqrt((R + h) ** 2 - R * R)
    return math.atan(min(float(reach), corner) / R)


__all__ = [
    "coverage_mask",
    "coverage_of",
    "held_pad_rolling",
    "held_tip_centre_x",
    "line_like_rows",
    "object_rotation",
    "tip_rolling",
    "pad_rolling",
    "outline_bins",
    "pad_shadow",
    "ridge_coverage",
    "round_tip_shadow",
    "detect_pad_features",
    "inside_pass",
    "slip_distance",
    "steady_sliding",
    "summary_metrics",
]
