"""The pivot of a polygon about its palm corner and the fingers' reach along it
(planner/exploration/planar/pivot_reach.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.exploration.planar import pivot_reach as pr
from planner.exploration.planar.pivot_grasps import pivot_grasps
from robots.planar_hand import PlanarHand, gait_hand_params

A = 0.055  # half-width of the 11 cm square [m]
SQUARE = np.array([[-A, 0.0], [A, 0.0], [A, 2 * A], [-A, 2 * A]])  # resting on the palm
R_TIP = 0.025


def scenario_hand() -> PlanarHand:
    """The square_gait hand (the gait's hand: right finger's ranges, the left one mirrors)."""
    return PlanarHand(gait_hand_params(1.0))


HAND = scenario_hand()


def test_palm_corner_is_the_lowest_rightmost_vertex():
    assert np.allclose(pr.palm_corner(SQUARE), [A, 0.0])
    tilted = pr.pivoted(SQUARE, [A, 0.0], -0.3)  # standing on its corner
    assert np.allclose(pr.palm_corner(tilted), [A, 0.0])
    # a posed face tilted 1.4 deg either way still pivots about its right end
    for a in (-0.025, 0.025):
        assert np.allclose(pr.palm_corner(pr.pivoted(SQUARE, [0.0, 0.0], a)),
                           pr.pivoted(SQUARE[1], [0.0, 0.0], a))  # fmt: skip
    with pytest.raises(InvalidParameter):
        pr.palm_corner(np.zeros((2, 2)))


def test_palm_corner_and_sharpness_of_sampled_outlines():
    """The executor's outlines are sampled every millimetre: the corner is still the
    vertex, and only a sharp one is a pivot (a rounded corner rolls)."""
    from planner.exploration.planar.outline_pose import Outline
    from planner.geometry import shapes

    sharp = Outline.from_profile(shapes.rounded_rectangle(0.11, 0.11, 0.0)).posed((0, A, 0))
    k = pr.palm_corner(sharp)
    assert np.allclose(k, [A, 0.0], atol=1e-12) and pr.is_sharp(sharp, k)
    standing = pr.pivoted(sharp, k, -0.3)
    assert np.allclose(pr.palm_corner(standing), k) and pr.is_sharp(standing, k)
    for rho in (0.01, 0.022):
        W = Outline.from_profile(shapes.rounded_rectangle(0.11, 0.11, rho)).posed((0, A, 0))
        assert not pr.is_sharp(W, pr.palm_corner(W))


@settings(max_examples=40, deadline=None)
@given(
    st.floats(-0.1, 0.1), st.floats(0.0, 0.1), st.floats(-math.pi, math.pi),
)  # fmt: skip
def test_a_pivoted_point_moves_on_a_circle_about_the_corner(x, y, theta):
    """``k + R(theta)(p - k)``: the distance to the corner is kept and the polar angle
    about it advances by ``theta``."""
    k = np.array([A, 0.0])
    p = np.array([x, y])
    q = pr.pivoted(p, k, theta)
    assert np.linalg.norm(q - k) == pytest.approx(np.linalg.norm(p - k), abs=1e-12)
    if np.linalg.norm(p - k) > 1e-6:
        a0 = math.atan2(*(p - k)[::-1])
        a1 = math.atan2(*(q - k)[::-1])
        assert math.remainder(a1 - a0 - theta, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)


@settings(max_examples=40, deadline=None)
@given(st.floats(0.0, 0.11), st.floats(-1.2, 0.2))
def test_the_tip_centre_is_r_off_the_turned_face(d, theta):
    """The round tip touching the right face at ``d`` sits ``r`` outside the turned face,
    opposite the contact point ``k + R(theta)(start + d e - k)``."""
    k = np.array([A, 0.0])
    face = pr.Face.between(SQUARE[1], SQUARE[2], SQUARE.mean(axis=0))
    assert np.allclose(face.normal, [1.0, 0.0]) and np.allclose(face.tangent, [0.0, 1.0])
    T = face.tip_centre(k, theta, d, R_TIP)
    contact = pr.pivoted(face.start + d * face.tangent, k, theta)
    m = pr.rotation(theta) @ face.normal
    assert np.allclose(T, contact + R_TIP * m, atol=1e-12)
    # the contact is on the turned face's line through the corner
    assert abs(float((contact - k) @ m)) < 1e-12


def test_face_between_orients_the_normal_outward():
    c = SQUARE.mean(axis=0)
    for i in range(4):
        f = pr.Face.between(SQUARE[i], SQUARE[(i + 1) % 4], c)
        mid = 0.5 * (SQUARE[i] + SQUARE[(i + 1) % 4])
        assert float((mid - c) @ f.normal) > 0
        assert f.length == pytest.approx(2 * A)
        # ``start + length * e`` is the other end
        end = f.start + f.length * f.tangent
        ends = SQUARE[[i, (i + 1) % 4]]
        assert np.linalg.norm(ends - end, axis=1).min() < 1e-12


def test_rolling_path_obeys_pure_rolling_and_the_kinematics():
    """Along the path: ``d - d0 = r (psi - psi0)`` with ``psi = phi - theta`` (the disc rolls
    on the face), forward kinematics of ``q`` puts the tip centre on the turned face's
    offset at ``d`` with orientation ``phi``, every joint ``JOINT_MARGIN`` inside."""
    face = pr.Face.between(SQUARE[1], SQUARE[2], SQUARE.mean(axis=0))
    path = pr.tip_rolling_path(HAND, SQUARE, face, 0.04, math.radians(200.0))
    assert path.reach > math.radians(10.0)
    psi = path.phi - path.theta
    assert np.allclose(path.d - path.d[0], R_TIP * (psi - psi[0]), atol=1e-12)
    lim = HAND.finger_limits("right")
    k = pr.palm_corner(SQUARE)
    for th, d, phi, q in zip(path.theta, path.d, path.phi, path.q, strict=True):
        full = np.r_[HAND.neutral()[:3], q]
        pose = HAND.fingertip_pose(full, "right")
        assert np.allclose(pose.position, face.tip_centre(k, th, d, R_TIP), atol=1e-9)
        assert math.remainder(pose.angle - phi, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
        assert np.all(q - lim[:, 0] >= pr.JOINT_MARGIN - 1e-12)
        assert np.all(lim[:, 1] - q >= pr.JOINT_MARGIN - 1e-12)
    # the relative orientation changes at most max_rate per unit of rotation
    assert np.all(np.abs(np.diff(psi)) <= 3.0 * math.radians(1.0) + 1e-9)


def test_rolling_path_reach_shrinks_with_the_margin_and_is_capped():
    face = pr.Face.between(SQUARE[1], SQUARE[2], SQUARE.mean(axis=0))
    args = (HAND, SQUARE, face, 0.04, math.radians(200.0))
    wide = pr.tip_rolling_path(*args)
    narrow = pr.tip_rolling_path(*args, margin=0.2)
    assert narrow.reach <= wide.reach
    capped = pr.tip_rolling_path(*args, max_turn=math.radians(5.0))
    assert capped.reach == pytest.approx(math.radians(5.0))
    # an infeasible start (the tip would be inside the palm): no path
    none = pr.tip_rolling_path(HAND, SQUARE, face, 0.004, math.radians(200.0))
    assert none.reach == 0.0 and len(none.theta) == 1


def test_the_right_face_is_out_of_reach_beyond_31_degrees():
    """The hand's workspace bound of square_gait: from no start on the right face does
    the right tip's rolling path pivot the 11 cm square 32 deg (links 4 mm clear)."""
    face = pr.Face.between(SQUARE[1], SQUARE[2], SQUARE.mean(axis=0))
    best = max(
        pr.tip_rolling_path(HAND, SQUARE, face, d0, math.radians(phi0), max_turn=0.6).reach
        for d0 in np.arange(0.01, 0.105, 0.01)
        for phi0 in range(90, 270, 10)
    )
    assert math.radians(25.0) < best < math.radians(32.0)


