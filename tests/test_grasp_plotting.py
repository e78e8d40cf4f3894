"""Grasp figures (planner.grasp.plotting): what they draw is drawn in one frame."""

from __future__ import annotations

import numpy as np
import pytest

from planner.geometry import curves
from planner.grasp.gait import gait_problem, search_gait
from planner.grasp.maps import grasp_map, profile_contacts
from planner.grasp.plotting import (
    finger_configuration,
    phase_segment,
    plot_gait_map,
    plot_gait_phases,
    plot_grasp_map,
)
from planner.grasp.workspace import HandReachability, rotation, workspace_tables


@pytest.fixture(scope="module")
def setup():
    from robots.planar_hand import PlanarHand

    hand = PlanarHand()
    reach = HandReachability(hand)
    profile = curves.circle(0.05)
    prob = gait_problem(profile, reach, 1.0, resolution=48)
    gait = search_gait(prob)
    assert gait.feasible, gait.reason
    return hand, reach, profile, prob, gait


def test_grasp_map_marks_only_the_gait_grasps_of_the_drawn_pose(setup):
    # regression: the gait over a full turn was drawn over the workspace of pose 0 only
    hand, reach, profile, prob, gait = setup
    g = grasp_map(profile, 1.0, 48)
    ws = workspace_tables(profile, reach, g.theta, [0.0], 0.0)
    fig = plot_grasp_map(g, ws, gait)
    red = [ln for ln in fig.axes[0].lines if ln.get_color() == "tab:red"]
    expected = gait.path[(gait.path[:, 0] == 0) & (gait.path[:, 1] >= 0) & (gait.path[:, 2] >= 0)]
    assert sum(len(ln.get_xdata()) for ln in red) == len(expected)
    # every marked grasp is reachable by both fingers at pose 0 (same frame as the regions)
    for _, i, j in expected:
        assert prob.reach["left"][0][i] and prob.reach["right"][0][j]


def test_phase_segments_join_the_phases_start_and_end(setup):
    _, _, _, prob, gait = setup
    step = 360.0 / prob.theta.size
    for ph in gait.phases:
        seg = phase_segment(ph, prob.sign, step)
        start = np.rad2deg([ph.start["left"], ph.start["right"]])
        end = np.rad2deg([ph.end["left"], ph.end["right"]])
        assert np.allclose(np.mod(seg[0] - start + 180, 360) - 180, 0, atol=1e-9)
        assert np.allclose(np.mod(seg[-1] - end + 180, 360) - 180, 0, atol=1e-9)
    fig = plot_gait_map(prob, gait, max_phases=4)
    assert len(fig.axes) == min(4, len(gait.phases))


def test_finger_configuration_touches_the_object(setup):
    hand, _, profile, prob, gait = setup
    ph = gait.phases[0]
    R, t = (
        rotation(prob.tables.placement.angles[ph.pose_end]),
        prob.tables.placement.offsets[ph.pose_end],
    )
    for finger in ("left", "right"):
        p, n_in = profile_contacts(profile, [ph.end[finger]])
        c, u = (p @ R.T + t)[0], -(n_in @ R.T)[0]
        qf = finger_configuration(hand, finger, c, u)
        assert qf is not None
        q = np.zeros(6)
        q[hand.finger_slice(finger)] = qf
        pose, f = hand.fingertip_pose(q, finger), hand.params.finger(finger)
        if f.tip == "round":  # the tip circle passes through the contact, centre outside
            assert np.linalg.norm(pose.position - c) == pytest.approx(f.tip_radius, abs=1e-9)
            assert (pose.position - c) @ u > 0
        else:  # the pad faces the object and the contact lies on it
            assert np.allclose(pose.axis, -u, atol=1e-9)
            assert abs((c - pose.position) @ pose.axis) < 1e-9
            assert np.linalg.norm(c - pose.position) <= f.pad_half_width + 1e-12


def test_gait_phases_draws_the_fingers(setup):
    # regression: gait_phases.png showed contact dots but no fingers
    hand, _, profile, prob, gait = setup
    fig = plot_gait_phases(profile, gait, prob, hand=hand)
    for ax in fig.axes:
        links = [ln for ln in ax.lines if len(ln.get_xdata()) == 4]  # base, 2 joints, tip
        assert len(links) == 2
    bare = plot_gait_phases(profile, gait, prob)
    assert all(not [ln for ln in ax.lines if len(ln.get_xdata()) == 4] for ax in bare.axes)
