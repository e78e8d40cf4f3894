"""The overlap rule of the exploring strokes (planar/stroke_overlap.py) on constructed
cases: the sensed explored outline, when a stroke goes back into it, and the stroke."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.exploration.planar.controller import TRACE_NAMES
from planner.exploration.planar.segments import explore_segment
from planner.exploration.planar.stroke_overlap import (
    LOOKBACK,
    MIN_GAP,
    OVERLAP,
    ExploredOutline,
    sensed_contact_angles,
)

R = 0.05
COL = {k: i for i, k in enumerate(TRACE_NAMES)}
DEG = math.pi / 180.0


def _rows(kind: int, world_angles, theta: float, centre=(0.0, R), roll=None) -> np.ndarray:
    """Trace rows of a phase ``kind`` whose explorer touches the circle of radius R about
    ``centre`` at the world polar angles ``world_angles`` [rad], rotation estimate ``theta``;
    ``roll`` (n,) [m]: the centre's x offset per row (the ball rolling on the palm)."""
    a = np.asarray(world_angles, float)
    n = a.size
    tr = np.zeros((n, len(TRACE_NAMES)))
    dx = np.zeros(n) if roll is None else np.asarray(roll, float)
    tr[:, COL["kind"]] = kind
    tr[:, COL["cx"]] = centre[0] + dx
    tr[:, COL["cy"]] = centre[1]
    tr[:, COL["theta"]] = theta
    px, py = tr[:, COL["cx"]] + R * np.cos(a), centre[1] + R * np.sin(a)
    side = ("pLx", "pLy") if kind == 3 else ("pRx", "pRy")
    tr[:, COL[side[0]]], tr[:, COL[side[1]]] = px, py
    tr[:, COL["pad_touch"]] = 1.0 if kind == 3 else 0.0
    tr[:, COL["fnR"]] = 0.3 if kind == 2 else 0.0
    return tr


def test_sensed_angles_are_in_the_object_frame_with_the_roll_on_the_palm():
    """A pad contact fixed in the world while the ball rolls 2 mm along the palm: the object
    frame angle moves by the roll, -dx / R (the executor's phase-3 estimate)."""
    rows = _rows(3, [math.radians(150.0)] * 3, theta=0.2, roll=[0.0, 0.001, 0.002])
    # the contact point is fixed in the world (the rows' centre moved under it)
    rows[:, COL["pLx"]] = rows[0, COL["pLx"]]
    got = sensed_contact_angles(rows, 3, R)
    centre_x = np.array([0.0, 0.001, 0.002])
    px, py = rows[0, COL["pLx"]], rows[0, COL["pLy"]]
    want = np.arctan2(py - R, px - centre_x) - 0.2 + centre_x / R
    assert got == pytest.approx(np.mod(want, 2 * math.pi))


def test_only_the_touching_explorer_rows_count():
    rows = np.vstack([_rows(3, [1.0, 1.1], 0.0), _rows(2, [0.3], 0.0)])
    rows[1, COL["pad_touch"]] = 0.0  # the pad lifted
    assert sensed_contact_angles(rows, 3, R) == pytest.approx([1.0])
    assert sensed_contact_angles(rows, 2, R) == pytest.approx([0.3])
    rows[2, COL["fnR"]] = 0.01  # the right tip below the touch force
    assert sensed_contact_angles(rows, 2, R).size == 0
    assert sensed_contact_angles(np.zeros((0, len(TRACE_NAMES))), 3, R).size == 0


def _explored(lo_deg: float, hi_deg: float, theta: float = 0.0) -> ExploredOutline:
    out = ExploredOutline()
    world = np.radians(np.arange(lo_deg, hi_deg, 0.25)) + theta
    out.observe(_rows(3, world, theta), 3, R)
    return out


def test_observe_marks_the_touched_cells_in_the_object_frame():
    out = _explored(30.0, 58.0, theta=-0.5)  # object frame 30-58 deg
    assert np.flatnonzero(out.seen).tolist() == list(range(30, 58))
    out.observe(_rows(1, [1.0], 0.0), 1, R)  # phase 1 rows: no explorer
    assert out.seen.sum() == 28


def test_a_stroke_past_a_gap_goes_back_into_the_explored_outline():
    """Constructed case (seed 0's 59-65 deg strip): explored up to 58 deg (object frame),
    the pad's next stroke starts at 67 deg towards larger angles; it first goes back to
    ``OVERLAP`` inside the explored outline."""
    theta = math.radians(-280.0)
    out = _explored(30.0, 58.0)
    beta = math.radians(67.0) + theta
    back = out.back_to(beta, beta + 0.3, theta)
    assert back is not None
    # the nearest explored cell is 57 (57-58 deg), found 9-10 cells behind 67.x deg
    gap = math.radians(67.0 - 57.0)
    assert beta - back == pytest.approx(gap + OVERLAP)
    # the stroke going the other way looks the other way: nothing explored ahead of it
    assert out.back_to(math.radians(20.0) + theta, math.radians(10.0) + theta, theta) is not None
    assert out.back_to(math.radians(75.0) + theta, math.radians(65.0) + theta, theta) is None


