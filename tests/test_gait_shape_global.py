"""The global pose search of a posed polygon (outline_pose.fit_pose_global and its symmetry
helpers): a square tipped far from the rolling prior is found again, up to its symmetry."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.exploration.planar.outline_pose import (
    Outline,
    Readings,
    distances_to_polygon,
    fit_pose,
    fit_pose_global,
    nearest_on_polygon,
    residuals,
    start_position,
    symmetric_pose,
    symmetry_order,
)
from planner.geometry import shapes
from tests.test_gait_shape import SQUARE, A, exact_readings, resting


def _ngon(n: int, radius: float = 0.05) -> Outline:
    ang = 2 * np.pi * np.arange(n) / n
    return Outline(radius * np.column_stack([np.cos(ang), np.sin(ang)]))


def _same_polygon(P, Q, tol=1e-9) -> bool:
    """Whether the closed polygons P and Q cover the same set (vertices on each other)."""
    return max(distances_to_polygon(P, Q).max(), distances_to_polygon(Q, P).max()) < tol


@pytest.mark.parametrize("n", [3, 4, 5, 6, 8])
def test_regular_polygons_have_their_order(n):
    assert symmetry_order(_ngon(n)) == n


def test_symmetry_orders_of_other_outlines():
    rect = Outline(np.array([[0.04, 0.02], [-0.04, 0.02], [-0.04, -0.02], [0.04, -0.02]]))
    kite = Outline(np.array([[0.05, 0.0], [0.0, 0.02], [-0.02, 0.0], [0.0, -0.02]]))
    rounded = Outline.from_profile(shapes.rounded_rectangle(0.08, 0.08, 0.016))
    assert symmetry_order(SQUARE) == 4
    assert symmetry_order(rect) == 2
    assert symmetry_order(kite) == 1
    assert symmetry_order(rounded) == 4


@settings(max_examples=25, deadline=None)
@given(
    x=st.floats(-0.05, 0.05),
    y=st.floats(0.0, 0.1),
    theta=st.floats(-math.pi, math.pi),
    turns=st.integers(-3, 3),
    off=st.tuples(st.floats(-0.02, 0.02), st.floats(-0.02, 0.02)),
)
def test_symmetric_pose_covers_the_same_polygon(x, y, theta, turns, off):
    """An off-centre frame (origin away from the centroid): the symmetric pose, turned by
    ``turns`` quarter turns, poses the square onto the same world polygon."""
    sq = Outline(SQUARE.points + np.asarray(off))
    pose = np.array([x, y, theta])
    other = symmetric_pose(sq, pose, turns, 4)
    assert other[2] == pytest.approx(theta + turns * math.pi / 2)
    assert _same_polygon(sq.posed(pose), sq.posed(other))


def test_start_position_puts_the_square_on_the_palm_and_the_pad_line():
    """Closed form: the square at rotation 0, the pad flat on its left face at x = x0 - A."""
    x0 = 0.007
    rd = Readings(pad_point=np.array([x0 - A, 0.05]), pad_angle=-math.pi / 2)
    s = start_position(SQUARE, 0.0, rd, (0.0, 0.0))
    np.testing.assert_allclose(s, [x0, A, 0.0], atol=1e-15)
    # without the palm the guess's height is kept
    rd = Readings(pad_point=np.array([x0 - A, 0.05]), pad_angle=-math.pi / 2, palm=False)
    np.testing.assert_allclose(start_position(SQUARE, 0.0, rd, (0.0, 0.02)), [x0, 0.02, 0.0])


def _tipped():
    """The 11 cm square standing 42 deg over on its palm corner, the pad on its upper-left
    corner, the tip on its lower-right face: the executor's case after a square tipped
    where its rolling estimate said 12 deg."""
    pose = resting(0.003, math.radians(-42.0))
    rd = exact_readings(pose, math.radians(10.0), 0.004, 0.5)
    assert np.abs(residuals(SQUARE, pose, rd)).max() < 1e-12
    return pose, rd


def test_local_fit_from_a_far_prior_misses_the_tipped_square():
    """Why the global search exists: started and pulled by a prior 30 deg off, the local
    fit does not reach the pose."""
    pose, rd = _tipped()
    prior = float(pose[2]) + math.radians(30.0)
    fit = fit_pose(SQUARE, rd, (0.0, 0.06, prior), prior, 0.01)
    assert not (fit.success and np.allclose(fit.pose, pose, atol=1e-3))


@pytest.mark.parametrize("prior_deg", [-12.0, -42.0, -70.0])
def test_global_fit_finds_the_tipped_square(prior_deg):
    pose, rd = _tipped()
    fit = fit_pose_global(SQUARE, rd, (0.0, 0.06, 0.0), math.radians(prior_deg))
    assert fit.success and fit.cost < 1e-9
    np.testing.assert_allclose(fit.pose, pose, atol=1e-7)


def test_global_fit_returns_the_symmetric_pose_nearest_the_prior():
    """A prior past the next quarter turn: the same world polygon, posed a quarter turn on
    (the square lying on its next face is the start again, turned 90 deg)."""
    pose, rd = _tipped()
    prior = float(pose[2]) - math.radians(60.0)
    fit = fit_pose_global(SQUARE, rd, (0.0, 0.06, 0.0), prior)
    assert fit.success
    assert fit.pose[2] == pytest.approx(float(pose[2]) - math.pi / 2, abs=1e-7)
    assert _same_polygon(SQUARE.posed(fit.pose), SQUARE.posed(pose), tol=1e-7)


def test_global_fit_of_a_hexagon():
    """A regular hexagon (symmetry 6) resting tipped 20 deg on a corner, read by the pad on
    its left, the tip on its right and the palm: found from a prior 25 deg off."""
    hexa = _ngon(6)
    theta = math.radians(-20.0)
    W0 = hexa.posed((0.0, 0.0, theta))
    pose = np.array([0.0, -W0[:, 1].min(), theta])
    W = hexa.posed(pose)
    phi = -math.pi / 2 + math.radians(20.0)  # pad tilted onto the lower-left corner
    n, t = np.array([math.sin(phi), -math.cos(phi)]), np.array([math.cos(phi), math.sin(phi)])
    corner = W[int(np.argmax(W @ n))]
    right = W[int(np.argmax(W[:, 0]))]
    tip = right + 0.0125 * np.array([1.0, 0.0])  # touching the rightmost corner
    rd = Readings(pad_point=corner - 0.003 * t, pad_angle=phi, pad_u=0.003,
                  pad_u_max=0.00875, tip_centre=tip, tip_radius=0.0125)  # fmt: skip
    assert np.abs(residuals(hexa, pose, rd)).max() < 1e-12
    fit = fit_pose_global(hexa, rd, (0.0, 0.05, 0.0), theta + math.radians(25.0))
    assert fit.success and fit.cost < 1e-9
    assert _same_polygon(hexa.posed(fit.pose), W, tol=1e-6)


def _estimate(rd: Readings):
    """A stand-in for the executor's ``GraspEstimate`` carrying the readings ``rd``."""
    from types import SimpleNamespace

    c, s = math.cos(rd.pad_angle), math.sin(rd.pad_angle)
    return SimpleNamespace(
        pad_touch=True, tips=np.array([rd.pad_point, rd.tip_centre]),
        phi=np.array([rd.pad_angle, 0.0]), u=rd.pad_u, normal_force=np.array([1.0, 1.0]),
        centre=rd.pad_point + 0.05 * np.array([-s, c]),
    )  # fmt: skip


