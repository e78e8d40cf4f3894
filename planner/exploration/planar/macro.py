"""Macro features (ridges, grooves) from the exploring fingertips' sensed outline (§2.3.2).

The planner's model is a feature-less circle of radius ``R``. Every trace row where a finger
explores gives a sensed point on the object (object frame, with the sensed rotation of
:func:`~.metrics.object_rotation`): the flat left pad's tactile contact point in phase 3,
the round right tip's centre (encoders) in phase 2. Its distance from the estimated centre
minus the model's (``R`` for the pad contact, ``R + r`` for the tip centre) is the sensed
height of the surface above the model. Binned by polar angle (median per bin), the regions
higher (lower) than :data:`MACRO_HEIGHT` are ridges (grooves); a feature is reported at the
middle of its region, regions of both fingers within :data:`MACRO_MERGE` merged.

The threshold adapts to each finger's own scatter (:func:`height_threshold`, a constant
false-alarm rule: :data:`NOISE_SIGMAS` robust standard deviations when that is more than
:data:`MACRO_HEIGHT`). On a round object the sensed heights scatter by 0.1-0.2 mm and the
1 mm threshold holds; on an object the circle model does not fit, every phase's pose
estimate is off in its own way (heights on the 11 x 10 cm ellipse scatter by 0.6-1.1 mm,
on an 11.5 x 10 cm one by 0.7-2.1 mm), which the outline's detrending cannot remove, and
the fixed threshold reported 0-4 ridges and grooves per turn that the ellipses do not have.
Measured on recorded runs (ellipses 1.1:1 seeds 0-7 and 1.15:1 seeds 0-3; the ridge ball
with the ridge at 0-315 deg, ``ball_with_ridge`` and ``explore_object`` defaults, 38 runs):
phantom features on the ellipses 26 -> 1, on the ridge ball 2 -> 1; ridges found (35/38)
and within 5 deg (27/38) unchanged.

Why not only the curvature detector of ch. 3: the rectangular 3 mm ridge stops the sliding
flat pad (its edge meets the ridge's wall) and the round tip rolls over it with its 25 mm
radius, so neither trace has the sharp curvature extrema that detector looks for; the height
above the model is what both traces show clearly (3 mm, against 0.1-0.3 mm of noise).

A ridge seen in one pass only (the pad stopped on it with few usable samples: seeds 0 and 2
of ``ball_with_ridge`` missed it) is reported when the pad's tactile images confirm it
(§2.3.2, Fig. 2.14: the pressure image changes from a round to a line-like pattern over the
ridge): :func:`.sensed_features.image_ridges`, :func:`.sensed_features.fuse_image_ridges`;
so is one whose only pass was the pad's end stalling at the ridge's near wall and jumping
over it (:func:`.corner_probe.jumped_walls`).
"""

from __future__ import annotations

import math

import numpy as np

from planner.exploration.planar.angles import circular_groups, circular_median
from planner.exploration.planar.result import DetectedFeature
from planner.exploration.planar.sensed_features import (
    PAD_HALF_WIDTH,
    fuse_image_ridges,
    image_ridges,
)

