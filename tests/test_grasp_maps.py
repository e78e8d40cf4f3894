"""Grasp maps, workspace maps and the diagonal-sliding property (planner.grasp.maps)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.geometry import curves
from planner.grasp import epsilon_quality, force_closure, grasp_map, shift_diagonal, workspace_map


@pytest.mark.parametrize("mu", [0.3, 1.0])
def test_circle_map_matches_separation_rule_and_pointwise_functions(mu):
    g = grasp_map(curves.circle(0.05), mu, resolution=72)
    sep = np.abs(np.angle(np.exp(1j * (g.theta[:, None] - g.theta[None, :]))))
    bound = np.pi - 2 * np.arctan(mu)
    clear = np.abs(sep - bound) > 1e-9
    assert np.array_equal(g.force_closure[clear], (sep > bound)[clear])
    rng = np.random.default_rng(0)
    for i, j in rng.integers(0, 72, size=(40, 2)):
        p = g.points[[i, j]]
        n = g.normals[[i, j]]
        if i != j:
            assert g.force_closure[i, j] == force_closure(p, n, mu)
            assert g.epsilon[i, j] == pytest.approx(epsilon_quality(p, n, mu), abs=1e-12)


def test_map_symmetry_and_epsilon_zero_outside_closure():
    g = grasp_map(curves.ellipse(0.06, 0.035), 0.6, resolution=90)
    assert np.array_equal(g.force_closure, g.force_closure.T)
    assert np.allclose(g.epsilon, g.epsilon.T, atol=1e-12)
    assert np.all(g.epsilon[~g.force_closure] == 0)
    assert np.all(g.epsilon[g.force_closure] > 0)
    assert not g.force_closure.diagonal().any()


@settings(max_examples=8, deadline=None)
@given(steps=st.integers(-30, 30), a=st.floats(0.03, 0.08), ratio=st.floats(0.4, 1.0))
def test_rotation_slides_map_along_diagonal(steps, a, ratio):
    n = 60
    prof = curves.ellipse(a, a * ratio)
    g = grasp_map(prof, 0.5, resolution=n)
    rotated = grasp_map(prof.transformed(2 * np.pi * steps / n), 0.5, resolution=n)
    assert np.mean(rotated.force_closure != shift_diagonal(g.force_closure, steps)) < 0.01
    assert np.allclose(rotated.epsilon, shift_diagonal(g.epsilon, steps), atol=2e-3)


@settings(max_examples=6, deadline=None)
@given(scale=st.floats(0.1, 10.0))
def test_map_invariant_under_scaling(scale):
    g1 = grasp_map(curves.ellipse(0.05, 0.03), 0.8, resolution=48)
    g2 = grasp_map(curves.ellipse(0.05 * scale, 0.03 * scale), 0.8, resolution=48)
    assert np.mean(g1.force_closure != g2.force_closure) < 0.01
    assert np.allclose(g1.epsilon, g2.epsilon, atol=1e-3)


def test_palm_friction_changes_one_axis():
    g = grasp_map(curves.circle(0.05), 1.0, resolution=72, mu2=0.2)
    # contact 2 with less friction: the closure region shrinks
    assert (
        g.force_closure.sum()
        < grasp_map(curves.circle(0.05), 1.0, resolution=72).force_closure.sum()
    )


def test_workspace_map_matches_robot_ball_workspace():
    from robots.planar_hand import PlanarHand, ball_workspace

    hand = PlanarHand()
    w = workspace_map(curves.circle(0.05), hand, resolution=72)
    assert w.palm_index[0] == 54  # 270 deg: the ball rests on the palm
    assert np.allclose(w.placement.offsets[0], [0.0, 0.05])
    for f in ("left", "right"):
        ref = ball_workspace(
            hand, f, (0.0, 0.05), 0.05, w.theta, n_orientations=13, n_pad_offsets=5
        )
        assert np.array_equal(w.reachable[f][0], ref.reachable)
        assert w.reachable[f][0].any()


def test_bad_inputs():
    with pytest.raises(InvalidParameter, match="resolution"):
        grasp_map(curves.circle(0.05), 1.0, resolution=2)
    with pytest.raises(InvalidParameter, match="mu"):
        grasp_map(curves.circle(0.05), -0.1)
    with pytest.raises(InvalidParameter, match="point_at_polar_angle"):
        grasp_map(object(), 1.0)
    with pytest.raises(InvalidParameter, match="PlanarHand"):
        workspace_map(curves.circle(0.05), hand="not a hand", resolution=36)


def test_hand_grasp_maps_three_pairs():
    from planner.grasp import hand_grasp_maps

    maps = hand_grasp_maps(curves.circle(0.05), 1.0, 72, mu_palm=0.4)
    assert set(maps) == {("left", "right"), ("left", "palm"), ("right", "palm")}
    sep = np.abs(
        np.angle(
            np.exp(1j * (maps["left", "palm"].theta[:, None] - maps["left", "palm"].theta[None, :]))
        )
    )
    # on a circle the chord makes the same angle with both normals: the lower friction rules
    bound = np.pi - 2 * np.arctan(0.4)
    clear = np.abs(sep - bound) > 1e-9
    assert np.array_equal(maps["left", "palm"].force_closure[clear], (sep > bound)[clear])
