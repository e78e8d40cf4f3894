"""MJCF export of the spatial world: MuJoCo loads the same scene."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.errors import HapexError
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


def test_mujoco_ridge_rollout_measures_the_same_quantities():
    """The peer runs the same scene and controller; its path is measured like ours."""
    from planner.sim.spatial.mujoco_peer import mujoco_ridge_rollout
    from planner.sim.spatial.scenes import centre_path_error, path_error

    r = mujoco_ridge_rollout(ridge_slide_scene(speed=0.02, travel=0.004), "best")
    assert r["status"] in ("ok", "did not cross the ridge")
    assert r["steps_per_s"] > 0 and r["rms"] > 0 and r["max"] >= r["rms"]
    assert r["penetration_max"] > 0  # soft contact: MuJoCo lets the tip sink in
    sc = ridge_slide_scene(speed=0.02, travel=0.004)
    log = sc.world.run(sc.duration, sc.controller)
    a = centre_path_error(sc, log)
    b = path_error(sc, log.poses["finger"][:, :3], log.normal_force[:, 0] > 0)
    assert (a.rms, a.max, a.lost_steps) == (b.rms, b.max, b.lost_steps)
    with pytest.raises(HapexError, match="settings"):
        mujoco_ridge_rollout(sc, "fastest")


def test_mujoco_model_settings_are_checked_and_best_is_stiffer():
    from planner.errors import InvalidParameter
    from planner.sim import PlanarWorld
    from planner.sim.mjcf import MUJOCO_SETTINGS, mujoco_model

    world = PlanarWorld(dt=1e-3)
    with pytest.raises(InvalidParameter, match="settings: 'fast'; choices"):
        mujoco_model(world, "fast")
    pytest.importorskip("mujoco")
    assert set(MUJOCO_SETTINGS) == {"default", "best"}
    _, m, _ = mujoco_model(world, "best")
    assert m.opt.impratio == 100.0 and m.opt.noslip_iterations == 20


@pytest.mark.parametrize(("mu_surface", "mu_ball"), [(0.2, 0.5), (0.5, 0.2)])
def test_a_pair_takes_the_larger_friction_here_and_in_the_export(mu_surface, mu_ball):
    # a ball launched without spin slides until it rolls (t = 2 v0 / (7 mu g) = 58 ms at
    # mu 0.5): over the first 20 ms it decelerates at mu g with mu the larger coefficient,
    # MuJoCo's rule; until 2026-11-25 the spatial world took the smaller one
    w = SpatialWorld()
    w.add_surface(Plane.tilted(0.0), friction=mu_surface, name="p")
    b = w.add_sphere(0.01, 0.1, (0.0, 0.0, 0.01), velocity=(1.0, 0.0, 0.0), friction=mu_ball)
    m, d = _load(w)
    log = w.run(0.02)
    ours = (1.0 - log.velocities[b][-1, 0]) / log.t[-1] / 9.81
    assert ours == pytest.approx(0.5, rel=1e-9)
    steps = round(0.02 / m.opt.timestep)
    for _ in range(steps):
        mujoco.mj_step(m, d)
    theirs = (1.0 - d.qvel[0]) / (steps * m.opt.timestep) / 9.81
    assert theirs == pytest.approx(0.5, rel=0.05)  # MuJoCo's soft contact: a few percent