def test_no_way_back_when_the_strokes_overlap_or_nothing_is_near():
    out = _explored(30.0, 58.0)
    near = math.radians(58.0) + 0.5 * MIN_GAP
    assert out.back_to(near, near + 0.3, 0.0) is None  # within MIN_GAP: they overlap
    far = math.radians(58.0) + LOOKBACK + 2 * DEG
    assert out.back_to(far, far + 0.3, 0.0) is None  # beyond the look-back
    assert ExploredOutline().back_to(1.0, 1.3, 0.0) is None  # nothing explored yet
    assert out.back_to(1.0, 1.0, 0.0) is None  # no stroke


def test_no_way_back_over_a_sensed_feature():
    out = _explored(30.0, 58.0)
    beta = math.radians(67.0)
    assert out.back_to(beta, beta + 0.3, 0.0, features=(math.radians(40.0),)) is None
    assert out.back_to(beta, beta + 0.3, 0.0, features=(math.radians(75.0),)) is None
    assert out.back_to(beta, beta + 0.3, 0.0, features=(math.radians(170.0),)) is not None


@settings(max_examples=60, deadline=None)
@given(
    end=st.floats(0.0, 360.0),
    gap=st.floats(0.0, 20.0),
    theta=st.floats(-7.0, 7.0),
)
@example(end=1.125, gap=4.875, theta=0.0)  # the gap from the last sample, not from end
def test_the_way_back_reaches_the_explored_outline_from_any_gap(end, gap, theta):
    """Invariant: explored ``[end - 20, end)`` deg (object frame), the stroke starting
    ``gap`` deg past ``end``: it goes back iff the gap (in whole cells) exceeds MIN_GAP and
    is within LOOKBACK, and then turns inside the explored outline, OVERLAP past its end.
    The gap found is the one from the last touched sample (0.25 deg apart, so up to
    0.25 deg short of ``end``), in whole cells: within one cell of it (Hypothesis found
    end = 1.125, gap = 4.875: the last sample at 0.875 deg, the gap 5.125 deg, found 6)."""
    out = _explored(end - 20.0, end, theta)
    last = float(np.arange(end - 20.0, end, 0.25)[-1])  # the last touched sample [deg]
    here = math.radians(end + gap)
    back = out.back_to(here + theta, here + theta + 0.3, theta)
    found = out.gap_behind(here, 1.0)
    assert found is None or found <= LOOKBACK + 1e-12
    if found is None or found <= MIN_GAP:
        assert back is None
        return
    assert back is not None
    turn = math.degrees(math.remainder(back - theta, 2 * math.pi)) % 360.0
    k = int(math.floor(turn + 1e-9)) % 360
    assert out.seen[k]  # the turning point lies on the explored outline
    true_gap = math.radians(end + gap - last)
    assert true_gap - DEG - 1e-9 <= found <= true_gap + DEG + 1e-9


def test_the_outline_validates_its_cells():
    with pytest.raises(InvalidParameter, match="cells"):
        ExploredOutline(cells=2)


def _est(beta_left: float, beta_right: float = 0.3):
    c = np.array([0.0, R])
    p = c + R * np.array([[math.cos(beta_left), math.sin(beta_left)],
                          [math.cos(beta_right), math.sin(beta_right)]])  # fmt: skip
    return SimpleNamespace(centre=c, p=p, beta=np.array([beta_left, beta_right]),
                           normal_force=np.array([0.6, 0.4]), u=0.0, tips=p.copy(),
                           n=(p - c) / R)  # fmt: skip


