"""Tests of the executed grasp gait (planner.exploration.planar) and the ``gait`` kind."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import assume, example, given
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.exploration.planar import GaitSettings, circle_with_ridge, explore_object
from planner.exploration.planar.objects import mean_radius, rest_height
from planner.exploration.planar.outline_segments import PolylinePath
from planner.geometry import shapes


def test_circle_with_ridge_geometry():
    p = circle_with_ridge(0.05, 0.004, 0.003, angle=1.0)
    assert p.closed
    # perimeter: circle minus the base plus the top arc and two sides (~3 mm each)
    assert p.length == pytest.approx(2 * math.pi * 0.05 + 2 * 0.003, abs=2e-4)
    assert rest_height(p) == pytest.approx(0.05, abs=1e-6)
    assert mean_radius(shapes.circle(0.04)) == pytest.approx(0.04, rel=1e-3)
    pts, _ = p.point_at_polar_angle([1.0, 1.0 + math.pi])
    assert np.linalg.norm(pts[0]) == pytest.approx(0.053, abs=1e-6)
    assert np.linalg.norm(pts[1]) == pytest.approx(0.05, abs=1e-6)


def test_bad_inputs_raise():
    with pytest.raises(InvalidParameter, match="mu"):
        explore_object(shapes.circle(0.05), mu=0.0)
    with pytest.raises(InvalidParameter, match="closed"):
        explore_object(shapes.plane())
    with pytest.raises(InvalidParameter, match="nominal: expected a closed"):
        explore_object(shapes.circle(0.05), nominal=shapes.plane())
    with pytest.raises(InvalidParameter, match="nominal"):
        explore_object(shapes.circle(0.05), nominal="square")
    with pytest.raises(InvalidParameter, match="does not fit"):
        explore_object(shapes.circle(0.01), duration=0.1)  # 2 cm across: below the pad


PROGRESS: list[float] = []


@pytest.fixture(scope="module")
def short_run():
    return explore_object(circle_with_ridge(angle=math.radians(170)), duration=0.3, seed=1,
                          on_progress=PROGRESS.append)  # fmt: skip


def test_progress_is_reported_every_tenth_of_a_simulated_second(short_run):
    from planner.exploration.planar.machine import PROGRESS_STEP

    assert len(PROGRESS) >= 2
    assert np.all(np.diff(PROGRESS) >= PROGRESS_STEP - 1e-9)
    assert 0.0 < PROGRESS[-1] <= 0.3 + 1e-9


def test_progress_gaps_are_bounded_by_the_compiled_chunk():
    """The compiled loop reports after each chunk of up to ``CHUNK`` steps: calls are at
    least ``PROGRESS_STEP`` and at most ``PROGRESS_STEP + CHUNK dt`` simulated s apart."""
    from planner.exploration.planar.gait_loop import CHUNK
    from planner.exploration.planar.machine import PROGRESS_STEP

    ticks: list[float] = []
    explore_object(shapes.circle(0.05), duration=2.0, seed=0, on_progress=ticks.append)
    gaps = np.diff([0.0, *ticks])
    assert len(ticks) >= 2.0 / (PROGRESS_STEP + CHUNK * GaitSettings().dt)
    assert np.all(gaps[1:] >= PROGRESS_STEP - 1e-9)
    assert np.all(gaps <= PROGRESS_STEP + CHUNK * GaitSettings().dt + 1e-9)


def test_short_run_grasps_and_rotates_clockwise(short_run):
    res = short_run
    assert res.status == "ok"
    assert res.phases[0].kind == 1
    assert res.phases[0].planned_rotation < 0  # the NLP plans a clockwise rotation
    assert res.rotation < 0  # and the object turns clockwise
    # phase 1 only: the fingertips touch the outline, but none explores it yet
    assert 0 < res.contact_coverage < 1 and res.coverage == 0.0
    tr = res.trace
    late = tr["t"] > 0.15
    # the internal-force servo settles near its command (sensed by the strain gauges)
    assert np.median(np.abs(tr["f_int"][late] - tr["f_des"][late])) < 0.2
    # the sensed rotation (tactile + encoders, eq. 2.4) follows the true one
    assert tr["theta"][-1] == pytest.approx(res.rotation, abs=math.radians(3))


def test_gait_kind_cli_runs_quick(cli, tmp_path):
    out = tmp_path / "run"
    proc = cli("run", "scenarios/ball_with_ridge.yaml", "--quick", "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    doc = json.loads((out / "result.json").read_text())
    assert doc["kind"] == "gait" and doc["status"] == "ok"
    m = doc["metrics"]
    for key in ("phases", "rotation_deg", "coverage", "min_epsilon", "real_time_factor",
                "nlp_solve_median_ms", "internal_force_rms_error_N"):  # fmt: skip
        assert key in m
    for plot in ("snapshots", "forces", "contacts", "timeline"):
        assert (out / "plots" / f"{plot}.png").exists()


def test_gait_kind_bad_input_exits_2(cli, tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("kind: gait\nobject:\n  shape: circle\n  radius: 0.05\nmu: -1\n")
    proc = cli("run", str(bad), "--out", str(tmp_path / "o"))
    assert proc.returncode == 2
    assert "mu" in proc.stderr
    assert not (tmp_path / "o").exists()
    small = tmp_path / "small.yaml"
    small.write_text("kind: gait\nobject:\n  shape: circle\n  radius: 0.01\n")
    proc = cli("validate", str(small))
    assert proc.returncode == 2
    assert "does not fit" in proc.stderr


# --------------------------------------------------------------- regrasp heuristics (§2.2.3)
def _ball_hand():
    from robots.planar_hand import PlanarHand, gait_hand_params

    return PlanarHand(gait_hand_params())


def test_stable_pair_is_the_cone_condition_of_a_circle():
    from planner.exploration.planar.heuristics import stable_pair

    mu, margin = 0.8, 0.1
    # antipodal contacts: the contact line is along both normals (margin atan(mu) - margin)
    assert stable_pair(math.pi, 0.0, mu, margin) == pytest.approx(math.atan(mu) - margin)
    # the contact line makes (pi - separation) / 2 with each normal
    sep = math.radians(120)
    expect = math.atan(mu) - margin - (math.pi - sep) / 2
    assert stable_pair(sep + 0.3, 0.3, mu, margin) == pytest.approx(expect)
    assert stable_pair(0.3, sep + 0.3, mu, margin) == pytest.approx(expect)  # symmetric


def test_regrasp_left_angle_is_stable_and_reachable_through_the_next_rotation():
    from planner.exploration.planar.heuristics import (
        _margin,
        pad_angle,
        regrasp_left_angle,
        stable_pair,
    )

    hand, c, R = _ball_hand(), np.array([0.0, 0.05]), 0.05
    travel = math.radians(22)
    for br_deg in (5.0, 15.0, 24.0):
        br = math.radians(br_deg)
        b = regrasp_left_angle(hand, c, R, br, 0.8, 0.15, travel)
        assert b is not None
        assert stable_pair(b, br, 0.8, 0.15) >= 0
        for bb in (b, b - travel):  # the pad reaches the grasp and the end of the rotation
            n = np.array([math.cos(bb), math.sin(bb)])
            q = hand.inverse_kinematics("left", c + R * n, angle=pad_angle(bb, -2.0))
            assert _margin(hand, "left", q) > 0
    # a right contact so high that no stable left grasp is reachable -> None
    assert regrasp_left_angle(hand, c, R, math.radians(80), 0.8, 0.15, travel) is None


def test_regrasp_orientation_maximizes_the_joint_margin():
    from planner.exploration.planar.heuristics import _reach_margin, regrasp_orientation

    hand, c, R = _ball_hand(), np.array([0.0, 0.05]), 0.05
    r = hand.params.right.tip_radius
    beta, travel = math.radians(24), math.radians(20)
    phi = regrasp_orientation(hand, c, R, beta, travel)
    apex = beta + math.pi / 2
    assert abs(phi - apex) <= 0.5 + 1e-12

    def score(p):
        pts = [c + (R + r) * np.array([math.cos(b), math.sin(b)]) for b in (beta, beta - travel)]
        return min(_reach_margin(hand, "right", x[None], np.array([p]))[0] for x in pts)

    best = score(phi)
    assert best > 0
    for other in apex + np.linspace(-0.5, 0.5, 11):
        assert score(other) <= best + 1e-9


def _posed_runner(hand, W, pose):
    """The slice of the phase machine's runner that ``shape_planning`` reads: the hand and
    a tracker posing the world polygon ``W`` at ``pose``."""
    from types import SimpleNamespace

    outline = SimpleNamespace(posed=lambda p: np.asarray(W, float))
    return SimpleNamespace(hand=hand, shape=SimpleNamespace(pose=np.asarray(pose), outline=outline))


def test_posed_regrasp_orientation_is_the_circle_heuristic_on_a_circle():
    """On a posed outline that is a fine polygon of a circle, the round tip's regrasp
    orientation (shape_planning._regrasp_tip_orientation) is the circle's heuristic
    (heuristics.regrasp_orientation) over the same next phase-1 travel."""
    from planner.exploration.planar import phase_planning, shape_planning
    from planner.exploration.planar.heuristics import regrasp_orientation
    from planner.exploration.planar.segments import MAX_REORIENT

    hand, c, R = _ball_hand(), np.array([0.0, 0.05]), 0.05
    a = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    W = c + R * np.c_[np.cos(a), np.sin(a)]
    runner = _posed_runner(hand, W, [c[0], c[1], 0.0])
    path = PolylinePath(W)  # the posed outline, as plan_explore builds it
    for beta in np.radians([0.0, 24.0, 40.0]):
        want = regrasp_orientation(hand, c, R, beta, phase_planning.PHASE1_TRAVEL)
        q = np.zeros(6)
        q[3] = want  # the tip's orientation now (the sum of its joints) is the answer
        got = shape_planning._regrasp_tip_orientation(runner, path, beta, q)
        assert got == pytest.approx(want, abs=0.02)  # the 61-point grid, 1 deg apart
        q[3] = want - 2.0  # far away: the turn is clipped
        got = shape_planning._regrasp_tip_orientation(runner, path, beta, q)
        assert got == pytest.approx(want - 2.0 + MAX_REORIENT, abs=1e-12)


def test_posed_regrasp_orientation_on_a_square():
    """On a 6 cm square on the palm the regrasp orientation keeps the contact within the
    heuristic's spread (0.5 rad) of the tip's axis. On the top face no orientation of that
    spread has a larger joint-limit margin at the new contact and after the next phase 1;
    on the right face none reaches both, and it is the four-region preference clipped to
    the spread (§2.2.3; the 8 cm rounded square's regrasps left the contact 97-106 deg off
    the axis when the tip kept its orientation)."""
    from planner.exploration.planar import phase_planning, shape_planning
    from planner.exploration.planar.heuristics import _reach_margin, preferred_orientation

    hand = _ball_hand()
    r = hand.params.right.tip_radius
    h = 0.03
    corners = np.array([[-h, 0.0], [h, 0.0], [h, 2 * h], [-h, 2 * h]])  # on the palm, CCW
    t = np.linspace(0, 1, 80, endpoint=False)[:, None]  # dense, as posed outlines are
    ends = np.roll(corners, -1, axis=0)
    W = np.vstack([a + t * (b - a) for a, b in zip(corners, ends, strict=True)])
    c = np.array([0.0, h])
    runner = _posed_runner(hand, W, [0.0, h, 0.0])
    path = PolylinePath(W)  # the posed outline, as plan_explore builds it
    b = -phase_planning.PHASE1_TRAVEL
    turn = np.array([[math.cos(b), -math.sin(b)], [math.sin(b), math.cos(b)]])
    cases = (  # (target polar angle, the tip's centre there, the apex orientation)
        (math.radians(70.0), lambda a: np.array([h / math.tan(a), 2 * h + r]), math.pi),
        (math.radians(10.0), lambda a: np.array([h + r, h + h * math.tan(a)]), 0.5 * math.pi),
    )
    for k, (target, centre_of, apex) in enumerate(cases):
        q = np.array([0.0, 0.0, 0.0, apex, 0.0, 0.0])  # the tip now at the apex
        phi = shape_planning._regrasp_tip_orientation(runner, path, target, q)
        assert abs(phi - apex) <= shape_planning.TIP_SPREAD + 1e-9
        tip = centre_of(target)
        pts = (tip, c + turn @ (tip - c))

        def score(p, pts=pts):
            return min(_reach_margin(hand, "right", x[None], np.array([p]))[0] for x in pts)

        grid = [score(o) for o in apex + np.linspace(-0.5, 0.5, 21)]
        if k == 0:
            assert score(phi) > 0.3
            assert max(grid) <= score(phi) + 1e-9
        else:
            assert not np.isfinite(grid).any()
            pref = preferred_orientation(hand, "right", tip)
            want = apex + float(np.clip(math.remainder(pref - apex, 2 * math.pi), -0.5, 0.5))
            assert phi == pytest.approx(want, abs=1e-12)


@given(st.floats(-math.pi, math.pi), st.floats(-math.pi, math.pi), st.floats(0.1, 2.0))
@example(3.1415926535897927, 5.960464477539063e-08, 1.0)  # antipodal: arccos was 3.5e-9 off
def test_outline_stability_on_a_circle_is_stable_pair(b_left, b_right, mu):
    """On a circle (inward normals = minus the polar directions) the general two-contact
    margin the posed planner's regrasp targets use (planner.grasp.two_contact_stability)
    is the circle's Yoshikawa-Nagai margin of heuristics.stable_pair."""
    from planner.exploration.planar.heuristics import stable_pair
    from planner.grasp import two_contact_stability

    assume(abs(math.remainder(b_left - b_right, 2 * math.pi)) > 1e-3)
    c, R = np.array([0.01, 0.05]), 0.04
    ul = np.array([math.cos(b_left), math.sin(b_left)])
    ur = np.array([math.cos(b_right), math.sin(b_right)])
    want = stable_pair(b_left, b_right, mu, 0.0)
    got = two_contact_stability([c + R * ul, c + R * ur], [-ul, -ur], mu).margin
    assert got == pytest.approx(want, abs=1e-9)