def test_the_stuck_pad_follows_the_pivot_on_its_circle():
    phi = -0.5 * math.pi  # pad flat on the left face (outward normal -x)
    centre = np.array([-A, 0.08])
    reach, qs = pr.pad_reach(HAND, SQUARE, centre, phi)
    assert math.radians(20.0) < reach < math.radians(40.0)
    k = pr.palm_corner(SQUARE)
    for i, q in enumerate(qs):
        th = -math.radians(1.0) * i
        pose = HAND.fingertip_pose(np.r_[q, HAND.neutral()[3:]], "left")
        assert np.allclose(pose.position, pr.pivoted(centre, k, th), atol=1e-9)
        assert math.remainder(pose.angle - (phi + th), 2 * math.pi) == pytest.approx(0, abs=1e-9)
    # the pad low on the left face is out of reach with the square flat on the palm
    assert pr.pad_reach(HAND, SQUARE, np.array([-A, 0.03]), phi)[1].shape == (0, 3)


def test_pivot_grasps_of_the_square_gait_hand():
    """Which faces the fingers reach as the square pivots: the right face (edge 1) only up
    to 30 deg, nothing at all for the round tip beyond 55 deg."""
    thetas = -np.radians([0.0, 30.0, 40.0, 60.0])
    g = pivot_grasps(HAND, SQUARE, thetas, 1.0)
    assert 1 in g[0].tip and 3 in g[0].pad and g[0].stable
    assert 1 in g[1].tip
    assert 1 not in g[2].tip and 2 in g[2].tip  # only the top face (and a corner)
    assert g[3].tip == () and not g[3].stable


