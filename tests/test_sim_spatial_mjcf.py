"""MJCF export of the spatial world: MuJoCo loads the same scene."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.sim.spatial import Plane, SpatialWorld
from planner.sim.spatial.mjcf import spatial_to_mjcf
from planner.sim.spatial.scenes import ridge_slide_scene

mujoco = pytest.importorskip("mujoco")


def _load(world):
    m = mujoco.MjModel.from_xml_string(spatial_to_mjcf(world))
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    mujoco.mj_forward(m, d)
    return m, d


def test_3gm_and_plate_export_match_the_world():
    sc = ridge_slide_scene()
    m, d = _load(sc.world)
    np.testing.assert_allclose(d.site("finger_tip").xpos, sc.world.pose("finger")[:3], atol=1e-12)
    gap = d.site("finger_closure_a").xpos - d.site("finger_closure_b").xpos
    assert np.linalg.norm(gap) <= 1e-12  # the loop is closed in the keyframe
    assert m.nu == 3 and m.neq == 1 and m.nhfield == 1
    np.testing.assert_allclose(m.actuator_ctrlrange[:, 1], sc.world.torque_limits)
    # link masses and the fingertip: MuJoCo's total mass equals Pinocchio's
    total = sum(Y.mass for Y in sc.world.finger.gm.model.inertias)
    assert float(np.sum(m.body_mass)) == pytest.approx(total, abs=1e-5)


def test_ball_on_exported_incline_rolls_like_ours():
    a = math.radians(25.0)
    w = SpatialWorld()
    w.add_surface(Plane.tilted(a), friction=0.5)
    n = np.array([math.sin(a), 0.0, math.cos(a)])
    w.add_sphere(0.01, 0.1, n * 0.01)
    m, d = _load(w)
    np.testing.assert_allclose(d.qpos[:3], n * 0.01)
    for _ in range(500):
        mujoco.mj_step(m, d)
    down = np.array([math.cos(a), 0.0, -math.sin(a)])
    s = (d.qpos[:3] - n * 0.01) @ down
    expected = 0.5 * 5 / 7 * 9.81 * math.sin(a) * 0.25
    assert s == pytest.approx(expected, rel=0.03)  # MuJoCo's soft contact: a few percent
