"""The executed gait's default hand (robots.planar_hand.gait_hand_params)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from planner.errors import InvalidParameter
from planner.exploration import explore_object
from planner.geometry import shapes
from planner.kinds.gait import HandConfig
from robots.planar_hand import (
    GAIT_LOWER_DEG,
    GAIT_UPPER_DEG,
    PlanarHand,
    default_finger,
    gait_hand_params,
    ranged_hand_params,
)


def test_ranged_hand_mirrors_the_left_finger_and_keeps_the_geometry():
    p = ranged_hand_params((-30.0, 5.0, -20.0), (80.0, 140.0, 120.0), friction=0.7)
    assert np.allclose(np.rad2deg(p.right.lower), (-30, 5, -20))
    assert np.allclose(np.rad2deg(p.right.upper), (80, 140, 120))
    # the left finger is the mirror image: its range is the negated, swapped right one
    assert np.allclose(p.left.lower, -np.asarray(p.right.upper))
    assert np.allclose(p.left.upper, -np.asarray(p.right.lower))
    assert p.friction == 0.7
    for side, f in (("left", p.left), ("right", p.right)):
        d = default_finger(side)
        assert (f.base, f.lengths, f.tip, f.tip_radius) == (d.base, d.lengths, d.tip, d.tip_radius)


def test_ranged_hand_rejects_bad_ranges_and_friction():
    with pytest.raises(InvalidParameter, match="friction"):
        gait_hand_params(-0.1)
    with pytest.raises(InvalidParameter, match="lower < upper"):
        ranged_hand_params((10.0, 0.0, 0.0), (5.0, 90.0, 90.0))
    with pytest.raises(InvalidParameter, match="3 pairs"):
        ranged_hand_params((0.0, 0.0), (90.0, 90.0, 90.0))


def test_a_round_left_tip_changes_the_left_tip_only():
    """``left_tip_radius``: the same hand with a round left tip of that radius (the pad's
    joint ranges, base and links kept); the scenario's ``hand.left_tip_radius`` builds it."""
    pad = ranged_hand_params((-30.0, 5.0, -20.0), (80.0, 140.0, 120.0), 0.7)
    tip = ranged_hand_params((-30.0, 5.0, -20.0), (80.0, 140.0, 120.0), 0.7, 0.015)
    assert (tip.left.tip, tip.left.tip_radius, tip.left.round_radius) == ("round", 0.015, 0.015)
    assert pad.left.round_radius == 0.0
    assert tip == replace(pad, left=replace(pad.left, tip="round", tip_radius=0.015))
    assert gait_hand_params(1.0, 0.025) == replace(
        gait_hand_params(1.0), left=replace(gait_hand_params(1.0).left, tip="round")
    )
    assert (
        HandConfig(left_tip_radius=0.02).hand(1.0).params
        == PlanarHand(gait_hand_params(1.0, 0.02)).params
    )
    for bad in (0.0, -0.01, float("nan")):
        with pytest.raises(InvalidParameter, match="left_tip_radius"):
            gait_hand_params(1.0, bad)


def test_scenario_default_and_library_default_are_the_gait_hand():
    assert HandConfig().joint_lower_deg == GAIT_LOWER_DEG
    assert HandConfig().joint_upper_deg == GAIT_UPPER_DEG
    assert HandConfig().hand(1.0).params == PlanarHand(gait_hand_params(1.0)).params
    # wider than the thesis' 110 deg fingers in every joint, same lower stops
    thesis = default_finger("right")
    assert gait_hand_params().right.lower == pytest.approx(thesis.lower)
    assert all(g > t for g, t in zip(gait_hand_params().right.upper, thesis.upper, strict=True))


def test_the_default_call_turns_a_plain_disc():
    # explore_object(profile) with every default: two phase-1 rotations in 5 s; the thesis'
    # 110 deg hand stalled here (-32 deg in 10 s, every phase 1 at a joint stop)
    r = explore_object(shapes.circle(0.05), duration=5.0)
    assert r.status == "ok", r.reason
    turns = [p.rotation for p in r.phases if p.kind == 1]
    assert len(turns) >= 2 and all(t < -math.radians(15) for t in turns)
    assert r.rotation < -math.radians(40)