def test_pivot_grasps_stability_is_the_friction_cone_test():
    """A constructed case: with a hand that reaches everything, the flat square's left and
    right faces are a stable pair for any mu > 0; with mu -> 0 only exactly opposite points
    are, which the sampling still finds (same heights on both faces)."""
    g = pivot_grasps(HAND, SQUARE, [0.0], 1e-3)
    assert g[0].stable  # pad and tip at the same height on parallel faces
    with pytest.raises(InvalidParameter):
        pivot_grasps(HAND, SQUARE, [0.0], 0.0)


# ---------------------------------------------------------------- the executor's use
def _start_on_square(d0: float = 0.04, phi0: float = math.radians(200.0), pad_y: float = 0.08):
    """Joint angles and a sensed estimate of the square at rest: the pad flat on the left
    face with its centre at height ``pad_y``, the round tip on the right face at ``d0``
    with the orientation ``phi0``; the estimate's centre half a width inside the pad."""
    from types import SimpleNamespace

    qL = HAND.inverse_kinematics("left", [-A, pad_y], angle=-0.5 * math.pi)
    face = pr.Face.between(SQUARE[1], SQUARE[2], SQUARE.mean(axis=0))
    T = face.tip_centre(SQUARE[1], 0.0, d0, R_TIP)
    qR = HAND.inverse_kinematics("right", T, angle=phi0)
    centre = np.array([0.0, pad_y])
    est = SimpleNamespace(
        tips=np.array([[-A, pad_y], T]),
        centre=centre,
        beta=np.array([math.pi, math.atan2(T[1] - pad_y, T[0])]),
        u=0.0,
    )
    return np.r_[qL, qR], est, face