#: a region at least this far above (below) the model is a ridge (groove) [m]
MACRO_HEIGHT = 1.0e-3
#: ... or this many times the robust scatter of the finger's sensed heights, if larger [-]
#: (:func:`height_threshold`)
NOISE_SIGMAS = 3.0
#: median absolute deviation -> standard deviation of a Gaussian sample [-]
MAD_TO_SIGMA = 1.4826
#: polar-angle bin of the sensed outline [rad]
MACRO_BIN = math.radians(0.5)
#: a region needs at least this many samples [-]
MACRO_MIN_SAMPLES = 8
#: regions of different passes closer than this are one feature [rad]: a round tip of
#: radius r rides over a feature of height h on a circle of radius R within
#: +-sqrt(2 r h) / R of it (14 deg for the 3 mm ridge), and a pass that ends on the
#: feature sees only one side of it (the ridge at 170 deg was seen at 165 and 177 deg)
MACRO_MERGE = math.radians(15.0)
#: a region covering this fraction of its pass's bins is not local (a whole pass lifted by
#: an estimate 3 mm off, e.g. with the ridge under the palm), so it is no feature [-]
MACRO_LOCAL = 0.8
#: pass numbers of the pad's rows are offset by this (the locality test applies to them:
#: in phase 3 the centre comes from the right tip and the palm; the round tip's passes are
#: exempt: riding over the ridge lifts it over +-14 deg, most of a short pass, and with the
#: test on them ``ball_with_ridge`` seed 0 lost its ridge) [-]
PAD_PASS = 1_000_000
#: a region must be seen in this many separate passes (phases) [-]: a single pass can be
#: off by the holder's estimate (in phase 3 the centre comes from the right tip and the
#: palm, 3 mm off while the ridge is under either; that gave two phantom ridges)
MACRO_MIN_PASSES = 2


def pass_numbers(kind) -> np.ndarray:
    """(N,) the pass (phase) number of every trace row: 0 for the first run of equal
    ``kind``, counting up at every change."""
    return np.concatenate([[0], np.cumsum(np.diff(np.asarray(kind)) != 0)])


def sensed_heights(trace: dict, theta, radius: float, tip_radius: float, band) -> tuple:
    """Object-frame polar angles [rad], heights above the model [m] and pass numbers (the
    phase each row belongs to) of every row where a finger explores (``band``: normal-force
    range [N] of a touching explorer)."""
    t_kind = trace["kind"]
    c, s = np.cos(-theta), np.sin(-theta)
    out_a, out_h, out_p = [], [], []
    passes = pass_numbers(t_kind)
    pad = (t_kind == 3) & (trace["pad_touch"] > 0)
    pad &= (trace["fnL"] >= band[0]) & (trace["fnL"] <= band[1])
    px, py = trace["pLx"] - trace["cx"], trace["pLy"] - trace["cy"]
    tip = (t_kind == 2) & (trace["fnR"] >= band[0]) & (trace["fnR"] <= band[1])
    rx = trace["pRx"] + tip_radius * trace["nRx"] - trace["cx"]
    ry = trace["pRy"] + tip_radius * trace["nRy"] - trace["cy"]
    for sel, x, y, model, off in (
        (pad, px, py, radius, PAD_PASS),
        (tip, rx, ry, radius + tip_radius, 0),
    ):
        X, Y = c[sel] * x[sel] - s[sel] * y[sel], s[sel] * x[sel] + c[sel] * y[sel]
        out_a.append(np.arctan2(Y, X))
        ang = np.arctan2(Y, X)
        out_h.append(_detrend(ang, np.hypot(X, Y) - model))
        out_p.append(passes[sel] + off)
    return np.concatenate(out_a), np.concatenate(out_h), np.concatenate(out_p)


#: harmonics of the smooth outline removed from the heights (an ellipse is harmonic 2) [-]
DETREND_ORDER = 4
#: ridge regularization of that fit [m^2] (keeps it bounded over unexplored angles)
DETREND_RIDGE = 1e-2


def _detrend(angles: np.ndarray, heights: np.ndarray) -> np.ndarray:
    """Heights minus their least-squares Fourier series of order :data:`DETREND_ORDER`
    in the polar angle: what is left are features narrower than ~360 / (2 order) deg (a
    12 x 10 cm ellipse is +-5 mm off its equal-area circle, which read as ridges and
    grooves; the ball's 4 mm ridge keeps ~90 % of its height)."""
    if angles.size < 4 * DETREND_ORDER + 2:
        return heights
    cols = [np.ones_like(angles)]
    for k in range(1, DETREND_ORDER + 1):
        cols += [np.cos(k * angles), np.sin(k * angles)]
    A = np.column_stack(cols)
    keep = np.ones(angles.size, dtype=bool)
    for _ in range(3):  # robust: refit without the features (no side-lobes beside a ridge)
        Ak = A[keep]
        coef = np.linalg.solve(Ak.T @ Ak + DETREND_RIDGE * np.eye(A.shape[1]), Ak.T @ heights[keep])
        res = heights - A @ coef
        keep = np.abs(res) < 0.5 * MACRO_HEIGHT
        if keep.sum() < A.shape[1]:
            break
    return res