def test_stable_target_moves_a_regrasp_into_the_planning_cones():
    """The explorer's regrasp target stays where the grasp is stable with the NLP's margin
    at the planning friction and otherwise moves, within STABLE_WINDOW, to the nearest
    (1 deg steps) angle where it is. A 6 cm square (half side h) on the palm, the left pad
    at height 0.2 h on the left face, the right tip on the right face at polar angle beta:
    both normals horizontal, the contact line at atan((1 + tan(beta) - 0.2) / 2) from
    them, inside atan(0.8) - 0.15 rad while tan(beta) <= 2 tan(atan(0.8) - 0.15) - 0.8
    (beta <= 19.7 deg)."""
    from types import SimpleNamespace

    from planner.exploration.planar import shape_planning
    from planner.exploration.planar.settings import GaitSettings

    h = 0.03
    corners = np.array([[-h, 0.0], [h, 0.0], [h, 2 * h], [-h, 2 * h]])
    t = np.linspace(0, 1, 240, endpoint=False)[:, None]
    ends = np.roll(corners, -1, axis=0)
    W = np.vstack([a + t * (b - a) for a, b in zip(corners, ends, strict=True)])
    runner = _posed_runner(_ball_hand(), W, [0.0, h, 0.0])
    path = PolylinePath(W)  # the posed outline, as plan_explore builds it
    runner.s = GaitSettings()  # planning mu 0.8, NLP margin 0.15 rad
    est = SimpleNamespace(p=np.array([[-h, 0.2 * h], [h, h]]))
    half = math.atan(runner.s.planning_mu) - runner.s.nlp_margin
    edge = math.atan(2 * math.tan(half) - 0.8)
    assert math.degrees(edge) == pytest.approx(19.68, abs=0.01)
    for target in np.radians([5.0, 15.0]):  # stable: kept
        assert shape_planning._stable_target(runner, path, 2, target, est) == target
    got = shape_planning._stable_target(runner, path, 2, math.radians(26.0), est)
    assert edge - math.radians(1.3) <= got <= edge + math.radians(0.3)
    # beyond the window: the most stable angle in it, the window's end
    got = shape_planning._stable_target(runner, path, 2, math.radians(40.0), est)
    assert got == pytest.approx(math.radians(40.0) - shape_planning.STABLE_WINDOW, abs=1e-9)


