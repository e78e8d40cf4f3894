"""Coverage of the outline: every fingertip contact, or the exploring finger's only."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from planner.exploration.planar.metrics import coverage_mask
from planner.exploration.planar.result import PhaseRecord


def _log(angles_left, angles_right, t):
    """A log of an object at the origin touched by the left tip at ``angles_left`` and the
    right tip at ``angles_right`` (object frame [rad], one contact per row)."""
    n = len(t)
    pts = np.zeros((n, 2, 2))
    pts[:, 0] = np.c_[np.cos(angles_left), np.sin(angles_left)] * 0.05
    pts[:, 1] = np.c_[np.cos(angles_right), np.sin(angles_right)] * 0.05
    return SimpleNamespace(
        t=np.asarray(t, float),
        poses={"object": np.zeros((n, 3))},
        pairs=["hand.left|object", "hand.right|object"],
        contact_pair=np.tile([0, 1], (n, 1)),
        normal_force=np.ones((n, 2)),
        contact_point=pts,
    )


def _phase(kind, start, end):
    return PhaseRecord(kind, False, start, end, 0.0, 0.0, "path finished")


def test_strict_coverage_counts_only_the_explorer_of_each_phase():
    t = np.arange(6) * 0.1
    left = np.radians([10.5, 20.5, 30.5, 40.5, 50.5, 60.5])
    right = np.radians([100.5, 110.5, 120.5, 130.5, 140.5, 150.5])
    log = _log(left, right, t)
    phases = [_phase(1, 0.0, 0.15), _phase(2, 0.15, 0.35), _phase(3, 0.35, 0.55)]
    full = coverage_mask(log, "object", None)
    strict = coverage_mask(log, "object", None, phases=phases)
    assert np.flatnonzero(full).tolist() == [10, 20, 30, 40, 50, 60, 100, 110, 120, 130, 140, 150]
    # phase 2 (rows 2, 3): the right finger explores; phase 3 (rows 4, 5): the left one
    assert np.flatnonzero(strict).tolist() == [50, 60, 120, 130]
    assert not (strict & ~full).any()


def test_contacts_without_force_and_the_object_pose_are_respected():
    t = np.arange(2) * 0.1
    log = _log(np.radians([5.5, 5.5]), np.radians([200.5, 200.5]), t)
    log.normal_force[:, 1] = 0.0  # the right tip only grazes
    log.poses["object"][:, 2] = math.radians(90.0)  # the object turned: world 5.5 deg
    mask = coverage_mask(log, "object", None)
    assert np.flatnonzero(mask).tolist() == [275]  # 5.5 - 90 deg in the object frame
