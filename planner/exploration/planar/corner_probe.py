"""The corner probe: the flat pad into the concave corner on the far side of a ridge.

Both fingertips move over the ball towards larger object angles (the pad in phase 3, the
round tip in phase 2), so both meet a ridge's near wall first and jump its far wall: the
corner there lies in their shadow (:func:`.metrics.round_tip_shadow`: 10.8 deg for the
25 mm tip beside the 3 mm ridge of the 10 cm ball; :func:`.metrics.pad_shadow`: 11.3 deg
for the pad touching with its middle). A pad lying on the circle with its contact ``d``
behind its leading end reaches ``atan(d / R)`` from the wall (``pad_shadow(R, h, d)``).

The reach is bounded by two things measured on ``ball_with_ridge``:

* the pad's orientation: commanded tangent with its contact 1.5 mm from the end, the
  contact sat 5 mm from it (the pad turned 3-4 deg by its contact moment and damping):
  the probe servoes the tactile centroid instead (``Segment.contact_target``, the
  controller kernel's contact servo);
* the pad's end must not go down onto the object: a pad pivoting on its end in the corner
  has the ridge's top corner behind its face (a fingertip's body; the simulator lifted
  the pad onto the ridge in one step). So the contact stays :data:`PROBE_EDGE` behind the
  end, where the tactile centroid still sees it (nearer, the image is clipped at the
  pad's end and the centroid saturates): 2.5 mm, i.e. 2.9 deg from a wall of the 10 cm
  ball, and the orientation follows the pad's own place, not its reference (which runs on
  when a wall stops the pad), with the push on the wall bounded (``tip_kp`` times 2.5 mm).

A probe is one phase 3 that first sends the pad back to a wall its leading end stalled at
in an earlier phase 3 (:func:`wall_stall`: object frame, from the sensed contact, the
encoders and the tactile centroid, no truth) and then on to its own target, when the pad
lies past that wall by :data:`MIN_BEYOND` .. :data:`MAX_BEYOND` (it jumped the ridge).
It aims at that NEAR wall, so the ridge's far wall stops the pad whatever the ridge's
width. Its rows are left out of the feature detection (the executor marks it as a
back-stroke).

The recorded walls serve two more strokes: a phase 3 running towards one leads with the
pad's end (:func:`approach_segment`), and a phase 2 whose round tip starts on a ridge's
top, just past one, first sweeps back over the top towards it (:func:`top_sweep_back`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from planner.exploration.planar.controller import TRACE_NAMES
from planner.exploration.planar.phase_segment import Segment
from planner.exploration.planar.segments import explore_segment
from planner.exploration.planar.sensed_features import pad_end_contact

#: the probe holds its contact this far behind the pad's leading end [m]: one taxel pitch
#: inside the outer column's centre, where the tactile centroid is unbiased (a 0.3 N
#: patch on the 10 cm ball has a 2.2 mm radius)
PROBE_EDGE = 2.5e-3
#: a wall stall: at least this many consecutive trace rows (0.05 s at 500 Hz) with the
#: leading end on the object (tactile centroid in the outer taxel column) ...
STALL_ROWS = 25
#: ... whose end angles (10-90 percentiles) lie within this spread [rad] (the pad sliding on
#: its end moves on; a stalled end lifts onto the wall's top at the last rows)
STALL_SPREAD = math.radians(2.0)
#: a probe follows when the pass ended at least this far past the wall [rad] (the pad
#: jumped the ridge: on ball_with_ridge it landed 26-28 deg past the near wall) ...
MIN_BEYOND = math.radians(8.0)
#: ... and at most this far (the left finger's reach back: the phase-3 strokes span 25-30
#: deg of world angle)
MAX_BEYOND = math.radians(45.0)
#: ... and the pad then jumped: at least this many untouched rows right after the stall
#: (the pad flew over the ridge for 0.06-0.08 s; a pad stalling without jumping did not
#: get past anything, and on smooth objects nothing is probed)
JUMP_ROWS = 5
#: a phase 3 approaches a known wall with its leading end when the wall lies within its
#: stroke plus this [rad] (the pad's end reaches the pad's half-length, 11.3 deg on the
#: 10 cm ball, ahead of its contact)
APPROACH_REACH = math.radians(12.0)
#: walls closer than this are one (object frame) [rad]
SAME_WALL = math.radians(10.0)
#: a phase 2 whose round tip starts at most this far past a known wall (along the pad's
#: motion there) first sweeps back towards the wall (:func:`top_sweep_back`) [rad]: the tip
#: sits on the ridge's top (4.6 deg wide on ball_with_ridge) or just past its far wall; the
#: pad landed at least :data:`MIN_BEYOND` past a wall it jumped
TOP_REACH = math.radians(8.0)
#: ... but at most this far back [rad]. The sensed angles are a few degrees off (the
#: rotation estimate and the pad's end): on seed 0 a sweep to the sensed wall (6.2 deg)
#: went 3 deg past the true one, the tip pivoted down the wall's far side and the right
#: finger's base joint reached its stop; the gait then lost the ball's rotation (coverage
#: 0.68). 4 deg swept 167.7-170.7 deg on seeds 0, 1 and 3 and ended no phase early.
TOP_SWEEP = math.radians(4.0)

_COL = {k: i for i, k in enumerate(TRACE_NAMES)}


def _phase_rows(rows: np.ndarray, radius: float, pad_half_width: float, columns: int):
    """Touching rows of a phase 3 with their object-frame angles [rad]: ``(index,
    contact angle, end angle)``; the rotation per row is the phase's estimate minus the
    centre's roll on the palm (``-(c_x - c_x0) / R``, as the executor integrates it)."""
    tr = np.asarray(rows, dtype=float)
    theta = tr[:, _COL["theta"]] - (tr[:, _COL["cx"]] - tr[0, _COL["cx"]]) / radius
    touch = np.flatnonzero((tr[:, _COL["kind"]] == 3) & (tr[:, _COL["pad_touch"]] > 0))
    cx, cy = tr[:, _COL["cx"]], tr[:, _COL["cy"]]
    cols = {k: tr[:, _COL[k]] for k in ("u", "pLx", "pLy", "nLx", "nLy")}
    ex, ey = pad_end_contact(cols, columns, pad_half_width)
    a = np.unwrap(np.arctan2(tr[:, _COL["pLy"]] - cy, tr[:, _COL["pLx"]] - cx) - theta)
    e = np.unwrap(np.arctan2(ey - cy, ex - cx) - theta)
    return touch, a, e


