"""What the executor learns online from the exploring pad and uses to plan (§2.2: the
plan is "re-done at the start of every phase from the current estimate: the nominal
shape plus what the fingers have sensed").

* :func:`sensed_bump`: after a phase 3, whether the flat pad met a macro feature (a ridge)
  and where: its sensed contact rose above the nominal circle during the pass. When the
  pad slid over it, the executor then runs a *back-stroke* (a second phase 3 that returns onto
  the feature's far side with the pad's trailing edge, :func:`.segments.explore_segment`
  ``via``): the pad and the round tip jump over a ridge's far side, and without it the
  9 deg next to the 10 cm ball's ridge were never touched (coverage 0.97).
* :func:`rotation_cap`: the largest phase-1 rotation that does not leave a sensed feature
  on the palm (the ball resting on its 3 mm ridge rocked, and every phase 3 rolled it
  10 deg back off the ridge until the gait stalled).
* :func:`image_shape`, :func:`image_ridges`, :func:`fuse_image_ridges`: the tactile-image
  cue of a ridge (§2.3.2, Fig. 2.14: "the pressure distribution near the feature becomes
  significantly sharper and changes from the characteristic pattern of a spherical contact
  to a ridge"), fused with the contact-trace detection of :mod:`.macro`.
"""

from __future__ import annotations

import math

import numpy as np

from planner.errors import InvalidParameter
from planner.exploration.planar.angles import circular_groups, circular_median
from planner.exploration.planar.controller import TRACE_NAMES

#: a pass whose pad contact rose this far above its median distance from the centre
#: crossed a macro feature [m] (the 3 mm ridge: 2.6-2.8 mm; elsewhere <= 0.5 mm)
FEATURE_HEIGHT = 1.5e-3
#: ... and a back-stroke follows when the pass ended at least this far beyond it [rad]
BACKSTROKE_MIN = math.radians(3.0)
#: phase 1 does not end with a sensed feature closer than this to the palm contact [rad]
PALM_CLEAR = math.radians(15.0)
#: ... unless that leaves less than this rotation [rad] (then the plan is not capped)
MIN_CAPPED = math.radians(4.0)
#: the palm contact's world polar angle about the object centre [rad]
PALM_ANGLE = -0.5 * math.pi

_COL = {k: i for i, k in enumerate(TRACE_NAMES)}


def sensed_bump(rows: np.ndarray) -> tuple[float, bool] | None:
    """The macro feature the pad met in one phase 3: ``(world polar angle [rad], crossed)``
    (``crossed``: the pad slid over it and the pass ended at least :data:`BACKSTROKE_MIN`
    beyond it), or None.

    Args:
        rows: (N, len(TRACE_NAMES)) the controller's trace rows of the phase.

    The feature is a bump of at least :data:`FEATURE_HEIGHT` in the pad contact's distance
    from the sensed centre above the pass's start (a whole pass lifted by a centre estimate
    3 mm off is no feature), located at the middle of the rows above half its height (the
    pad tilts onto the ridge's corners: the highest row was 8 deg beside the ridge's
    middle; a pass that ends on the feature saw its near half only).
    """
    tr = np.asarray(rows, dtype=float)
    if tr.ndim != 2 or len(tr) < 10:
        return None
    t = tr[:, _COL["t"]]
    m = (tr[:, _COL["kind"]] == 3) & (tr[:, _COL["pad_touch"]] > 0) & (t > t[0] + 0.1)
    if m.sum() < 10:
        return None
    dx = tr[m, _COL["pLx"]] - tr[m, _COL["cx"]]
    dy = tr[m, _COL["pLy"]] - tr[m, _COL["cy"]]
    r, b = np.hypot(dx, dy), np.unwrap(np.arctan2(dy, dx))
    k = int(np.argmax(r))
    base = float(np.median(r))
    if r[k] - base < FEATURE_HEIGHT or r[0] > r[k] - FEATURE_HEIGHT:
        return None
    top = b[r >= 0.5 * (r[k] + base)]
    mid = 0.5 * float(top.min() + top.max())
    beyond = math.copysign(1.0, b[-1] - b[0]) * (b[-1] - mid) >= BACKSTROKE_MIN
    crossed = bool(beyond and r[-1] <= r[k] - FEATURE_HEIGHT)
    return math.remainder(mid, 2 * math.pi), crossed


