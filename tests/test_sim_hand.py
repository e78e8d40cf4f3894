"""The planar hand in the planar world: pinch hold/drop, dynamics, sensors."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from planner.geometry import shapes
from planner.sim import PlanarWorld, SensorSettings
from planner.sim.planar.scenes import pinch_scene
from robots.planar_hand import PlanarHand


def _slip(log, world):
    mask = log.pair_mask("hand.left", "disc") | log.pair_mask("hand.right", "disc")
    return float(np.abs(np.where(mask, log.slip_velocity, 0.0)).sum() * world.dt)


def test_pinch_holds_without_creep_for_ten_seconds():
    world, ctrl, info = pinch_scene(squeeze=1.96, friction=1.0)
    assert info["holds"]
    log = world.run(10.0, ctrl)
    assert log.status == "ok"
    kinds = [e.kind for e in log.events]
    assert "object_dropped" not in kinds and "contact_lost" not in kinds
    assert _slip(log, world) <= 1e-9  # integrated slip at both contacts [m]
    # the disc moves only with the fingertips (their impedance settles), never through them
    both = (log.normal_force > 0).sum(axis=1)
    assert np.all(both[1:] == 2)
    assert np.nanmin(log.gap[1:]) >= -1e-6


def test_pinch_drops_with_an_event_below_the_friction_bound():
    world, ctrl, info = pinch_scene(squeeze=0.4, friction=1.0)  # 2 mu F = 0.8 N < m g
    assert not info["holds"]
    log = world.run(0.6, ctrl)
    kinds = [e.kind for e in log.events]
    assert "contact_lost" in kinds and "object_dropped" in kinds
    assert log.poses["disc"][-1, 1] < log.poses["disc"][0, 1] - 0.02
    mask = log.pair_mask("hand.left", "disc")
    sliding = mask & (np.abs(log.slip_velocity) > 1e-6) & (log.normal_force > 0)
    ratio = np.abs(log.tangential_force[sliding]) / log.normal_force[sliding]
    assert ratio.size and np.allclose(ratio, 1.0, rtol=1e-9)  # mu f_n while sliding


def test_hand_dynamics_equal_pinocchio():
    world, _, _ = pinch_scene()
    q = world.q + 0.1
    qd = np.linspace(-1, 1, 6)
    M, h = world.hand.mass_bias(q, qd)
    model = world.hand.model
    data = model.createData()
    assert np.allclose(M, M.T)
    C = np.array(pin.crba(model, data, q))
    assert np.allclose(M, np.triu(C) + np.triu(C, 1).T)
    assert np.allclose(h, pin.rnea(model, data, q, qd, np.zeros(6)))
    assert np.allclose(world.hand.gravity(q), pin.computeGeneralizedGravity(model, data, q))
    # gravity acts in the hand plane: -y
    assert np.allclose(model.gravity.linear, [0.0, -9.81, 0.0])
    joints, tips = world.hand.frames(q)
    pos = world.hand.hand.fingertip_positions(q)
    assert np.allclose(tips[0][:2], pos["left"]) and np.allclose(tips[1][:2], pos["right"])


def test_joint_limit_is_a_unilateral_constraint_with_an_event():
    hand = PlanarHand()
    world = PlanarWorld(sensors=SensorSettings.ideal())
    q = np.array([0.5, -0.3, -0.8, -0.5, 0.3, 0.8])  # fingers spread apart
    world.add_hand(hand, q, palm=False)
    assert not world.penetrations()
    lo = hand.joint_limits[2, 0]
    tau = np.zeros(6)
    tau[2] = -0.3  # push left joint 3 toward its lower limit
    log = world.run(1.0, lambda t, obs: tau + world.hand.gravity(obs.q))
    assert any(e.kind == "joint_limit" and e.data["joint"] == 2 for e in log.events)
    assert log.q[:, 2].min() >= lo - 1e-6
    assert log.q[-1, 2] == pytest.approx(lo, abs=1e-6)


def test_torque_saturation_is_an_event_and_clips():
    world, _, _ = pinch_scene()
    log = world.run(0.01, lambda t, obs: np.full(6, 10.0))
    assert [e.kind for e in log.events].count("torque_saturated") == 1
    assert np.max(np.abs(log.tau)) <= 2.0


def test_observation_is_quantized_and_seeded():
    def obs_of(seed):
        world, ctrl, _ = pinch_scene(seed=seed)
        world.run(0.01, ctrl)
        return world, world.observe()

    w1, o1 = obs_of(1)
    _, o1b = obs_of(1)
    _, o2 = obs_of(2)
    res = w1.sensors.encoder.resolution
    assert np.allclose(o1.q / res, np.round(o1.q / res))
    assert np.all(np.abs(o1.q - w1.q) <= res + 1e-12)
    assert np.array_equal(o1.tip_forces, o1b.tip_forces)  # same seed, same noise
    assert not np.array_equal(o1.tip_forces, o2.tip_forces)  # noise differs
    assert o1.truth is None and w1.observe(oracle=True).truth["q"] is not None
    # the gauges read the squeeze: left pushes +x, right pushes -x (within noise)
    assert o1.tip_force("left")[0] == pytest.approx(1.96, abs=0.2)
    assert o1.tip_force("right")[0] == pytest.approx(-1.96, abs=0.2)


def test_flat_pad_tactile_image_integrates_to_the_contact_force():
    hand = PlanarHand()  # flat left pad
    world = PlanarWorld()
    q = np.array([0.5, -0.3, -0.8, -0.5, 0.3, 0.8])
    world.add_hand(hand, q, palm=False)
    pose = hand.fingertip_pose(q, "left")
    c = pose.position + 0.03 * pose.axis  # a disc resting on the pad's outward side
    world.add_body(shapes.circle(0.03), (c[0], c[1], 0.0), 0.05, name="disc")
    g = world.gravity
    world.gravity = (0.0, 0.0)
    world.set_state("disc", velocity=(*(-0.05 * pose.axis), 0.0))
    world.gravity = g
    hold = world.hand.gravity(q)
    world.run(0.01, lambda t, obs: hold)
    obs = world.observe()
    img = obs.tactile["left"]
    arr = world.sensors.tactile
    assert img.shape == (8, 8) and img.sum() > 0
    fn = sum(c.normal_force for c in world.contacts() if "disc" in c.bodies)
    assert img.sum() * arr.pitch**2 == pytest.approx(fn, rel=0.05)
