"""The executor with a round left tip (no tactile array): the hand the map-space study
(``benchmarks/bench_gait_hands.py``) found to turn rounded squares. On the 10 cm ball it
runs the same cycle as the thesis' flat pad: phase 1 rolls the ball clockwise on both round
tips, phases 2/3 hold it and move one tip each."""

from __future__ import annotations

import math

import pytest

from planner.exploration import explore_object
from planner.exploration.planar.settings import GaitSettings
from planner.geometry import shapes


@pytest.fixture(scope="module")
def run():
    from robots.planar_hand import PlanarHand, gait_hand_params

    hand = PlanarHand(gait_hand_params(1.0, left_tip_radius=0.025))
    return explore_object(shapes.circle(0.05), hand=hand, mu=1.0, duration=4.0,
                          settings=GaitSettings(mu=1.0), use_prior=False)  # fmt: skip


def test_the_ball_turns_through_the_three_phases(run):
    assert run.status == "ok", run.reason
    assert [p.kind for p in run.phases[:4]] == [1, 2, 3, 1]
    ones = [p for p in run.phases if p.kind == 1 and p.event == "path finished"]
    assert ones and all(p.rotation < -math.radians(20) for p in ones)
    assert run.rotation < -math.radians(45)


def test_phases_2_and_3_hold_the_ball(run):
    """The holding round tip and the palm keep the ball: each of phases 2/3 turns it by
    less than 3 deg (the explorer's friction drags it)."""
    for p in run.phases:
        if p.kind in (2, 3):
            assert abs(p.rotation) < math.radians(3), p