def rotation_cap(features, theta: float) -> float:
    """The largest clockwise phase-1 rotation [rad] that leaves every sensed feature ahead
    of the palm at least :data:`PALM_CLEAR` from it; ``inf`` when no feature is ahead or
    the cap would leave less than :data:`MIN_CAPPED` (the rotation then carries it over).

    Args:
        features: object-frame polar angles of the sensed features [rad].
        theta: the object rotation estimate [rad] (world angle = object angle + theta).
    """
    cap = math.inf
    for f in features:
        # clockwise rotation lowers the feature's world angle towards the palm's
        ahead = math.remainder(float(f) + theta - PALM_ANGLE, 2 * math.pi)
        if ahead > PALM_CLEAR:
            cap = min(cap, ahead - PALM_CLEAR)
    return cap if cap >= MIN_CAPPED else math.inf


#: an image this elongated is line-like [-] (:func:`image_shape`). A round contact of the
#: 10 cm ball on the 20 mm pad at 0.3 N is a Hertz patch of radius (3 F R / 4 E*)^(1/3) =
#: 2.2 mm (E* = 1 MPa): 6-16 taxels, elongation 1.00-1.09 (99th percentile of 3,000 sensed
#: images off the ridge, 4 seeds; 1.0-1.2 for any position and 0.15-0.9 N). A 4 mm wide
#: ridge under the pad is a line: across the pad (a 3-D ridge, 8 taxels long) ~8. In the
#: planar world the contacts lie on the pad's mid-line between two taxel rows, and the
#: sliding pad meets the ridge with its edge (all 4 seeds: the centroid in the outer taxel
#: column, u = 8.75 mm): a corner contact, imaged as a 1 mm sphere clipped at the pad's
#: end, that loads the two taxels beside the mid-line: exactly 2 (an edge inside the pad:
#: 1.5-2 within 0.2-0.4 mm of a taxel column's centre, 1.2 nearer a column boundary).
#: The peak fraction (:func:`image_shape`'s sharpness) is not used: a round patch centred
#: on one taxel puts 0.4-0.7 of its load into it, as much as an edge does.
LINE_ELONGATION = 1.5
#: a ridge candidate is a run of at least this many consecutive line-like images
#: of the touching pad (0.1 s at the controller's 100 Hz image rate): a pad lifting off
#: gives single 1-4 taxel images at ~0 N, the ridge held the pad for 0.25-0.45 s
IMAGE_MIN_RUN = 10
#: candidates closer than this are one ridge [rad] (the pad stops on the near edge of the
#: ridge and, on a later pass, on its far edge; the sensed pose drifts a few degrees over
#: a turn; same reach as :data:`.macro.MACRO_MERGE`)
IMAGE_MERGE = math.radians(15.0)
#: an image ridge needs a single-pass height region of the contact trace this close [rad]:
#: a line-like image says that a sharp edge touches the pad, and the pad's own edge
#: pressing on the object looks the same (it did on the 12 x 10 cm ellipse, 0.4 s at
#: -152 deg, with no height region near); the height region says something stands out of
#: the nominal outline there. A pass that ends on the ridge sees one side of it: the
#: regions of the 3 mm ridge at 170 deg lay at 165-180 deg
FUSE_ANGLE = math.radians(10.0)


#: half the length of the default left pad (``PlanarHand``) [m]
PAD_HALF_WIDTH = 0.01