def wall_stall(rows: np.ndarray, radius: float, pad_half_width: float, columns: int = 8):
    """Where the pad's leading end stalled at a wall in one phase 3.

    Args:
        rows: (N, len(TRACE_NAMES)) the controller's trace rows of the phase.
        radius: the estimate's radius [m]; pad_half_width: half the pad's length [m];
            columns: taxel columns across the pad.

    Returns:
        ``(wall, direction)``: the wall's object-frame polar angle [rad] (the median of the
        pad's end over the longest stall) and the pad's motion (+1: towards larger polar
        angles); None without a stall.

    A stall is :data:`STALL_ROWS` consecutive touching rows with the tactile centroid in
    the outer column on the leading side (:func:`.sensed_features.pad_end_contact` moves
    it to the pad's end) whose end angles stay within :data:`STALL_SPREAD` (10-90
    percentiles), followed by :data:`JUMP_ROWS` rows without touch (the pad jumped).
    """
    tr = np.asarray(rows, dtype=float)
    if tr.ndim != 2 or len(tr) < STALL_ROWS:
        return None
    touch, a, e = _phase_rows(tr, radius, pad_half_width, columns)
    if touch.size < STALL_ROWS:
        return None
    direction = 1.0 if a[touch[-1]] >= a[touch[0]] else -1.0
    pitch = 2.0 * pad_half_width / columns
    lead = np.zeros(len(tr), dtype=bool)
    lead[touch] = direction * tr[touch, _COL["u"]] > pad_half_width - pitch
    idx = np.flatnonzero(lead)
    best = None
    for run in np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1):
        if run.size < STALL_ROWS:
            continue
        lo, hi = np.percentile(e[run], (10.0, 90.0))
        after = tr[run[-1] + 1 : run[-1] + 1 + JUMP_ROWS, _COL["pad_touch"]]
        jumped = after.size == JUMP_ROWS and not np.any(after > 0)
        if jumped and hi - lo <= STALL_SPREAD and (best is None or run.size > best.size):
            best = run
    if best is None:
        return None
    return math.remainder(float(np.median(e[best])), 2 * math.pi), direction


