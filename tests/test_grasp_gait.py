"""Gait search in map space (planner.grasp.gait)."""

from __future__ import annotations

import numpy as np
import pytest

from planner.errors import InvalidParameter
from planner.geometry import curves
from planner.grasp import plan_gait


@pytest.fixture(scope="module")
def hand():
    from robots.planar_hand import PlanarHand

    return PlanarHand()


def test_circle_forward_gait_turns_object_fully(hand):
    g = plan_gait(curves.circle(0.05), hand, 1.0, resolution=72)
    assert g.feasible, g.reason
    assert g.turns >= 1
    assert g.coverage == pytest.approx(1.0)
    assert g.min_epsilon > 0
    assert g.rotation_per_cycle < 0  # clockwise
    # the loop's phase-1 rotations add up to whole turns
    total = sum(p.rotation for p in g.phases)
    assert total == pytest.approx(-2 * np.pi * g.turns)
    assert g.rotation_per_cycle == pytest.approx(total / g.cycles)
    # prototype forward gait 1 -> 2 -> 3 -> 1
    assert [p.phase for p in g.phases[:3]] == [1, 2, 3]
    for p in g.phases:
        assert p.min_epsilon > 0
        assert (p.moving is None) == (p.phase == 1)
        if p.phase == 2:
            assert p.start["left"] == p.end["left"]  # the holding finger stays
        if p.phase == 3:
            assert p.start["right"] == p.end["right"]
    # consecutive phases connect
    for a, b in zip(g.phases, g.phases[1:] + g.phases[:1], strict=True):
        assert a.end["left"] == pytest.approx(b.start["left"])
        assert a.end["right"] == pytest.approx(b.start["right"])
    js = g.to_json()
    assert js["feasible"] and len(js["phases"]) == len(g.phases)


def test_counterclockwise_gait_rotates_the_other_way(hand):
    g = plan_gait(curves.circle(0.05), hand, 1.0, resolution=48, direction="counterclockwise")
    if g.feasible:
        assert g.rotation_per_cycle > 0
    else:
        assert g.reason


def test_long_thin_object_has_no_gait_and_says_why(hand):
    g = plan_gait(curves.ellipse(0.15, 0.015), hand, 1.0, resolution=48)
    assert not g.feasible
    assert g.phases == ()
    assert "force closure" in g.reason or "workspace" in g.reason


def test_object_beyond_the_workspace_has_no_gait_and_says_why(hand):
    # a 60 cm disc: no fingertip pose touches it (used to crash reshaping an empty selection)
    g = plan_gait(curves.circle(0.3), hand, 1.0, resolution=36)
    assert not g.feasible and g.phases == ()
    assert "workspace" in g.reason and "cannot reach" in g.reason


def test_the_search_finds_the_cycle_of_a_mildly_oval_object():
    # a 1.5:1 ellipse with the gait's hand: its cyclic gait needs more than the 6 phase-1
    # successors per node the search once kept (it said "no gait")
    from robots.planar_hand import PlanarHand, gait_hand_params

    g = plan_gait(curves.ellipse(0.05, 0.05 / 1.5), PlanarHand(gait_hand_params()), 1.0)
    assert g.feasible, g.reason
    assert g.turns >= 1 and g.rotation_per_cycle < 0 and g.min_epsilon > 0


def test_frictionless_object_has_no_gait(hand):
    g = plan_gait(curves.circle(0.05), hand, 0.0, resolution=36)
    assert not g.feasible and "force closure" in g.reason


def test_custom_reachability_model():
    class Everywhere:
        fingers = ("left", "right")
        palm_half_width = 1.0

        def reachable(self, finger, contacts, normals, inside):
            # left reaches the upper-left quadrant, right the upper-right, world frame
            a = np.arctan2(contacts[:, 1] - 0.05, contacts[:, 0])
            return (a > np.pi / 2) if finger == "left" else (a < np.pi / 2) & (a > -0.2)

    g = plan_gait(curves.circle(0.05), Everywhere(), 1.0, resolution=36, roll_length=0.02)
    assert g.feasible, g.reason
    assert g.turns >= 1


def test_bad_arguments(hand):
    with pytest.raises(InvalidParameter, match="direction"):
        plan_gait(curves.circle(0.05), hand, 1.0, direction="sideways")
    with pytest.raises(InvalidParameter, match="resolution"):
        plan_gait(curves.circle(0.05), hand, 1.0, resolution=3)
    with pytest.raises(InvalidParameter, match="roll_length"):
        plan_gait(curves.circle(0.05), hand, 1.0, roll_length=-1.0)


def test_min_epsilon_margin_is_respected(hand):
    g = plan_gait(curves.circle(0.05), hand, 1.0, resolution=48, min_epsilon=0.1)
    assert g.feasible, g.reason
    assert g.min_epsilon > 0.1
    assert all(p.min_epsilon > 0.1 for p in g.phases)
    with pytest.raises(InvalidParameter, match="min_epsilon"):
        plan_gait(curves.circle(0.05), hand, 1.0, min_epsilon=1.5)