def test_prior_grasp_in_world_angles():
    """plan_gait's contact angles are object-frame angles at its start pose; the start grasp
    needs world angles (object angle + rotation of the pose)."""
    from planner.exploration.planar.setup import gait_prior, prior_world_grasp

    prior, error = gait_prior(None, 0.05, _ball_hand(), 1.0)
    assert prior is not None and prior.feasible and error == ""
    ph = prior.phases[0]
    theta = -2 * math.pi * ph.pose_start / prior.resolution
    bl, br = prior_world_grasp(prior)
    assert math.cos(bl - (ph.start["left"] + theta)) == pytest.approx(1.0)
    assert math.cos(br - (ph.start["right"] + theta)) == pytest.approx(1.0)
    assert math.pi / 2 < bl < 3 * math.pi / 2  # left contact on the left half
    assert -math.pi / 2 < br < math.pi / 2


def test_object_rotation_of_a_ball_rolling_on_the_palm():
    """Phases 2/3: a ball rolling on the palm turns by -dx / R; phase-1 rows without the
    fingertips' readings keep the controller's estimate."""
    from planner.exploration.planar.metrics import object_rotation

    R = 0.05
    t = np.linspace(0, 1, 11)
    kind = np.array([1] * 4 + [3] * 7)
    cx = np.r_[np.zeros(4), -R * np.linspace(0, 0.1, 7)]  # rolls left by R * 0.1 rad
    theta = np.r_[np.linspace(0, -0.3, 4), np.full(7, -0.3)]
    th = object_rotation({"t": t, "kind": kind, "cx": cx, "theta": theta}, R)
    np.testing.assert_allclose(th[:4], theta[:4])
    np.testing.assert_allclose(th[4:], -0.3 + np.linspace(0, 0.1, 7))


