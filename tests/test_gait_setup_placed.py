"""The start estimate of the gait's sensing (sensing.GraspSensing.mark_placed): the pad lies
where the start grasp put it, so the first estimate is the pad's, with no jump at the first
touch; the latch ends at the first pressure the tactile array reads."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from planner.exploration.planar.sensing import PLACED, TOUCH_FORCE, GraspSensing
from planner.geometry import shapes


@pytest.fixture(scope="module")
def hand():
    from robots.planar_hand import PlanarHand, gait_hand_params

    return PlanarHand(gait_hand_params())


def _start(hand, profile):
    """The world at t = 0 with the start grasp (setup.build_world) and its observation."""
    from planner.exploration.planar.objects import mean_radius
    from planner.exploration.planar.settings import GaitSettings
    from planner.exploration.planar.setup import build_world

    R = mean_radius(profile)
    world, start = build_world(profile, hand, 1.0, R, None, GaitSettings(mu=1.0), 0)
    return world.observe(), R, start


def _obs(obs, image):
    return SimpleNamespace(q=obs.q, tip_forces=obs.tip_forces, tactile={"left": image})


def test_placed_on_a_circle_the_first_estimate_is_the_true_centre(hand):
    obs, R, start = _start(hand, shapes.circle(0.05))
    s = GraspSensing(hand, R)
    s.mark_placed()
    est = s.update(obs, "auto")
    assert est.pad_touch and est.buffer[1] == PLACED and est.u == 0.0
    # within the encoders' quantization (0.27 mm here)
    np.testing.assert_allclose(est.centre, start["rest"][:2], atol=5e-4)
    assert math.degrees(est.beta[0]) == pytest.approx(math.degrees(start["beta"][0]), abs=0.5)


def test_placed_on_an_ellipse_the_estimate_is_the_pads_not_the_palms(hand):
    """The 12 x 10 cm ellipse: the palm estimate (c_y = R) is 12 mm from the pad's, the
    jump that turned the ellipse the wrong way at the first touch."""
    obs, R, _ = _start(hand, shapes.ellipse(0.06, 0.05))
    placed, plain, pad = GraspSensing(hand, R), GraspSensing(hand, R), GraspSensing(hand, R)
    placed.mark_placed()
    a = placed.update(obs, "auto").centre.copy()
    b = plain.update(obs, "auto").centre.copy()
    c = pad.update(obs, "pad").centre.copy()
    np.testing.assert_array_equal(a, c)
    assert not plain.est.pad_touch and np.linalg.norm(a - b) > 0.005


def test_the_latch_ends_at_the_first_pressure(hand):
    obs, R, _ = _start(hand, shapes.circle(0.05))
    s = GraspSensing(hand, R)
    s.mark_placed()
    rows, cols = s.array.rows, s.array.cols
    zero = np.zeros((rows, cols))
    s.update(SimpleNamespace(q=obs.q, tip_forces=obs.tip_forces, tactile=None))
    assert s.est.buffer[1] == PLACED  # no image: kept
    s.update(_obs(obs, zero))
    assert s.est.buffer[1] == PLACED  # an all-zero image: still unpressed
    weak = np.zeros((rows, cols))
    weak[0, 0] = 0.5 * TOUCH_FORCE / s.array.pitch**2
    s.update(_obs(obs, weak))
    assert not s.est.pad_touch  # a pressure below the touch force ends it
    s.update(_obs(obs, zero))
    assert not s.est.pad_touch


def test_a_pressed_pad_reads_its_centroid_and_then_lifts(hand):
    obs, R, _ = _start(hand, shapes.circle(0.05))
    s = GraspSensing(hand, R)
    s.mark_placed()
    image = np.zeros((s.array.rows, s.array.cols))
    image[:, 2] = 2.0 * TOUCH_FORCE / s.array.pitch**2
    est = s.update(_obs(obs, image))
    assert est.buffer[1] == 1.0 and est.u == pytest.approx(float(s.array.u[2]))
    est = s.update(_obs(obs, np.zeros_like(image)))
    assert not est.pad_touch and est.u == pytest.approx(float(s.array.u[2]))


def test_without_mark_placed_nothing_changes(hand):
    """The default sensing: an unpressed pad does not touch and the centre is the palm's."""
    obs, R, _ = _start(hand, shapes.circle(0.05))
    s = GraspSensing(hand, R)
    est = s.update(obs, "auto")
    assert not est.pad_touch and est.centre[1] == pytest.approx(R)