def pad_end_contact(trace: dict, columns: int, pad_half_width: float = PAD_HALF_WIDTH):
    """The left pad's contact points (x (N,), y (N,)) [m] of ``trace``, moved to the pad's
    end where the tactile centroid ``u`` lies in an outer taxel column of the ``columns``
    across the pad: an edge touching the pad's end is imaged clipped at it, its centroid
    the outer column's centre, half a pitch (1.25 mm on the 20 mm, 8-column pad) short of
    the contact. On ``ball_with_ridge`` with the true rotation the ridge's near wall
    (167.7 deg) was imaged at 166.4-166.6 deg; at the pad's end, at 167.8-168.0 deg.
    The pad's axis is ``(-n_y, n_x)`` (``p = tip + u (cos phi, sin phi)``, ``n = (sin
    phi, -cos phi)``, :mod:`.sensing`)."""
    u = np.asarray(trace["u"], float)
    pitch = 2.0 * pad_half_width / columns
    shift = np.where(np.abs(u) > pad_half_width - pitch, np.sign(u) * pad_half_width - u, 0.0)
    return (trace["pLx"] - shift * trace["nLy"], trace["pLy"] + shift * trace["nLx"])


def image_shape(images) -> tuple[np.ndarray, np.ndarray]:
    """Elongation and peak sharpness of tactile images, from their pressure alone.

    Args:
        images: (M, rows, cols) taxel pressures [Pa] (negative values count as 0).

    Returns:
        ``(elongation, peak)``, each (M,): the square root of the ratio of the principal
        second moments of the pressure distribution, each plus 1/12 taxel^2 (a single
        taxel's own spread; so a round patch gives ~1, a line of n taxels
        ``sqrt(1 + (n^2 - 1))`` = n), and the fraction of the pressure in the peak taxel
        [-]; NaN for empty images. Same measure as
        :func:`.plots.tactile_elongation`, vectorized.
    """
    w = np.clip(np.asarray(images, float), 0.0, None)
    if w.ndim != 3:
        raise InvalidParameter(f"images: expected shape (M, rows, cols), got {w.shape}")
    total = w.sum(axis=(1, 2))
    safe = np.where(total > 0, total, 1.0)
    i, j = np.indices(w.shape[1:])
    mi = (w * i).sum(axis=(1, 2)) / safe
    mj = (w * j).sum(axis=(1, 2)) / safe
    di, dj = i[None] - mi[:, None, None], j[None] - mj[:, None, None]
    a = (w * di * di).sum(axis=(1, 2)) / safe + 1.0 / 12.0
    c = (w * dj * dj).sum(axis=(1, 2)) / safe + 1.0 / 12.0
    b = (w * di * dj).sum(axis=(1, 2)) / safe
    root = np.sqrt(0.25 * (a - c) ** 2 + b * b)
    hi, lo = 0.5 * (a + c) + root, 0.5 * (a + c) - root
    empty = total <= 0
    elong = np.where(empty, np.nan, np.sqrt(hi / np.maximum(lo, 1e-12)))
    peak = np.where(empty, np.nan, w.max(axis=(1, 2)) / safe)
    return elong, peak


