"""to_mjcf: the planar world as a MuJoCo model (skipped without the [peers] extra)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.errors import InvalidParameter
from planner.sim import to_mjcf
from planner.sim.planar.scenes import incline_scene, pinch_scene

mujoco = pytest.importorskip("mujoco")


def _load(world):
    m = mujoco.MjModel.from_xml_string(to_mjcf(world))
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    return m, d


def test_rolling_disc_in_mujoco_matches_the_closed_form():
    world, _, info = incline_scene("disc", angle=0.3, friction=0.5)
    m, d = _load(world)
    for _ in range(500):
        mujoco.mj_step(m, d)
    a = d.qvel[:2] @ info["tangent"] / d.time
    assert a == pytest.approx(-2 / 3 * 9.81 * math.sin(0.3), rel=0.01)


def test_hand_model_has_the_pinocchio_inertias_and_the_state():
    world, _, _ = pinch_scene()
    m, d = _load(world)
    assert (m.nq, m.nu) == (9, 6)
    assert np.allclose(d.qpos[:6], world.q)
    pin_masses = [world.hand.model.inertias[j].mass for j in range(1, 7)]
    link_masses = [
        m.body(f"hand.{s}_link{k}").mass[0] for s in ("left", "right") for k in (1, 2, 3)
    ]
    assert np.allclose(link_masses, pin_masses)
    assert np.allclose(m.jnt_range[:6], world.hand.limits)
    for name in ("hand.left", "hand.right", "disc"):
        assert m.geom(name).type[0] == mujoco.mjtGeom.mjGEOM_SPHERE


def test_unknown_world_is_rejected():
    with pytest.raises(InvalidParameter, match="PlanarWorld"):
        to_mjcf(object())
