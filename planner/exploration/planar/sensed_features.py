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
"""

from __future__ import annotations

import math

import numpy as np

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


__all__ = ["rotation_cap", "sensed_bump"]