def image_ridges(trace: dict, theta, band, pad_half_width: float = PAD_HALF_WIDTH) -> list[float]:
    """Object-frame polar angles [rad] of the ridges the pad's tactile images show.

    A candidate is a run of :data:`IMAGE_MIN_RUN` consecutive images of the exploring,
    touching pad (phase 3, normal force in ``band`` [N]) that are line-like
    (:data:`LINE_ELONGATION`), placed at the circular median
    of the pad contact's object angle over the run (sensed: tactile centroid on the pad from
    the encoders, minus the sensed centre, rotated by ``theta`` (N,) [rad]); candidates
    within :data:`IMAGE_MERGE` are one ridge, at their circular median.

    Args:
        trace: the controller's sensed series (``t``, ``kind``, ``pad_touch``, ``fnL``,
            ``pLx``, ``pLy``, ``cx``, ``cy``, ``image_t`` (M,), ``images`` (M, 8, 8)).
        theta: (N,) sensed object rotation per row [rad].
        band: ``(low, high)`` normal force [N] of a touching explorer.
        pad_half_width: half the pad's length [m] (:func:`pad_end_contact`).

    Candidates are located at the pad's end when the tactile centroid lies in an outer
    taxel column (:func:`pad_end_contact`), and a ridge seen in several runs at the median
    of their angles weighted by :func:`sighting_weight`. An image at the pad's end is a
    *wall* whose body lies beyond that end (:func:`wall_sides`): when a ridge's group has
    walls of both sides, in order (the body between them), it lies midway between their
    (weighted) medians. The sliding pad stalls on the near wall with its leading end in
    most passes and meets the far wall with its trailing end in few, so the median of all
    sightings was the near wall: with the true rotation every ``explore_object`` run of
    the ridge ball (ridge at 0-315 deg) placed the 4 mm ridge 2.1 deg short, its half-width.
    """
    ti = np.asarray(trace.get("image_t", ()), float)
    t = np.asarray(trace["t"], float)
    if ti.size < IMAGE_MIN_RUN or t.size == 0:
        return []
    rows = np.searchsorted(t, ti).clip(0, t.size - 1)
    fn = trace["fnL"][rows]
    ok = (trace["kind"][rows] == 3) & (trace["pad_touch"][rows] > 0)
    ok &= (fn >= band[0]) & (fn <= band[1])
    elong, _ = image_shape(trace["images"])
    ok &= elong >= LINE_ELONGATION
    columns = trace["images"].shape[-1]
    px, py = pad_end_contact(trace, columns, pad_half_width)
    ang = np.arctan2(py - trace["cy"], px - trace["cx"]) - theta
    side = _wall_sides(trace, columns, pad_half_width, px, py)
    idx = np.flatnonzero(ok)
    runs = np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1) if idx.size else []
    theta = np.asarray(theta, float)
    found = []
    for r in runs:
        if r.size < IMAGE_MIN_RUN:
            continue
        rr = rows[r]
        w = sighting_weight(float(np.median(theta[rr]) - theta[0]))
        found.append((circular_median(ang[rr]), w, 0))
        for sd in (1, -1):  # the run's wall images of each side, when it has enough
            m = side[rr] == sd
            if np.count_nonzero(m) >= WALL_MIN_IMAGES:
                found.append((circular_median(ang[rr][m]), w, sd))
    found.sort()
    groups = circular_groups(found, IMAGE_MERGE, angle=lambda f: f[0])
    return [_ridge_of(g) for g in groups]


#: a run's images at one end of the pad count as a wall sighting when there are this many
#: (a tenth of a second at the 100 Hz image rate; the near wall held the pad's end for
#: 0.1-0.5 s, the far wall 0.12-0.15 s) [-]
WALL_MIN_IMAGES = 10


def wall_sides(trace: dict, columns: int, pad_half_width: float = PAD_HALF_WIDTH) -> np.ndarray:
    """(N,) per trace row: +1 when the pad's contact lies at its end (the tactile centroid
    in an outer taxel column, :func:`pad_end_contact`) with the object beyond that end at
    larger polar angles (counter-clockwise about the sensed centre), -1 at smaller ones,
    0 for a contact inside the pad. An edge touching the pad's end is a wall of a bump
    whose body lies beyond the end. The pad's axis is ``(-n_y, n_x)`` (:mod:`.sensing`)."""
    px, py = pad_end_contact(trace, columns, pad_half_width)
    return _wall_sides(trace, columns, pad_half_width, px, py)