def test_plan_pivot_turns_every_point_about_the_palm_corner():
    from planner.exploration.planar.pivot_planning import PIVOT_SLACK, plan_pivot

    q, est, face = _start_on_square()
    plan = plan_pivot(HAND, SQUARE, face, 0.04, est, q, math.radians(40.0), 12)
    assert plan.success and plan.rotation < -math.radians(5.0)
    k = pr.palm_corner(SQUARE)
    path = pr.tip_rolling_path(HAND, SQUARE, face, 0.04, q[3:].sum(), max_turn=0.7,
                               margin=0.045)  # fmt: skip
    reach_l, _ = pr.pad_reach(HAND, SQUARE, est.tips[0], q[:3].sum(), margin=0.045)
    assert -plan.rotation == pytest.approx(min(path.reach, reach_l) - PIVOT_SLACK, abs=1e-9)
    assert plan.theta[0] == 0.0 and np.all(np.diff(plan.theta) < 0)
    rho = np.linalg.norm(est.centre - k)
    assert np.allclose(np.linalg.norm(plan.centre - k, axis=1), rho, atol=1e-12)
    assert np.allclose(plan.beta[:, 0], math.pi + plan.theta, atol=1e-12)
    assert np.allclose(plan.u, 0.0)
    for th, qk in zip(plan.theta, plan.q, strict=True):
        pad = HAND.fingertip_pose(qk, "left")
        # knots between the 1 deg grid interpolate the joints: sub-millimetre
        assert np.linalg.norm(pad.position - pr.pivoted(est.tips[0], k, th)) < 2e-4
        assert math.remainder(pad.angle - (-0.5 * math.pi + th), 2 * math.pi) == pytest.approx(
            0.0, abs=2e-3
        )
        tip = HAND.fingertip_pose(qk, "right").position
        m = pr.rotation(th) @ face.normal
        assert float((tip - k) @ m) == pytest.approx(R_TIP, abs=2e-4)  # on the face's offset
        assert HAND.within_limits(qk)


def test_plan_pivot_fails_with_its_reason_at_the_workspace_end():
    from planner.exploration.planar.pivot_planning import plan_pivot

    q, est, face = _start_on_square()
    turned = pr.pivoted(SQUARE, SQUARE[1], -math.radians(33.0))
    fturned = pr.Face.between(turned[1], turned[2], turned.mean(axis=0))
    T = fturned.tip_centre(turned[1], 0.0, 0.05, R_TIP)
    qR = HAND.inverse_kinematics("right", T)  # within the limits, but its links cut the square
    plan = plan_pivot(HAND, turned, fturned, 0.05, est, np.r_[q[:3], qR], 0.5, 8)
    assert not plan.success and plan.rotation == 0.0
    assert "right tip reaches" in plan.stop and "left pad" in plan.stop


def test_best_tip_regrasp_beats_the_start_grasp_and_is_its_paths_reach():
    """The regrasp chosen on the square_gait hand's right face pivots further than the start
    grasp's contact (69.7 mm up the face, tip at 147 deg), and its reach is its rolling
    path's."""
    from planner.exploration.planar.pivot_planning import PIVOT_MARGIN, best_tip_regrasp

    face = pr.Face.between(SQUARE[1], SQUARE[2], SQUARE.mean(axis=0))
    d0, phi0, reach = best_tip_regrasp(HAND, SQUARE, face, theta_cap=math.radians(40.0))
    start = pr.tip_rolling_path(HAND, SQUARE, face, 0.0697, math.radians(147.2),
                                max_turn=math.radians(40.0), margin=PIVOT_MARGIN)  # fmt: skip
    assert reach > start.reach + math.radians(10.0)
    again = pr.tip_rolling_path(HAND, SQUARE, face, d0, phi0, max_turn=math.radians(40.0),
                                margin=PIVOT_MARGIN)  # fmt: skip
    assert again.reach == pytest.approx(reach)


def test_outline_explore_segment_goes_to_a_point_and_turns_the_tip():

    from planner.exploration.planar.outline_pose import Outline
    from planner.exploration.planar.outline_segments import outline_explore_segment
    from planner.exploration.planar.settings import GaitSettings
    from planner.exploration.planar.shape_tracking import ShapeTracker

    outline = Outline(np.array([[A, -A], [A, A], [-A, A], [-A, -A]]))
    tracker = ShapeTracker(outline, (0.0, A, 0.0), HAND)
    q, est, _ = _start_on_square(d0=0.07)
    est.p = np.array([[-A, 0.08], [A, 0.07]])
    est.normal_force = np.array([0.4, 0.3])
    s = GaitSettings()
    target = np.array([A, 0.04])
    phi_end = float(q[3:].sum()) + 0.5
    seg = outline_explore_segment(2, est, q, tracker, 0.0, 0.0, s, HAND,
                                  target_point=target, phi_end=phi_end)  # fmt: skip
    p0, _, phi_a = seg.explore(0.0)
    p1, v1, phi_b = seg.explore(seg.duration)
    assert np.allclose(p0, [A, 0.07], atol=1e-9) and phi_a == pytest.approx(q[3:].sum())
    assert np.allclose(p1, target, atol=1e-9) and phi_b == pytest.approx(phi_end)
    assert np.allclose(v1, 0.0, atol=1e-9)
    # the turn is spread over the move (monotone with the contact's progress)
    phis = [seg.explore(t)[2] for t in np.linspace(0.0, seg.duration, 50)]
    assert np.all(np.diff(phis) >= -1e-12)