def jumped_walls(trace: dict, theta, radius: float, pad_half_width: float, columns: int = 8):
    """The walls the exploring pad's end stalled at and then jumped, over a whole trace:
    object-frame polar angles [rad], one per phase 3 at most.

    Args:
        trace: the controller's sensed series (:data:`TRACE_NAMES` columns; rows of kind 0
            are left out, e.g. phases whose held object moved).
        theta: (N,) the sensed object rotation per row [rad] (the mapping estimate,
            :func:`.metrics.object_rotation`); each phase 3 starts from its value at the
            phase's first row, and :func:`wall_stall` adds the roll of the trace's centre
            on the palm.
        radius: the estimate's radius [m]; pad_half_width: half the pad's length [m];
            columns: taxel columns across the pad.

    A phase 3 counts when :func:`wall_stall` finds a stall followed by a jump AND the pad
    touches again at least :data:`MIN_BEYOND` past the wall along its motion: it got past
    something that stands out of the surface. A pad stalling at its stroke's end and
    lifting off (the phase's end) lands nowhere; on a smooth outline the sliding pad's
    contact moves on without gaps.
    """
    from planner.exploration.planar.pad_trace import phase_runs

    kind = np.asarray(trace["kind"])
    theta = np.asarray(theta, float)
    if kind.size == 0:
        return []
    table = np.column_stack([np.asarray(trace[k], float) for k in TRACE_NAMES])
    out = []
    for run in phase_runs(kind):
        if kind[run[0]] != 3 or run.size < STALL_ROWS:
            continue
        rows = table[run].copy()
        rows[:, _COL["theta"]] = theta[run[0]]  # wall_stall adds the palm roll itself
        found = wall_stall(rows, radius, pad_half_width, columns)
        if found is None:
            continue
        wall, direction = found
        touch, a, _ = _phase_rows(rows, radius, pad_half_width, columns)
        past = direction * (np.remainder(a[touch] - wall + math.pi, 2 * math.pi) - math.pi)
        if np.any(past >= MIN_BEYOND):
            out.append(wall)
    return out


@dataclass
class CornerProbe:
    """The executor's memory of the walls the pad's end stalled at, and which it probed.

    Attributes:
        pad_half_width: half the pad's length [m]; columns: taxel columns across it.
        walls: ``(object-frame polar angle [rad], motion sign)`` of each wall, first sighting
            (the rotation estimate drifts over a turn: the first one is the best).
        probed: the walls (angles [rad]) probed already: one probe each.
    """

    pad_half_width: float
    columns: int = 8
    walls: list = field(default_factory=list)
    probed: list = field(default_factory=list)

    def observe(self, rows: np.ndarray, radius: float) -> None:
        """Records the wall the pad's end stalled at in a phase 3 (``rows`` of its trace,
        ``radius`` [m] the estimate's), if any (:func:`wall_stall`)."""
        found = wall_stall(rows, radius, self.pad_half_width, self.columns)
        if found is not None and not _near(found[0], [w for w, _ in self.walls]):
            self.walls.append(found)

    def aim(self, theta: float, beta: float) -> float | None:
        """At a phase-3 start, the world polar angle [rad] a probe aims the pad's end at (a
        recorded wall), or None: the pad's contact (world polar angle ``beta`` [rad],
        ``theta`` [rad] the rotation estimate) is past no unprobed wall by
        :data:`MIN_BEYOND` .. :data:`MAX_BEYOND` along the pad's motion at that wall."""
        for wall, direction in self.walls:
            beyond = direction * math.remainder(beta - theta - wall, 2 * math.pi)
            if MIN_BEYOND <= beyond <= MAX_BEYOND and not _near(wall, self.probed):
                self.probed.append(wall)
                return math.remainder(wall + theta, 2 * math.pi)
        return None


def wall_ahead(walls: list, theta: float, beta: float, target: float) -> float | None:
    """The object-frame angle [rad] of a recorded wall (``walls`` of :class:`CornerProbe`)
    that a phase-3 stroke from the pad's contact ``beta`` to ``target`` (world polar angles
    [rad]; ``theta`` the rotation estimate [rad]) runs towards, its motion the pad's motion
    when it stalled there, the wall within the stroke plus :data:`APPROACH_REACH`; or None."""
    turn = math.remainder(target - beta, 2 * math.pi)
    for wall, direction in walls:
        if turn * direction <= 0.0:
            continue
        ahead = direction * math.remainder(wall + theta - beta, 2 * math.pi)
        if 0.0 < ahead <= abs(turn) + APPROACH_REACH:
            return wall
    return None