def test_the_overlap_stroke_goes_back_centred_and_ends_at_the_target():
    """The overlap stroke (``via`` with ``edge=False``): from 150 deg back to 140 deg and on
    to 170 deg (world), quintic pieces at rest at their ends; at the turn the contact is on
    the circle at the via angle with the pad centred on it (no trail), then at the target."""
    from planner.exploration.planar.settings import GaitSettings
    from robots.planar_hand import PlanarHand

    s, hand = GaitSettings(), PlanarHand()
    b0, via, target = math.radians(150.0), math.radians(140.0), math.radians(170.0)
    seg = explore_segment(3, _est(b0), np.full(6, 0.2), target, 0.1, s, hand, via=via, edge=False)
    T1 = (b0 - via) * R / s.explore_speed
    T2 = (target - via) * R / s.explore_speed
    assert seg.kind == 3 and seg.duration == pytest.approx(s.startup_time + T1 + T2 + 0.02)
    c = np.array([0.0, R])
    (px, py), (vx, vy), phi = seg.explore(s.startup_time + T1)
    assert np.hypot(vx, vy) < 1e-12
    assert np.array([px, py]) - c == pytest.approx(R * np.array([math.cos(via), math.sin(via)]))
    assert math.remainder(phi - via - math.pi / 2, 2 * math.pi) == pytest.approx(0.0, abs=1e-12)
    turn = np.array([px, py])
    (px, py), _, _ = seg.explore(seg.duration)
    assert math.atan2(py - R, px) == pytest.approx(target)
    # the edge-led back-stroke differs only by its trail at the turn
    edge = explore_segment(3, _est(b0), np.full(6, 0.2), target, 0.1, s, hand, via=via)
    (qx, qy), _, _ = edge.explore(s.startup_time + T1)
    assert math.hypot(qx - turn[0], qy - turn[1]) == pytest.approx(
        hand.params.left.pad_half_width - 1.5e-3
    )


def test_only_the_same_fingers_previous_stroke_counts():
    """The right tip's stroke over the strip behind the pad does not stop the pad's way
    back (the estimate drifts between the fingers' passes); the pad's newer stroke
    replaces its older one, and a phase without touch keeps it."""
    out = _explored(30.0, 58.0)
    out.observe(_rows(2, np.radians(np.arange(55.0, 70.0, 0.25)), 0.0), 2, R)
    beta = math.radians(67.0)
    assert out.seen[60] and out.back_to(beta, beta + 0.3, 0.0) is not None
    assert out.back_to(beta, beta + 0.3, 0.0, kind=2) is None  # the right tip is there
    out.observe(_rows(3, np.radians(np.arange(100.0, 120.0, 0.25)), 0.0), 3, R)
    assert out.back_to(beta, beta + 0.3, 0.0) is None  # the pad's last stroke is elsewhere
    lifted = _rows(3, [1.0], 0.0)
    lifted[:, COL["pad_touch"]] = 0.0
    out.observe(lifted, 3, R)
    assert np.flatnonzero(out.last[3]).tolist() == list(range(100, 120))


# ------------------------------------------------------- the end-first approach to a wall
def test_a_known_wall_ahead_of_the_stroke_is_approached():
    """The wall (object 167 deg, met moving towards larger angles) lies ahead of a stroke
    from 150 to 160 deg (object) within the stroke plus APPROACH_REACH; not behind it, not
    beyond the reach, not for a stroke the other way."""
    from planner.exploration.planar.corner_probe import APPROACH_REACH, wall_ahead

    walls = [(math.radians(167.0), 1.0)]
    theta = -2.0
    b = math.radians(150.0) + theta
    assert wall_ahead(walls, theta, b, b + math.radians(10.0)) == pytest.approx(walls[0][0])
    assert wall_ahead(walls, theta, b + math.radians(20.0), b + math.radians(30.0)) is None
    short = math.radians(17.0) - APPROACH_REACH - math.radians(1.0)
    assert wall_ahead(walls, theta, b, b + short) is None
    assert wall_ahead(walls, theta, b, b - math.radians(10.0)) is None
    assert wall_ahead([], theta, b, b + 0.2) is None


def test_the_approach_leads_with_the_pad_end_and_servoes_the_contact_there():
    """The approach: the contact from 150 to 160 deg (world) on the circle with the pad's
    centre trailing it by the pad's half-width less EDGE_MARGIN once the startup is over,
    the tactile servo's target PROBE_EDGE behind the leading end; the plain stroke has no
    trail (the friction lead only), and both tables equal their callables."""
    from planner.exploration.planar.corner_probe import PROBE_EDGE, approach_segment
    from planner.exploration.planar.phase_segment import references
    from planner.exploration.planar.segments import EDGE_MARGIN, friction_lag, segment_references
    from planner.exploration.planar.settings import GaitSettings
    from robots.planar_hand import PlanarHand

    s, hand = GaitSettings(), PlanarHand()
    w_pad = hand.params.left.pad_half_width
    b0, target = math.radians(150.0), math.radians(160.0)
    seg = approach_segment(_est(b0), np.full(6, 0.2), target, 0.1, s, hand)
    plain = explore_segment(3, _est(b0), np.full(6, 0.2), target, 0.1, s, hand)
    assert seg.contact_target == pytest.approx(w_pad - PROBE_EDGE)
    assert plain.contact_target is None and seg.duration == pytest.approx(plain.duration)
    t = 0.5 * plain.duration
    (px, py), _, _ = seg.explore(t)
    (qx, qy), _, _ = plain.explore(t)
    diff = np.array([px - qx, py - qy])  # both references share the contact angle
    assert np.hypot(*diff) == pytest.approx(w_pad - EDGE_MARGIN)
    b = math.atan2(qy - R, qx)
    assert diff @ np.array([-math.sin(b), math.cos(b)]) < -0.99 * (w_pad - EDGE_MARGIN)
    assert np.hypot(qx, qy - R) == pytest.approx(math.hypot(R, friction_lag(s)))
    tl = np.linspace(0.0, seg.duration + 0.1, 201)
    rows = np.array([[seg.hold_force(x), *references(seg, x)] for x in tl])
    np.testing.assert_allclose(segment_references(seg, tl), rows, rtol=0, atol=1e-15)