def _wall_sides(trace: dict, columns: int, pad_half_width: float, px, py) -> np.ndarray:
    """:func:`wall_sides` with the pad's end contacts ``(px, py)`` [m] already found."""
    u = np.asarray(trace["u"], float)
    pitch = 2.0 * pad_half_width / columns
    end = np.abs(u) > pad_half_width - pitch
    rx, ry = px - np.asarray(trace["cx"], float), py - np.asarray(trace["cy"], float)
    ax, ay = -np.asarray(trace["nLy"], float), np.asarray(trace["nLx"], float)
    ccw = np.sign(rx * ay - ry * ax)  # +1: the pad's +u axis turns counter-clockwise
    return np.where(end, np.sign(u) * ccw, 0.0)


def _ridge_of(group: list) -> float:
    """The angle [rad] of one ridge from its sightings ``(angle, weight, side)``: midway
    between its walls when both sides were seen in order (the side +1 wall below the side
    -1 one, less than :data:`IMAGE_MERGE` apart), else the weighted median of the whole
    runs' sightings (of the walls' when a long run's own median fell into another group)."""
    walls = {}
    for sd in (1, -1):
        sel = [(a, w) for a, w, s in group if s == sd]
        if sel:
            walls[sd] = circular_median([a for a, _ in sel], [w for _, w in sel])
    if len(walls) == 2:
        span = math.remainder(walls[-1] - walls[1], 2 * math.pi)
        if 0.0 < span < IMAGE_MERGE:
            return math.remainder(walls[1] + 0.5 * span, 2 * math.pi)
    runs = [(a, w) for a, w, s in group if s == 0] or [(a, w) for a, w, _ in group]
    return circular_median([a for a, _ in runs], [w for _, w in runs])


#: rotation [rad] over which the dead-reckoned rotation estimate's error grows to about
#: its starting error (:func:`sighting_weight`)
DRIFT_ROTATION = 0.5 * math.pi


def sighting_weight(turned: float) -> float:
    """Weight [-] of a feature sighting made after the object turned ``turned`` [rad] from
    the start: ``1 / (1 + (turned / DRIFT_ROTATION)^2)``, the inverse of the variance of a
    dead-reckoned rotation estimate whose error grows in proportion to the rotation
    integrated. The pad re-meets the ridge after the full turn, on an estimate 3-5 deg off
    (the phase-1 rolling estimate eq. 2.4 assumes a circle; with the pad on the ridge it
    gained 4.5 deg in one phase): those late sightings weigh 1/17 of the first ones."""
    return 1.0 / (1.0 + (turned / DRIFT_ROTATION) ** 2)


def fuse_image_ridges(image: list[float], found: list, single: list[float]) -> list:
    """The image ridges (angles [rad]) that the contact trace confirms but did not report:
    ``[(angle, +1), ...]``.

    An image ridge within :data:`IMAGE_MERGE` of a feature in ``found`` (``[(angle, sign)]``,
    the trace's features seen in two passes) is that feature (the trace places it from the
    ridge's whole top). Otherwise the image evidence replaces the trace's second pass: a
    single-pass ridge region or a wall the pad's end stalled at and jumped (``single``,
    angles [rad]; :func:`.macro.detect_macro_features` passes both, the walls from
    :func:`.corner_probe.jumped_walls`) within :data:`FUSE_ANGLE` confirms it, and it is
    reported where the images saw it (the pad rests on the ridge there; the region of a
    pass that ended on the ridge is off by up to 10 deg); without one it is dropped
    (:data:`FUSE_ANGLE`).
    """
    out = []
    for a in image:
        if any(abs(math.remainder(a - b, 2 * math.pi)) < IMAGE_MERGE for b, _ in found):
            continue
        if any(abs(math.remainder(a - b, 2 * math.pi)) < FUSE_ANGLE for b in single):
            out.append((a, 1))
    return out


__all__ = [
    "fuse_image_ridges",
    "image_ridges",
    "image_shape",
    "pad_end_contact",
    "rotation_cap",
    "sensed_bump",
    "sighting_weight",
    "wall_sides",
]