def test_move_check_of_a_regrasp():
    """The phase-2 move to a regrasp: staying put is fine; a target beyond the base joint's
    lower limit on the way (the tip far down the right face turned the wrong way) is not."""
    from planner.exploration.planar.pivot_planning import _move_ok

    q, _, face = _start_on_square(d0=0.06, phi0=math.radians(180.0))
    here = (0.06, float(q[3:].sum()))
    assert _move_ok(HAND, SQUARE, face, q[3:], here)
    lim = HAND.finger_limits("right")
    far = (0.006, float(q[3:].sum()) - 2.5)
    assert not _move_ok(HAND, SQUARE, face, q[3:], far)
    assert np.all(q[3:] > lim[:, 0])


def test_a_start_inside_the_margin_band_may_start_a_path():
    """``start_margin``: the executor starts where the finger is (the start grasp's base
    joint 4.8 deg = 0.084 rad from its limit); every later knot keeps the full margin."""
    face = pr.Face.between(SQUARE[1], SQUARE[2], SQUARE.mean(axis=0))
    args = (HAND, SQUARE, face, 0.0697, math.radians(147.2))
    strict = pr.tip_rolling_path(*args, margin=0.1)
    assert strict.reach == 0.0 and not np.isfinite(strict.margin[0])
    loose = pr.tip_rolling_path(*args, margin=0.1, start_margin=0.0)
    assert loose.margin[0] == pytest.approx(math.radians(4.8), abs=2e-3)
    # the pivot drives that joint toward its limit: no knot after the start keeps 0.1 rad
    assert loose.reach == 0.0
    wide = pr.tip_rolling_path(*args, margin=0.06, start_margin=0.0)
    assert wide.reach > math.radians(3.0) and np.all(wide.margin[1:] >= 0.06)
    assert np.all(np.diff(wide.margin) < 0)  # the base joint nears its limit knot by knot


@settings(max_examples=40, deadline=None)
@given(
    finger=st.sampled_from(["left", "right"]),
    theta=st.floats(-1.0, 0.0),
    margin=st.floats(0.0, 0.1),
    clr=st.floats(-0.01, 0.006),
    seed=st.integers(0, 2**16),
)
def test_compiled_finger_configurations_equal_the_numpy_reference(finger, theta, margin, clr,
                                                                  seed):  # fmt: skip
    """The compiled configurations (both elbow branches, limits with margin, link clearance
    of the pivoted square) are the numpy reference's: the same branch and feasibility, the
    same angles and margins to rounding, over tip poses in and out of reach."""
    from robots.planar_hand import kinematics as kin

    rng = np.random.default_rng(seed)
    f, lim = HAND.params.finger(finger), HAND.finger_limits(finger)
    qs = rng.uniform(lim[:, 0], lim[:, 1], (30, 3))  # reachable poses, then arbitrary ones
    tips, phis = kin.fingertip(np.array(f.base), np.array(f.lengths), qs)
    T = np.vstack([tips, rng.uniform([-0.15, -0.02], [0.15, 0.2], (30, 2))])
    phi = np.concatenate([phis, rng.uniform(-math.pi, math.pi, 30)])
    clear = pr.HullClearance(SQUARE)
    k = np.array([A, 0.0])
    q, m, ok = pr.finger_configurations(HAND, finger, T, phi, clear, k, theta, margin, clr)
    q0, m0, ok0 = pr.finger_configurations_reference(HAND, finger, T, phi, clear, k, theta,
                                                     margin, clr)  # fmt: skip
    np.testing.assert_array_equal(ok, ok0)
    np.testing.assert_allclose(q, q0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(m, m0, rtol=0, atol=1e-12)