@settings(max_examples=60, deadline=None)
@given(
    past=st.floats(-20.0, 20.0),
    theta=st.floats(-7.0, 7.0),
    wall=st.floats(0.0, 360.0),
    direction=st.sampled_from([-1.0, 1.0]),
)
@example(past=3.0, theta=-2.0, wall=167.7, direction=1.0)  # seed 1's sweep (3 deg)
@example(past=6.2, theta=-2.0, wall=167.7, direction=1.0)  # seed 0's: capped at TOP_SWEEP
def test_the_tip_sweeps_back_over_the_top_towards_the_wall_at_most_top_sweep(
    past, theta, wall, direction
):
    """The round tip ``past`` deg beyond a known wall (along the pad's motion there) with a
    stroke running that way first goes back by ``min(past, TOP_SWEEP)``: to the wall when
    within TOP_SWEEP, never beyond it; before the wall, farther than TOP_REACH, or with a
    stroke the other way, no sweep."""
    from planner.exploration.planar.corner_probe import TOP_REACH, TOP_SWEEP, top_sweep_back

    # (the angles are rounded when composed: no verdict within 1e-6 deg of a bound)
    assume(min(abs(past), abs(past - math.degrees(TOP_REACH))) > 1e-6)
    walls = [(math.radians(wall), direction)]
    beta = math.radians(wall + direction * past) + theta
    ahead = beta + direction * 0.3
    back = top_sweep_back(walls, theta, beta, ahead)
    p = math.radians(past)
    if 0.0 < p <= TOP_REACH:
        went = direction * math.remainder(beta - back, 2 * math.pi)
        assert went == pytest.approx(min(p, TOP_SWEEP), abs=1e-9)
        left = direction * math.remainder(back - theta - math.radians(wall), 2 * math.pi)
        assert left >= -1e-9  # still on the wall's far side (or at it)
    else:
        assert back is None
    assert top_sweep_back(walls, theta, beta, beta - direction * 0.3) is None
    assert top_sweep_back([], theta, beta, ahead) is None


def test_the_round_tip_sweep_goes_back_and_ends_at_the_target():
    """Phase 2 with ``via``: the right tip's contact from 40 deg back to 37 deg (at rest
    there) and on to 60 deg (world) on the circle; without ``via`` the same stroke runs
    straight, and the pad's trail never applies to the round tip."""
    from planner.exploration.planar.settings import GaitSettings
    from robots.planar_hand import PlanarHand

    s, hand = GaitSettings(), PlanarHand()
    b0, via, target = math.radians(40.0), math.radians(37.0), math.radians(60.0)
    est = _est(math.radians(150.0), b0)
    seg = explore_segment(2, est, np.full(6, 0.2), target, 0.1, s, hand, via=via)
    T1 = (b0 - via) * R / s.explore_speed
    T2 = (target - via) * R / s.explore_speed
    assert seg.kind == 2 and seg.duration == pytest.approx(s.startup_time + T1 + T2 + 0.02)
    (px, py), (vx, vy), _ = seg.explore(s.startup_time + T1)
    assert np.hypot(vx, vy) < 1e-12
    assert math.atan2(py - R, px) == pytest.approx(via, abs=1e-9)
    assert math.hypot(px, py - R) == pytest.approx(R)  # no trail, no friction lead at rest
    (px, py), _, _ = seg.explore(seg.duration)
    assert math.atan2(py - R, px) == pytest.approx(target)
    plain = explore_segment(2, est, np.full(6, 0.2), target, 0.1, s, hand)
    assert plain.duration == pytest.approx(s.startup_time + (target - b0) * R / s.explore_speed
                                           + 0.02)  # fmt: skip