#: evidence weight of a pass next to an excluded phase (see :func:`suspect_passes`) [-]
SUSPECT_WEIGHT = 0.5


def suspect_passes(trace: dict) -> frozenset:
    """Pass numbers (as :func:`sensed_heights` numbers them) of the passes right before or
    after an excluded window (rows whose ``kind`` is 0: a phase that ended "object moved",
    or a back-stroke). The held object starts moving before the 10 mm safety net ends such a
    phase and the estimate settles only after it, so these passes' heights are often off:
    with the ridge at 20 deg of ``ball_with_ridge`` (``explore_object``, seed 0) the round
    tip's passes right before and after one such phase made a phantom ridge 128 deg from
    the true one. They count :data:`SUSPECT_WEIGHT` of a pass."""
    kind = np.asarray(trace["kind"])
    if kind.size == 0:
        return frozenset()
    pass_kind = kind[np.r_[True, np.diff(kind) != 0]]  # the kind of every pass, in order
    out = set()
    for q in np.flatnonzero(pass_kind == 0):
        for n in (q - 1, q + 1):
            if 0 <= n < pass_kind.size and pass_kind[n] != 0:
                out.add(int(n) + (PAD_PASS if pass_kind[n] == 3 else 0))
    return frozenset(out)


def macro_regions(
    angles: np.ndarray, heights: np.ndarray, passes=None, suspect: frozenset = frozenset()
) -> list:
    """``[(angle [rad], sign), ...]`` of the features of the sensed heights (sign +1
    ridge, -1 groove).

    Each pass (``passes`` (N,) pass numbers; None: one pass) is binned by polar angle
    (median height per bin); its feature regions are the contiguous bins beyond
    :data:`MACRO_HEIGHT`, located at the middle of the bins beyond half their peak (the
    round tip's centre rises as soon as the tip touches the ridge's corner, 10-14 deg
    before it is over the ridge, and stalls on one side: the middle of the half-height
    bins is the ridge's middle, the median of the samples was not). Regions of all passes
    within :data:`MACRO_MERGE` form one feature, reported at their median when at least
    :data:`MACRO_MIN_PASSES` passes saw it; a pass in ``suspect`` (:func:`suspect_passes`)
    counts :data:`SUSPECT_WEIGHT` of a pass, in both the count and the (weighted) median.
    """
    if angles.size == 0:
        return []
    return merge_passes(pass_regions(angles, heights, passes), suspect)


def merge_passes(seen: list, suspect: frozenset = frozenset()) -> list:
    """The features ``[(angle [rad], sign), ...]`` of the single passes' regions ``seen``
    (:func:`pass_regions`): those of one sign within :data:`MACRO_MERGE` form one, kept when
    seen in :data:`MACRO_MIN_PASSES` passes (``suspect`` ones weigh :data:`SUSPECT_WEIGHT`;
    :func:`macro_regions`)."""
    out = []
    for sign in (1, -1):
        pts = sorted((a, q) for a, sg, q in seen if sg == sign)
        for g in circular_groups(pts, MACRO_MERGE, angle=lambda p: p[0]):
            weight = {q: SUSPECT_WEIGHT if q in suspect else 1.0 for _, q in g}
            if sum(weight.values()) >= MACRO_MIN_PASSES - 1e-9:
                w = [weight[q] for _, q in g]
                out.append((circular_median([a for a, _ in g], w), sign))
    return out