def test_object_rotation_skips_a_phase_1s_first_centre():
    """Phase 1 is read from its second row: a ball rolling between fixed contacts (pad
    ``u = -R theta``, tip ``s_R = R theta``, eq. 2.4) gives its rotation from there
    exactly, also when the first row's sensed centre is the phase before's, 3 mm off (the
    first row's increment is left out: at a phase's start-up it is 0.004 deg on average)."""
    from planner.exploration.planar.metrics import PHASE1_SKIP, object_rotation

    R, n = 0.05, 12
    theta = np.linspace(0.0, -0.2, n)
    tr = {
        "t": np.linspace(0.0, 0.11, n), "kind": np.ones(n), "theta": np.zeros(n),
        "u": -R * theta, "sR": R * theta, "pad_touch": np.ones(n),
        "pLx": np.full(n, -R), "pLy": np.full(n, R), "nLx": -np.ones(n), "nLy": np.zeros(n),
        "pRx": np.full(n, R), "pRy": np.full(n, R), "cx": np.zeros(n), "cy": np.full(n, R),
    }  # fmt: skip
    assert PHASE1_SKIP == 1
    expected = np.r_[0.0, theta[1:] - theta[1]]
    np.testing.assert_allclose(object_rotation(tr, R), expected, atol=1e-12)
    tr["cx"], tr["cy"] = tr["cx"].copy(), tr["cy"].copy()
    tr["cx"][0], tr["cy"][0] = -2.4e-3, R - 1.8e-3  # the first row: 3 mm off
    th = object_rotation(tr, R)
    np.testing.assert_allclose(th, expected, atol=1e-12)
    # one row's increment is left out, not the centre's error (3 mm / R = 3.4 deg)
    assert abs(th[-1] - (theta[-1] - theta[0])) <= abs(theta[1] - theta[0]) + 1e-12