def top_sweep_back(walls: list, theta: float, beta: float, target: float) -> float | None:
    """The world polar angle [rad] a phase 2's round tip first goes back to, or None.

    Phase 1 rolls the right tip onto the outline (those contacts do not count as explored:
    the tip explores in phase 2 only), so a phase 2 that starts with the tip on a ridge's
    top leaves the top between the near wall and its start untouched by an explorer
    (``ball_with_ridge`` seeds 0-3: 168-169 deg, the ridge 167.7-172.3 deg). When the tip's
    contact ``beta`` lies past a recorded wall (``walls`` of :class:`CornerProbe`; ``theta``
    the rotation estimate [rad]) by at most :data:`TOP_REACH` along the pad's motion there,
    and the stroke to ``target`` runs that way too, the stroke first sweeps back to the
    wall, at most :data:`TOP_SWEEP`: a round tip moving over a convex top touches it where
    its centre's polar angle is, up to the top's corner.
    """
    turn = math.remainder(target - beta, 2 * math.pi)
    for wall, direction in walls:
        if turn * direction <= 0.0:
            continue
        past = direction * math.remainder(beta - theta - wall, 2 * math.pi)
        if 0.0 < past <= TOP_REACH:
            return math.remainder(beta - direction * min(past, TOP_SWEEP), 2 * math.pi)
    return None


def approach_segment(est, q, target: float, theta0: float, settings, hand) -> Segment:
    """A phase 3 towards a known wall (:func:`wall_ahead`) with the pad's leading end
    first: its centre trails the contact and the tactile servo holds the contact
    :data:`PROBE_EDGE` behind the leading end, so that the contact gets within ``atan(
    PROBE_EDGE / R)`` (2.9 deg on the 10 cm ball) of the NEAR wall instead of the pad's
    half-length (11.3 deg) when it touches with its middle.

    Args:
        est: the sensed grasp now; q: joint angles [rad]; target: the phase's target (world
            polar angle [rad]); theta0: the rotation estimate [rad]; settings:
            :class:`.settings.GaitSettings`; hand: the ``PlanarHand``.
    """
    seg = explore_segment(3, est, q, target, theta0, settings, hand, lead_end=True)
    lead = 1.0 if math.remainder(target - float(est.beta[0]), 2 * math.pi) > 0 else -1.0
    seg.contact_target = lead * (hand.params.left.pad_half_width - PROBE_EDGE)
    return seg


def _near(angle: float, angles: list) -> bool:
    """Whether ``angle`` lies within :data:`SAME_WALL` of one of ``angles`` [rad]."""
    return any(abs(math.remainder(angle - a, 2 * math.pi)) < SAME_WALL for a in angles)


def probe_segment(est, q, aim: float, target: float, theta0: float, settings, hand) -> Segment:
    """The probe: a phase 3 whose pad goes from where it is to ``aim`` with its leading
    end and on to ``target`` (world polar angles [rad]; the target is the phase's own,
    the pad's next grasp): :func:`.segments.explore_segment` through ``via=aim`` (the
    pad on the estimated circle, its centre trailing its contact) with its contact held
    :data:`PROBE_EDGE` behind the leading end by the tactile servo
    (``Segment.contact_target``), so that the end meets the far wall first.

    Args:
        est: the sensed grasp now; q: joint angles [rad]; aim, target: see above; theta0:
            the rotation estimate [rad]; settings: :class:`.settings.GaitSettings`; hand:
            the ``PlanarHand``.
    """
    seg = explore_segment(3, est, q, target, theta0, settings, hand, via=aim)
    lead = -1.0 if math.remainder(aim - float(est.beta[0]), 2 * math.pi) < 0 else 1.0
    seg.contact_target = lead * (hand.params.left.pad_half_width - PROBE_EDGE)
    return seg


__all__ = [
    "CornerProbe",
    "approach_segment",
    "jumped_walls",
    "probe_segment",
    "top_sweep_back",
    "wall_ahead",
    "wall_stall",
]
