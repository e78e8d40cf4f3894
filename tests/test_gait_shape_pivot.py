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
from robots.planar_hand import PlanarHand
from robots.planar_hand.params import HandParams, default_finger

A = 0.055  # half-width of the 11 cm square [m]
SQUARE = np.array([[-A, 0.0], [A, 0.0], [A, 2 * A], [-A, 2 * A]])  # resting on the palm
R_TIP = 0.025


def scenario_hand() -> PlanarHand:
    """The square_gait hand (right finger's ranges; the left one mirrors them)."""
    lo = tuple(math.radians(v) for v in (-40.0, 0.0, -10.0))
    hi = tuple(math.radians(v) for v in (90.0, 150.0, 130.0))
    right = default_finger("right")
    left = default_finger("left")
    from dataclasses import replace

    right = replace(right, lower=lo, upper=hi)
    left = replace(left, lower=tuple(-v for v in hi), upper=tuple(-v for v in lo))
    return PlanarHand(HandParams(left=left, right=right, friction=1.0))


HAND = scenario_hand()


def test_palm_corner_is_the_lowest_rightmost_vertex():
    assert np.allclose(pr.palm_corner(SQUARE), [A, 0.0])
    tilted = pr.pivoted(SQUARE, [A, 0.0], -0.3)  # standing on its corner
    assert np.allclose(pr.palm_corner(tilted), [A, 0.0])
    with pytest.raises(InvalidParameter):
        pr.palm_corner(np.zeros((2, 2)))


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
    g = pr.pivot_grasps(HAND, SQUARE, thetas, 1.0)
    assert 1 in g[0].tip and 3 in g[0].pad and g[0].stable
    assert 1 in g[1].tip
    assert 1 not in g[2].tip and 2 in g[2].tip  # only the top face (and a corner)
    assert g[3].tip == () and not g[3].stable


def test_pivot_grasps_stability_is_the_friction_cone_test():
    """A constructed case: with a hand that reaches everything, the flat square's left and
    right faces are a stable pair for any mu > 0; with mu -> 0 only exactly opposite points
    are, which the sampling still finds (same heights on both faces)."""
    g = pr.pivot_grasps(HAND, SQUARE, [0.0], 1e-3)
    assert g[0].stable  # pad and tip at the same height on parallel faces
    with pytest.raises(InvalidParameter):
        pr.pivot_grasps(HAND, SQUARE, [0.0], 0.0)