def pass_regions(angles: np.ndarray, heights: np.ndarray, passes=None) -> list:
    """``[(angle [rad], sign, pass), ...]``: the feature regions of every single pass (see
    :func:`macro_regions`, which keeps those seen in :data:`MACRO_MIN_PASSES` passes)."""
    passes = np.zeros(angles.size, int) if passes is None else np.asarray(passes)
    pad = passes >= PAD_PASS
    level = {True: height_threshold(heights[pad]), False: height_threshold(heights[~pad])}
    seen: list[tuple[float, int, int]] = []
    for q in np.unique(passes):
        m = passes == q
        regions = _pass_regions(angles[m], heights[m], local=q >= PAD_PASS,
                                threshold=level[bool(q >= PAD_PASS)])  # fmt: skip
        seen += [(a, sg, int(q)) for a, sg in isolated(regions)]
    return seen


def isolated(regions: list) -> list:
    """The regions of one pass without a region of the same sign within :data:`MACRO_MERGE`.

    One ridge or groove gives one region per pass; several of one sign a few degrees apart
    are the estimate wandering (the held object moving: in the passes next to an "object
    moved" phase of ``ball_with_ridge`` with the ridge at 90, 225 and 315 deg, 2-4 grooves
    6-13 deg apart made phantom grooves 110-130 deg from the ridge)."""
    return [
        (a, sg) for i, (a, sg) in enumerate(regions)
        if not any(sg2 == sg and j != i and abs(math.remainder(a - a2, 2 * math.pi)) < MACRO_MERGE
                   for j, (a2, sg2) in enumerate(regions))
    ]  # fmt: skip


