"""Exploring strokes that overlap the same finger's previous stroke (the strict coverage
of issue 11: "the fraction of the outline touched by an exploring fingertip").

The left pad's strokes of phase 3 tile the outline as the object turns: each runs from
where phase 1 rolled the contact to (20-28 deg on) towards larger object angles, over
20-28 deg (the right tip's strokes of phase 2, 12-16 deg, fill between them). A stroke
that starts farther past the end of the previous one than the pad's contact slips back at
its start (3.5-4 deg, as its force ramps down) leaves a strip that no explorer touched
(only phase-1 rolling and the hold did): on ``ball_with_ridge`` 59-65 and 84-85 deg (seed
0), 62/63-64 and 219-221 deg (seeds 1-3).

:class:`ExploredOutline` is the executor's memory of the explored outline (object frame,
from the sensed contacts and the rotation estimate, no truth), and
:meth:`ExploredOutline.back_to` is the overlap rule: a stroke whose start lies more than
:data:`MIN_GAP` past the end of the same finger's previous stroke (looking back at most
:data:`LOOKBACK`) first goes back :data:`OVERLAP` into it and then on to its own target
(:func:`.segments.explore_segment` with ``via`` and ``edge=False``: the contact centred
on the pad). With it the strips are gone on seeds 0-7; what the explorers leave are the
ridge's shadows (:func:`.corner_probe.approach_segment`). Off by default
(``GaitSettings.stroke_overlap``): each way back costs a Fig. 2.14 sign change (below).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from planner import checks
from planner.exploration.planar.controller import TRACE_NAMES

#: a stroke goes back when it starts this far past the previous stroke's end [rad]
#: (sensed). The pad's contact slips back 3.5-4 deg at a stroke's start, so the sensed gap
#: is the true one plus ~4 deg: on seeds 0-3 of ``ball_with_ridge`` the 73 pad strokes with
#: sensed gaps up to 5.0 deg left true gaps of at most 1.0 deg (filled by the other
#: finger), the 10 with 5.9-10.9 deg true gaps of 1.8-7.8 deg (the untouched strips). 4 deg
#: goes back 5-6 times a run (seeds 0-3 ok); 5.5 deg 1-2 times, and seed 0 then failed
#: (its first way back changed the gait enough that the ridge later stuck on the palm:
#: 4 cycles of -10/+10 deg, "no progress" at 255 deg; the unchanged gait passed there after
#: 2 such cycles). Each way back costs a tangential sign change at the 2 -> 3 switch (Fig.
#: 2.14: a stroke that starts backwards keeps phase 2's sign)
MIN_GAP = math.radians(4.0)
#: how far back a stroke looks for the explored outline [rad] (one phase 1 turns the ball
#: 20-28 deg; a longer way back runs over what the other finger will explore anyway)
LOOKBACK = math.radians(12.0)
#: how far into the explored outline the stroke goes back [rad]
OVERLAP = math.radians(3.0)
#: no way back within this of a sensed feature [rad] (the pad's half-length seen from the
#: 10 cm ball's centre is 11.3 deg: going back over a ridge, its end would meet the wall)
FEATURE_CLEARANCE = math.radians(15.0)
#: a round tip touches the object above this sensed normal force [N]
TOUCH_FORCE = 0.05

_COL = {k: i for i, k in enumerate(TRACE_NAMES)}


def sensed_contact_angles(rows: np.ndarray, kind: int, radius: float) -> np.ndarray:
    """Object-frame polar angles [rad] of the explorer's sensed contacts in one phase 2
    (``kind`` 2: the right tip, touching above :data:`TOUCH_FORCE`) or 3 (the left pad,
    touching by its tactile array).

    Args:
        rows: (N, len(TRACE_NAMES)) the controller's trace rows of the phase.
        kind: 2 or 3; radius: the estimate's radius [m].

    The rotation of a row is the phase's estimate minus the centre's roll on the palm
    (``-(c_x - c_x0) / R``), as the executor integrates it after a phase 3.
    """
    tr = np.asarray(rows, dtype=float)
    if tr.ndim != 2 or not len(tr):
        return np.zeros(0)
    cx, cy = tr[:, _COL["cx"]], tr[:, _COL["cy"]]
    theta = tr[:, _COL["theta"]] - (cx - cx[0]) / radius
    if kind == 2:
        px, py = tr[:, _COL["pRx"]], tr[:, _COL["pRy"]]
        touch = tr[:, _COL["fnR"]] > TOUCH_FORCE
    else:
        px, py = tr[:, _COL["pLx"]], tr[:, _COL["pLy"]]
        touch = tr[:, _COL["pad_touch"]] > 0
    touch &= tr[:, _COL["kind"]] == kind
    a = np.arctan2(py - cy, px - cx) - theta
    return np.mod(a[touch], 2 * math.pi)


@dataclass
class ExploredOutline:
    """The outline the exploring fingertips touched so far, as sensed (object frame).

    Attributes:
        cells: polar-angle cells over the turn (cell ``k`` spans ``[k, k + 1) 2 pi / cells``).
        seen: (cells,) whether an explorer touched the cell.
        last: ``{kind: (cells,) mask}`` the cells of the last stroke of each explorer (phase
            kind 2: the right tip, 3: the left pad). The overlap rule compares a stroke with
            the previous one of the same finger only: the rotation estimate drifts a few
            degrees over a turn, so the strokes of the other finger, which pass a place half
            a turn earlier or later, are placed too unsurely (on ``ball_with_ridge`` the
            right tip's sensed strokes hid a 2-deg strip the pad then left untouched).
    """

    cells: int = 360
    seen: np.ndarray = field(default=None)  # type: ignore[assignment]
    last: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        checks.integer("cells", self.cells, 8)
        if self.seen is None:
            self.seen = np.zeros(self.cells, dtype=bool)

    def _cell(self, angle) -> np.ndarray:
        k = np.floor(np.mod(angle, 2 * math.pi) / (2 * math.pi) * self.cells).astype(int)
        return np.clip(k, 0, self.cells - 1)

    def observe(self, rows: np.ndarray, kind: int, radius: float) -> None:
        """Marks the cells the explorer of a phase 2/3 touched (``rows`` of its trace,
        ``radius`` [m] the estimate's; :func:`sensed_contact_angles`); a stroke without
        touch leaves that finger's last stroke as it was."""
        if kind not in (2, 3):
            return
        k = self._cell(sensed_contact_angles(rows, kind, radius))
        if k.size:
            self.seen[k] = True
            self.last[kind] = np.zeros(self.cells, dtype=bool)
            self.last[kind][k] = True

    def gap_behind(self, angle: float, direction: float, kind: int = 3) -> float | None:
        """How far [rad] behind ``angle`` (object frame [rad]; behind: against
        ``direction``, +1 = towards larger angles) the last stroke of the explorer of phase
        ``kind`` reached, looking back at most :data:`LOOKBACK`; None when it lies not
        within it (or there was none)."""
        mask = self.last.get(kind)
        if mask is None:
            return None
        step = 2 * math.pi / self.cells
        for i in range(int(math.ceil(LOOKBACK / step)) + 1):
            back = i * step
            if mask[self._cell(angle - direction * back)]:
                return back
        return None

    def back_to(
        self, beta: float, target: float, theta: float, features: tuple = (), kind: int = 3
    ) -> float | None:
        """The overlap rule at a stroke's start: the world polar angle [rad] the stroke first
        goes back to, or None.

        Args:
            beta: the explorer's sensed contact, world polar angle [rad].
            target: the stroke's own target, world polar angle [rad] (gives its direction).
            theta: the rotation estimate [rad] (object angle = world angle - theta).
            features: object-frame angles [rad] of sensed features (no way back near one).
            kind: the phase (2: the right tip explores, 3: the left pad).

        The stroke goes back :data:`OVERLAP` into the previous stroke of the same finger
        when that ended more than :data:`MIN_GAP` (and at most :data:`LOOKBACK`) behind its
        start.
        """
        turn = math.remainder(target - beta, 2 * math.pi)
        if turn == 0.0:
            return None
        direction = math.copysign(1.0, turn)
        here = beta - theta
        gap = self.gap_behind(here, direction, kind)
        if gap is None or gap <= MIN_GAP:
            return None
        back = gap + OVERLAP
        for f in features:
            # the feature's place along the way back (0 = here, back = the turning point)
            along = -direction * math.remainder(f - here, 2 * math.pi)
            if -FEATURE_CLEARANCE < along < back + FEATURE_CLEARANCE:
                return None
        return beta - direction * back


__all__ = ["ExploredOutline", "sensed_contact_angles"]