def test_friction_lead_balances_the_impedance():
    from planner.exploration.planar import GaitSettings
    from planner.exploration.planar.segments import friction_lag

    s = GaitSettings(mu=0.9, explore_force=0.3, tip_kp=150.0)
    # kp * lag = mu * f_n: the tangential spring pulls the Coulomb friction along
    assert s.tip_kp * friction_lag(s) == pytest.approx(s.mu * s.explore_force)


def test_macro_regions_find_a_ridge_seen_twice():
    from planner.exploration.planar.macro import macro_regions

    rng = np.random.default_rng(0)
    a = np.linspace(0.5, 1.5, 400)
    ridge = np.where(np.abs(a - 1.0) < 0.04, 3e-3, 0.0)  # 3 mm high, centred at 1.0 rad
    h = ridge + rng.normal(0, 1e-4, a.size)
    one = macro_regions(a, h, np.zeros(a.size, int))
    assert one == []  # a single pass is not enough
    two = macro_regions(np.r_[a, a], np.r_[h, h], np.r_[np.zeros(400), np.ones(400)].astype(int))
    assert len(two) == 1
    ang, sign = two[0]
    assert sign == 1 and abs(ang - 1.0) < math.radians(0.5)
    groove = macro_regions(np.r_[a, a], -np.r_[h, h], np.r_[np.zeros(400), np.ones(400)])
    assert [s for _, s in groove] == [-1]
    # wraps around +-pi
    w = np.remainder(a + (math.pi - 1.0) + math.pi, 2 * math.pi) - math.pi
    wrapped = macro_regions(np.r_[w, w], np.r_[h, h], np.r_[np.zeros(400), np.ones(400)])
    assert len(wrapped) == 1 and abs(math.remainder(wrapped[0][0] - math.pi, 2 * math.pi)) < 0.01