def binned_median(keys: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The occupied keys (sorted) and the median of ``values`` in each: the same numbers as
    ``np.median(values[keys == k])`` per key (the middle element, or the mean of the two
    middle ones), from one sort instead of a mask and a partition per key (3,550 calls
    took 0.23 s of the detection on ``ball_with_ridge``).

    Args:
        keys: (N,) integer bin of each value; values: (N,) floats.
    """
    keys, values = np.asarray(keys), np.asarray(values, float)
    if keys.size == 0:
        return keys.astype(int), values
    order = np.lexsort((values, keys))
    k, v = keys[order], values[order]
    start = np.flatnonzero(np.r_[True, k[1:] != k[:-1]])
    count = np.diff(np.r_[start, k.size])
    lo = start + (count - 1) // 2
    hi = start + count // 2
    return k[start], np.where(lo == hi, v[lo], (v[lo] + v[hi]) / 2.0)


def height_threshold(heights: np.ndarray) -> float:
    """The height [m] a region of one finger's passes must exceed: :data:`MACRO_HEIGHT`,
    or :data:`NOISE_SIGMAS` times the robust scatter of that finger's ``heights`` [m]
    (1.4826 x their median absolute deviation, the standard deviation of Gaussian
    scatter), whichever is larger (module docstring)."""
    heights = np.asarray(heights, float)
    if heights.size == 0:
        return MACRO_HEIGHT
    sigma = MAD_TO_SIGMA * float(np.median(np.abs(heights - np.median(heights))))
    return max(MACRO_HEIGHT, NOISE_SIGMAS * sigma)


def _pass_regions(
    angles: np.ndarray, heights: np.ndarray, local: bool = False, threshold: float = MACRO_HEIGHT
) -> list:
    """Feature regions of one pass: ``[(middle angle [rad], sign), ...]``; ``local``: drop
    regions covering :data:`MACRO_LOCAL` of the pass."""
    n = int(round(2 * math.pi / MACRO_BIN))
    k = np.floor(np.mod(angles, 2 * math.pi) / MACRO_BIN).astype(int) % n
    count = np.bincount(k, minlength=n)
    med = np.zeros(n)
    occupied, medians = binned_median(k, heights)
    med[occupied] = medians
    out = []
    for sign in (1, -1):
        flag = (count > 0) & (sign * med > threshold)
        if not flag.any() or flag.all():
            continue
        start = int(np.flatnonzero(~flag)[0])  # walk the circle from an unflagged bin
        run: list[int] = []
        for j in range(start, start + n + 1):
            if flag[j % n] and j < start + n:
                run.append(j)
                continue
            ok = not local or len(run) < MACRO_LOCAL * np.count_nonzero(count)
            if run and ok and count[np.array(run) % n].sum() >= MACRO_MIN_SAMPLES:
                h = sign * med[np.array(run) % n]
                top = [b for b, x in zip(run, h, strict=True) if x >= 0.5 * h.max()]
                mid = (0.5 * (top[0] + top[-1]) + 0.5) * MACRO_BIN
                out.append((math.remainder(mid, 2 * math.pi), sign))
            run = []
    return out


def detect_macro_features(
    trace: dict, theta, profile, radius: float, tip_radius: float, band, image_kind=None
) -> list[DetectedFeature]:
    """Ridges and grooves of the sensed outline (module docstring), each compared with the
    nearest true feature of ``profile`` (the middle of its cluster of curvature features).
    ``image_kind``: (N,) the ``kind`` column for the tactile images (default the trace's;
    back-strokes are left out of the trace's heights but not of the images)."""
    a, h, p = sensed_heights(trace, theta, radius, tip_radius, band)
    seen = pass_regions(a, h, p) if a.size else []
    found = merge_passes(seen, suspect_passes(trace))
    single = [ang for ang, sign, _ in seen if sign > 0]
    images = trace if image_kind is None else {**trace, "kind": image_kind}
    found += fuse_image_ridges(
        image_ridges(images, theta, band), found, single + _walls(trace, theta, radius)
    )
    truth = _truth_clusters(profile)
    return [as_feature(ang, "ridge" if sign > 0 else "groove", truth) for ang, sign in found]


def _walls(trace: dict, theta, radius: float) -> list[float]:
    """The walls the pad's end stalled at and jumped (:func:`.corner_probe.jumped_walls`),
    [rad]: they confirm an image ridge as a single-pass height region does. A pad that
    stops at a ridge's near wall touches it with its end, 1 mm up the 3 mm wall (sensed
    heights 0.3-0.8 mm, under :data:`MACRO_HEIGHT`), and flies over the top: on the ridge
    ball with the ridge at 0, 45 and 315 deg (``explore_object`` defaults) the only pass
    over it was such a jump, the images saw the ridge and no height region confirmed it."""
    from planner.exploration.planar.controller import TRACE_NAMES
    from planner.exploration.planar.corner_probe import jumped_walls

    if "images" not in trace or not all(k in trace for k in TRACE_NAMES):
        return []  # no images to confirm, or a partial trace (every column is read)
    columns = int(np.shape(trace["images"])[-1]) if np.size(trace["images"]) else 8
    return jumped_walls(trace, theta, radius, PAD_HALF_WIDTH, columns)


def as_feature(angle: float, kind: str, truth: list[float]) -> DetectedFeature:
    """A :class:`DetectedFeature` at ``angle`` [rad] compared with the nearest of ``truth``
    (polar angles [rad]; empty: not compared)."""
    if not truth:
        return DetectedFeature(angle, kind)
    err = [math.remainder(angle - b, 2 * math.pi) for b in truth]
    j = int(np.argmin(np.abs(err)))
    return DetectedFeature(angle, kind, truth[j], err[j])


def _truth_clusters(profile) -> list[float]:
    """Polar angles [rad] of the profile's features: its curvature features within
    :data:`MACRO_MERGE` of each other taken as one (a ridge has four edges)."""
    from planner.exploration.planar.pad_trace import VIRTUAL_RADIUS

    angs = sorted(
        math.atan2(f.position[1], f.position[0]) for f in profile.curvature_features(VIRTUAL_RADIUS)
    )
    # each cluster's mean, unwrapped about its first angle (a cluster may span +-pi)
    return [
        math.remainder(c[0] + float(np.mean([math.remainder(x - c[0], 2 * math.pi) for x in c])),
                       2 * math.pi)
        for c in circular_groups(angs, MACRO_MERGE)
    ]  # fmt: skip


__all__ = [
    "as_feature",
    "binned_median",
    "detect_macro_features",
    "height_threshold",
    "macro_regions",
    "merge_passes",
    "pass_regions",
    "sensed_heights",
    "suspect_passes",
]
