"""Friction-cone geometry of holds and grasps on non-round objects (planar/hold_geometry.py):
closed forms on the circle (inscribed angle, stable_pair) and on the standing ellipse."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.errors import InvalidParameter
from planner.exploration.planar.heuristics import stable_pair
from planner.exploration.planar.hold_geometry import (
    contact_line_angles,
    grasp_window,
    palm_press_angle,
    resting_contact,
)
from planner.geometry import shapes

BETAS = np.radians([-60.0, -20.0, 0.0, 15.0, 40.0, 75.0, 90.0, 120.0, 160.0, 200.0])


@pytest.mark.parametrize("beta", BETAS)
def test_circle_palm_press_angle_is_the_inscribed_angle(beta):
    """On a circle the chord to the bottom point makes |pi/2 - beta| / 2 with the radius
    (inscribed angle theorem; hold_tangential_force with M = 0: T/N = tan((beta-pi/2)/2))."""
    R = 0.05
    c = np.array([0.01, R])
    p = c + R * np.array([math.cos(beta), math.sin(beta)])
    got = palm_press_angle(p, c - p, (c[0], 0.0))
    assert got == pytest.approx(abs(0.5 * math.pi - beta) / 2, abs=1e-12)


@pytest.mark.parametrize("angle", np.radians([0.0, -37.0, -90.0, 143.0]))
def test_resting_circle_matches_the_closed_form_at_any_rotation(angle):
    circle = shapes.circle(0.05)
    for beta in np.radians([10.0, 24.0, 50.0]):
        p, n, palm = resting_contact(circle, angle, beta)
        assert palm_press_angle(p, n, palm) == pytest.approx((0.5 * math.pi - beta) / 2, abs=2e-3)
        assert np.linalg.norm(n) == pytest.approx(1.0)
        assert p[1] == pytest.approx(0.05 + 0.05 * math.sin(beta), abs=1e-5)


def _standing_ellipse_angle(a: float, b: float, beta: float) -> float:
    """Closed form: the ellipse x^2/a^2 + y^2/b^2 = 1 turned by -90 deg stands on its end
    (horizontal semi-axis b, vertical a, centre at height a, palm contact (0, 0)); the
    contact at polar angle beta: r = 1 / sqrt(cos^2/b^2 + sin^2/a^2), outward normal along
    the gradient (x / b^2, y / a^2)."""
    cb, sb = math.cos(beta), math.sin(beta)
    r = 1.0 / math.sqrt(cb * cb / (b * b) + sb * sb / (a * a))
    x, y = r * cb, r * sb
    n = np.array([x / b**2, y / a**2])
    n /= np.linalg.norm(n)
    chord = np.array([0.0, -a]) - np.array([x, y])
    chord /= np.linalg.norm(chord)
    return math.acos(float(-n @ chord))


@pytest.mark.parametrize("beta_deg", [15.0, 20.0, 40.0, 60.0])
def test_standing_ellipse_against_its_closed_form(beta_deg):
    a, b = 0.06, 0.05
    beta = math.radians(beta_deg)
    p, n, palm = resting_contact(shapes.ellipse(a, b), -0.5 * math.pi, beta)
    assert palm[1] == 0.0 and palm[0] == pytest.approx(0.0, abs=1e-4)
    assert p[1] == pytest.approx(a + math.sin(beta) / math.sqrt(
        math.cos(beta) ** 2 / b**2 + math.sin(beta) ** 2 / a**2), abs=1e-5)  # fmt: skip
    expected = _standing_ellipse_angle(a, b, beta)
    assert palm_press_angle(p, n, palm) == pytest.approx(expected, abs=2e-3)


def test_standing_12x10_ellipse_puts_the_holder_on_its_cone_edge():
    """ellipse_gait's description (its 12 x 10 cm ellipse): with the object on its end the
    right holder at beta = 20 deg pushes 44 deg off its normal (tan 44 deg = 0.97, the
    measured T/N 0.95-0.97 at mu = 1), where the circle model says 35 deg; lying flat it is
    24 deg."""
    e = shapes.ellipse(0.06, 0.05)
    beta = math.radians(20.0)
    standing = palm_press_angle(*resting_contact(e, -0.5 * math.pi, beta))
    lying = palm_press_angle(*resting_contact(e, 0.0, beta))
    assert math.degrees(standing) == pytest.approx(44.1, abs=0.3)
    assert math.degrees(lying) == pytest.approx(24.3, abs=0.3)
    assert (0.5 * math.pi - beta) / 2 == pytest.approx(math.radians(35.0))


@pytest.mark.parametrize(("bl", "br"), [(150.0, 20.0), (170.0, -10.0), (120.0, 60.0)])
def test_circle_contact_line_matches_stable_pair(bl, br):
    """On a circle both angles are pi/2 - |beta_L - beta_R| / 2, and stable_pair is
    atan(mu) - margin minus that angle."""
    R, c = 0.05, np.array([0.0, 0.05])
    bl, br = math.radians(bl), math.radians(br)
    pl = c + R * np.array([math.cos(bl), math.sin(bl)])
    pr = c + R * np.array([math.cos(br), math.sin(br)])
    a_l, a_r = contact_line_angles(pl, c - pl, pr, c - pr)
    half = 0.5 * math.pi - abs(bl - br) / 2
    assert a_l == pytest.approx(half, abs=1e-12) and a_r == pytest.approx(half, abs=1e-12)
    assert stable_pair(bl, br, 0.8, 0.1) == pytest.approx(math.atan(0.8) - 0.1 - half)


def test_angles_are_invariant_under_rigid_motion():
    rng = np.random.default_rng(3)
    for _ in range(20):
        pts = rng.normal(size=(3, 2))
        nl, nr = rng.normal(size=(2, 2))
        th = rng.uniform(-math.pi, math.pi)
        rot = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
        t = rng.normal(size=2)
        moved = pts @ rot.T + t
        assert palm_press_angle(pts[0], nl, pts[1]) == pytest.approx(
            palm_press_angle(moved[0], rot @ nl, moved[1]), abs=1e-12
        )
        a = contact_line_angles(pts[0], nl, pts[2], nr)
        b = contact_line_angles(moved[0], rot @ nl, moved[2], rot @ nr)
        assert a == pytest.approx(b, abs=1e-12)


def test_degenerate_input_is_one_clear_error():
    with pytest.raises(InvalidParameter, match="palm_contact - contact"):
        palm_press_angle((0.0, 0.0), (0.0, -1.0), (0.0, 0.0))
    with pytest.raises(InvalidParameter, match="inward_normal"):
        palm_press_angle((0.0, 0.1), (0.0, 0.0), (0.0, 0.0))
    with pytest.raises(InvalidParameter, match="p_right - p_left"):
        contact_line_angles((0.0, 0.0), (1.0, 0.0), (0.0, 0.0), (-1.0, 0.0))


def _window_hand():
    from robots.planar_hand import PlanarHand, gait_hand_params

    return PlanarHand(gait_hand_params())


WINDOW = {
    "press_limit": math.radians(34.0),
    "line_limit": math.atan(0.8) - 0.15,
    "joint_reserve": math.radians(2.9),
}


def test_grasp_window_shrinks_when_the_ellipse_stands_on_its_end():
    """ellipse_gait's description (its 12 x 10 cm ellipse): 13 of the 195 pairs lying flat,
    2-6 between -60 and -120 deg, every one with the right contact >= 35 deg (the executor
    holds at 24)."""
    hand, e = _window_hand(), shapes.ellipse(0.06, 0.05)
    flat = grasp_window(e, hand, 0.0, 1.0, **WINDOW)
    assert len(flat) == 13
    for deg in (-60.0, -90.0, -120.0):
        pairs = grasp_window(e, hand, math.radians(deg), 1.0, **WINDOW)
        assert 1 <= len(pairs) <= 6
        assert min(br for br, _ in pairs) >= math.radians(35.0) - 1e-9
        for br, bl in pairs:  # each pair meets the limits it was selected by
            pr, nr, palm = resting_contact(e, math.radians(deg), br)
            pl, nl, _ = resting_contact(e, math.radians(deg), bl)
            assert palm_press_angle(pr, nr, palm) <= WINDOW["press_limit"]
            assert max(contact_line_angles(pl, nl, pr, nr)) <= WINDOW["line_limit"]
    circle = grasp_window(shapes.circle(0.0548), hand, 0.0, 1.0, **WINDOW)
    assert len(circle) > len(flat)


def test_grasp_window_limits_beyond_the_cone_are_refused():
    with pytest.raises(InvalidParameter, match="press_limit"):
        grasp_window(shapes.circle(0.05), _window_hand(), 0.0, 0.5, press_limit=0.5,
                     line_limit=0.3, joint_reserve=0.05)  # fmt: skip