def test_a_phase_entered_by_transition_4_is_kind_4():
    """The issue's phase kinds 1/2/3/4-skip: a phase 1 entered through transition 4 is
    kind 4 (``skip``), and its ``phase`` is still 1 (both fingers rotate)."""
    from planner.exploration.planar.result import PHASE_KINDS, PhaseRecord

    rec = PhaseRecord(kind=1, skip=True, start=0.0, end=1.0, rotation=-0.2,
                      planned_rotation=-0.3, event="path finished")  # fmt: skip
    assert (rec.kind, rec.phase, rec.skip) == (4, 1, True)
    assert rec.to_json()["kind"] == 4 and rec.to_json()["phase"] == 1
    assert rec.to_json()["name"] == PHASE_KINDS[4]
    four = PhaseRecord(kind=4, skip=False, start=0.0, end=1.0, rotation=0.0,
                       planned_rotation=0.0, event="x")  # fmt: skip
    assert four.skip and four.phase == 1
    for kind in (1, 2, 3):
        plain = PhaseRecord(kind=kind, skip=False, start=0.0, end=1.0, rotation=0.0,
                            planned_rotation=0.0, event="x")  # fmt: skip
        assert (plain.kind, plain.phase, plain.skip) == (kind, kind, False)
    with pytest.raises(ValueError, match="1, 2, 3 or 4"):
        PhaseRecord(kind=5, skip=False, start=0.0, end=1.0, rotation=0.0,
                    planned_rotation=0.0, event="x")  # fmt: skip
    with pytest.raises(ValueError, match="only a phase 1"):
        PhaseRecord(kind=2, skip=True, start=0.0, end=1.0, rotation=0.0,
                    planned_rotation=0.0, event="x")  # fmt: skip


def test_phase_record_names_of_the_issue():
    """The issue's "start/end time" and "end event" of a phase are the record's
    ``start`` / ``end`` / ``event`` under those names too."""
    from planner.exploration.planar.result import PhaseRecord

    rec = PhaseRecord(kind=3, skip=False, start=1.25, end=2.0, rotation=0.1,
                      planned_rotation=0.0, event="workspace limit")  # fmt: skip
    assert (rec.start_time, rec.end_time, rec.end_event) == (1.25, 2.0, "workspace limit")
    assert rec.duration == pytest.approx(0.75)


def test_regrasp_orientation_refuses_a_pad_and_unknown_fingers():
    """The heuristic orients a round tip: the default hand's left pad and a finger name that
    is neither side are bad input, named."""
    from planner.errors import InvalidParameter
    from planner.exploration.planar.heuristics import regrasp_orientation

    hand, c, R = _ball_hand(), np.array([0.0, 0.05]), 0.05
    with pytest.raises(InvalidParameter, match="flat pad"):
        regrasp_orientation(hand, c, R, math.radians(150), math.radians(20), finger="left")
    with pytest.raises(InvalidParameter, match="'left' or 'right'"):
        regrasp_orientation(hand, c, R, math.radians(24), math.radians(20), finger="thumb")