def _with_tip_radius(pose, rd: Readings, r_tip: float) -> Readings:
    """``rd`` with a round tip of radius ``r_tip`` [m] touching the posed square where the
    tip of ``rd`` touches it."""
    q, d = nearest_on_polygon(SQUARE.posed(pose), rd.tip_centre)
    tip = q + r_tip * (rd.tip_centre - q) / d
    return Readings(**{**rd.__dict__, "tip_centre": tip, "tip_radius": r_tip})


def test_tracker_takes_the_global_fit_when_the_prior_is_far():
    """The tracker's rolling prior says -12 deg, the square stands at -42: the update lands
    on the true pose (the global search), counted in ``global_fits``."""
    from planner.exploration.planar.shape_tracking import ShapeTracker
    from robots.planar_hand import PlanarHand

    pose, rd = _tipped()
    hand = PlanarHand()
    rd = _with_tip_radius(pose, rd, hand.params.right.tip_radius)
    tr = ShapeTracker(SQUARE, (0.0, A, 0.0), hand, pad_u_max=rd.pad_u_max)
    assert tr.order == 4
    assert tr.update(_estimate(rd), math.radians(-12.0))
    np.testing.assert_allclose(tr.pose, pose, atol=1e-6)
    assert tr.global_fits == 1


def test_simplified_outline_is_the_same_polygon():
    """A sharp square sampled every millimetre keeps its 4 corners; a rounded one its arcs;
    both cover the same set."""
    sharp = Outline.from_profile(shapes.rounded_rectangle(0.06, 0.06, 0.0))
    rounded = Outline.from_profile(shapes.rounded_rectangle(0.08, 0.08, 0.016))
    s = sharp.simplified()
    assert len(sharp.points) > 200 and len(s.points) == 4
    assert _same_polygon(s.points, sharp.points, tol=1e-12)
    r = rounded.simplified()
    assert 4 < len(r.points) < len(rounded.points)
    assert _same_polygon(r.points, rounded.points, tol=1e-12)
