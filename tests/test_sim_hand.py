"""The planar hand in the planar world: pinch hold/drop, dynamics, sensors."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

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


@pytest.mark.parametrize("gravity", [(0.0, -1.0), (-3.0, -1.0)])
def test_pinch_under_a_given_gravity_holds_what_9_81_drops(gravity):
    """The squeeze that drops the disc under 9.81 (above) holds it under a weaker or tilted
    gravity: the scene's world and its fingertip tasks use the given vector (the
    ``contact_sim`` scene presets ignored ``gravity`` until 2026-11-25)."""
    world, ctrl, info = pinch_scene(squeeze=0.4, friction=1.0, gravity=gravity)
    assert world.gravity == gravity and info["holds"]
    assert info["weight"] == pytest.approx(0.1 * math.hypot(*gravity))
    log = world.run(0.6, ctrl)
    assert [e.kind for e in log.events] == ["contact_made", "contact_made"]
    assert np.abs(log.poses["disc"][-1, :2] - log.poses["disc"][0, :2]).max() < 2e-4


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


# The real state of the ball_with_ridge gait (scenarios/ball_with_ridge.yaml, seed 0, dt = 2 ms)
# at t = 8.640 s, where the left pad's end corner was reported 9 cm "inside" the palm's end
# (an open outline's end signed by its face normal): the position projection then threw two
# joints to their limits (qd 837 rad/s) and a later projection ended on a Lemke ray.
BWR_STATE = {
    "x": [0.014384798068766516, 0.050062562102836, -0.7469486266127997],
    "v": [0.030502824679198834, 2.895917257820027e-05, -0.6092948246486284],
    "q": [0.17646861185522883, -1.6377104308833292, -0.6985628590065003,
          -0.5167687279923971, 1.5731255664292207, 1.7411055119351826],
    "qd": [-0.17429173763348346, -0.5325785888856001, 1.2371033555873772,
           -0.2493267191290444, 0.24856371396929416, 0.4339261910527247],
    "tau": [-0.012478480594639694, 0.017127563693310772, -0.00591905770875286,
            0.08984947505173566, 0.030938238374704267, 0.00503040494487441],
}  # fmt: skip


def _bwr_world():
    import dataclasses
    import math

    from planner.exploration.planar import circle_with_ridge
    from robots.planar_hand.params import HandParams, default_finger

    lo = tuple(math.radians(v) for v in (-40, 0, -10))
    hi = tuple(math.radians(v) for v in (90, 150, 130))
    right = dataclasses.replace(default_finger("right"), lower=lo, upper=hi)
    left = dataclasses.replace(
        default_finger("left"), lower=tuple(-v for v in hi), upper=tuple(-v for v in lo)
    )
    hand = PlanarHand(HandParams(left=left, right=right, friction=1.0))
    world = PlanarWorld(dt=0.002)
    world.add_hand(hand, BWR_STATE["q"], BWR_STATE["qd"])
    ball = circle_with_ridge(0.05, 0.004, 0.003, math.radians(170))
    world.add_body(ball, (0.0, 0.05, 0.0), 0.05, friction=1.0, name="object")
    world.set_state("object", pose=BWR_STATE["x"], velocity=BWR_STATE["v"])
    return world


def test_open_outline_ends_give_no_phantom_penetration():
    """A corner behind an open face but beyond its end is outside it (unsigned distance)."""
    from planner.geometry.primitives import Line
    from planner.geometry.profiles import Profile

    world = PlanarWorld(gravity=(0.0, 0.0))
    world.add_fixed(shapes.plane(0.0, 0.16), name="palm")  # y = 0, |x| <= 0.08, facing +y
    pad = Profile((Line((-0.005, 0.0), (0.005, 0.0)),), name="pad")
    # a closed body cannot be a pad: place a small box whose corner is behind the palm's
    # plane but 1 cm beyond its end, and a pad-like open fixed face the body's corner faces
    world.add_body(shapes.rounded_rectangle(0.01, 0.01, 0.0), (0.095, -0.004, 0.0), 0.01)
    world.add_fixed(pad, (0.095, -0.02, math.pi), name="pad")  # faces -y, 1 cm away
    assert world.penetrations(0.0) == []
    # a disc through the palm's end: the overlap is its centre-to-end distance minus r
    disc = PlanarWorld(gravity=(0.0, 0.0))
    disc.add_fixed(shapes.plane(0.0, 0.16), name="palm")
    disc.add_body(shapes.circle(0.008), (0.0855, -0.003, 0.0), 0.01, name="d")
    (pair,) = {(a, b): g for a, b, g in disc.penetrations()}.items()
    assert pair[1] == pytest.approx(math.hypot(0.0055, 0.003) - 0.008, abs=1e-15)


def test_gait_state_of_the_lemke_ray_steps_without_a_jump():
    world = _bwr_world()
    assert world.penetrations(1e-6) == []  # the phantom was a 9 cm "penetration"
    q0 = world.q.copy()
    for _ in range(3):  # open loop (the gait's controller would react after that)
        world.step(BWR_STATE["tau"])
        assert np.abs(world.qd).max() < 3.0  # rad/s (was 837 after one step)
    assert np.abs(world.q - q0).max() < 0.01  # [rad] in 6 ms with < 0.1 N m (was 1.6 rad)
    assert not world.penetrations(1e-6)
    kinds = {c.bodies for c in world.contacts() if c.normal_force > 0}
    assert ("hand.palm", "object") in kinds or ("object", "hand.palm") in kinds


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), gx=st.floats(-10, 10), gy=st.floats(-10, 10))
def test_closed_form_hand_dynamics_equal_pinocchio(seed, gx, gy):
    from planner.sim.planar.step_kernel import hand_dynamics, hand_kinematics, hand_parameters

    hand = PlanarHand()
    model = hand.model.copy()
    model.gravity.linear = np.array([gx, gy, 0.0])
    data = model.createData()
    P = hand_parameters(model, [hand.params.finger(f).lengths[2] for f in ("left", "right")])
    rng = np.random.default_rng(seed)
    q, qd = rng.uniform(-3, 3, 6), rng.uniform(-20, 20, 6)
    M, h = np.zeros((6, 6)), np.zeros(6)
    hand_dynamics(q, qd, gx, gy, P, M, h)
    Mp = pin.crba(model, data, q)
    Mp = np.triu(Mp) + np.triu(Mp, 1).T
    assert np.abs(M - Mp).max() <= 1e-12 * max(1.0, np.abs(Mp).max())
    hp = pin.rnea(model, data, q, qd, np.zeros(6))
    assert np.abs(h - hp).max() <= 1e-12 * max(1.0, np.abs(hp).max())
    joints, tips = np.zeros((2, 3, 2)), np.zeros((2, 3))
    hand_kinematics(q, P, joints, tips)
    for k, f in enumerate(("left", "right")):
        pose = hand.fingertip_pose(q, f)
        assert np.allclose(tips[k, :2], pose.position, rtol=0, atol=1e-15)
        assert np.allclose(joints[k], hand.finger_points(q, f)[:3], rtol=0, atol=1e-15)


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31 - 1))
def test_compiled_preset_equals_its_reference(seed):
    world, ctrl, _ = pinch_scene(squeeze=1.96, friction=1.0)
    rng = np.random.default_rng(seed)
    world.q = world.q + rng.normal(0.0, 0.1, 6)
    world.qd = rng.normal(0.0, 2.0, 6)
    obs, t = world.observe(), float(rng.uniform(0.0, 5.0))
    assert np.abs(ctrl(t, obs) - ctrl.reference(t, obs)).max() <= 1e-12


#: the state of a fuzzed gait (explore_object on a regular 5-gon of 2.55 cm at mu 3, seed
#: 363, t = 0.836 s): an object corner under the left pad's face 60 um from its end, the pad's
#: end against the next side - a wedge at mu 3
WEDGE = {
    "q": [-0.28794595110818355, -1.6450191350171137, -0.4546201472611658,
          0.13534766695130918, 2.0760816353620357, 0.6309607538400521],
    "qd": [0.22812960948283573, 0.12989801467646156, -5.900286157292609,
           2.424113759855933, -3.468718079552313, 5.447766175913548],
    "tau": [-0.15608592414159217, 0.01631290111983849, 0.036644989563028946,
            -0.04966077184958721, -0.33200819371798174, -0.12633765203784691],
    "pose": (-0.02007413840626403, 0.030596847379347814, -0.8988320769811609),
    "velocity": (-0.3440122921304133, 0.16970824419243938, -4.622426205553605),
}  # fmt: skip


def _recorded_step(profile, mu: float, state: dict, compiled: bool):
    """One step of the gait hand (friction ``mu``) and a 50 g ``profile`` from a recorded
    ``state`` (q, qd, tau, the object's pose and velocity): ``(e0, e1, bound, w)`` - the
    kinetic energy before and after [J], ``e0`` plus the work the torques and gravity can
    do in the step [J], and the object's angular velocity after [rad/s]."""
    from robots.planar_hand import gait_hand_params

    world = PlanarWorld(dt=2e-3, gravity=(0.0, -9.81), seed=0, compiled=compiled)
    world.add_hand(PlanarHand(gait_hand_params(mu)), np.array(state["q"]))
    world.qd = np.array(state["qd"])
    world.add_body(profile, state["pose"], 0.05, friction=mu, name="object")
    world.set_state("object", pose=state["pose"], velocity=state["velocity"])
    body = next(b for b in world.bodies if b.name == "object")

    def kinetic() -> float:
        M, _ = world.hand.mass_bias(world.q, world.qd)
        vx, vy, w = world._v[body.index]
        return 0.5 * (world.qd @ M @ world.qd + body.mass * (vx * vx + vy * vy)) + (
            0.5 * body.inertia * w * w
        )

    e0, y0 = kinetic(), world._x[body.index][1]
    tau = np.array(state["tau"])
    world.step(tau)
    h = world.dt
    work = abs(float(tau @ world.qd)) * h + body.mass * 9.81 * abs(world._x[body.index][1] - y0)
    gravity_hand = abs(float(world.hand.gravity(world.q) @ world.qd)) * h
    return e0, kinetic(), e0 + work + gravity_hand, float(world._v[body.index][2])


@pytest.mark.parametrize("compiled", [False, True])
def test_a_wedged_step_answer_is_refused_and_no_energy_is_added(compiled):
    """At mu 3 the step's LCP has more than one answer in a wedge (Painleve's paradox in the
    plane): Lemke found one with 376 N s impulses at a 12 um overlap left by the projection,
    whose gap term (6 mm/s) took the kinetic energy from 7 mJ to 0.94 J and spun the 50 g
    object to 201 rad/s. The stepper refuses an answer that adds more kinetic energy than
    the gap terms can (``step_kernel.gains_energy``) and closes gaps only, which cannot add
    any: the kinetic energy after the step is at most the one before plus the work of the
    torques and of gravity over the step. (At this state the compiled step's Lemke path
    happens to end on the small answer with or without the check; the Python step's ends on
    the wedged one without it: 0.94 J after the step instead of <= 0.014 J.)"""
    n = 5
    r = 0.025512646173997244
    ring = [(r * math.cos(2 * math.pi * j / n), r * math.sin(2 * math.pi * j / n))
            for j in range(n)]  # fmt: skip
    _, e1, bound, w = _recorded_step(shapes.polygon(ring[::-1]), 3.0, WEDGE, compiled)
    assert e1 <= bound + 1e-6
    assert abs(w) < 20.0  # [rad/s] (201 with the wedged answer)


#: a 2.84 cm regular 7-gon at mu 1 (explore_object, seed 687, t = 1.2 s) tumbling in phase 2:
#: one corner has come round the left pad's end and lies 25 mm behind its face
BEHIND_PAD = {
    "q": [-0.8034206881007163, 1.5829351718288365e-17, -1.7990298839669099,
          0.1689777930931553, 2.0190433654436575, 0.7128779807774684],
    "qd": [-6.239838010445408, 0.8418706347796743, 4.803577461345553,
           4.171700074719904, -7.215663083383597, 11.183989956306878],
    "tau": [-2.0, -0.3822157981523924, 0.03987341594807173,
            -0.09106189462631759, -0.07191407295196793, -0.03213599341698768],
    "pose": (-0.0013844611162508909, 0.07036237587877141, -2.7580559077753364),
    "velocity": (0.35038981633782595, 0.6665380867866744, -37.13964371779938),
}  # fmt: skip


@pytest.mark.parametrize("compiled", [False, True])
def test_a_corner_far_behind_a_pad_is_not_pushed_out_through_its_face(compiled):
    """A pad is the face of a body ``PAD_DEPTH`` (5 mm) deep: a corner 25 mm behind it has
    gone round its end and is behind the fingertip, not in it. Pushed out through the face
    (until 2026-11-25), the projection left 23 mm of it and the step's gap term, allowed by
    the energy rule at that depth, took the kinetic energy from 0.078 to 1.25 J and the
    object from 37 to 235 rad/s in one step. Without that row the step's energy gain is at
    most the torques' and gravity's work."""
    n, size, offset = 7, 0.028407344632261754, 0.3332020420704127
    ang = -0.5 * np.pi + np.pi / n - 2 * np.pi * np.arange(n) / n + offset
    profile = shapes.polygon(size * np.column_stack([np.cos(ang), np.sin(ang)]))
    e0, e1, bound, w = _recorded_step(profile, 1.0, BEHIND_PAD, compiled)
    assert e0 == pytest.approx(0.078, abs=1e-3)
    assert e1 <= bound + 1e-6
    assert abs(w) < 60.0  # [rad/s] (235 pushed out through the face)


def test_a_hand_outside_its_joint_limits_is_refused_naming_the_joint():
    """``add_hand`` accepted q = 3 rad on every joint (the audit of issue 15)."""
    from planner.errors import InvalidParameter

    hand = PlanarHand()
    lim = hand.joint_limits
    with pytest.raises(
        InvalidParameter, match=r"q\[0\]: joint left_j1 starts at 3 rad.* \(6 joint"
    ):
        PlanarWorld().add_hand(hand, np.full(6, 3.0))
    q = hand.neutral()
    q[4] = lim[4, 0] - 0.01
    with pytest.raises(
        InvalidParameter,
        match=rf"q\[4\]: joint right_j2 .* limits \[{lim[4, 0]:.6g}, {lim[4, 1]:.6g}\]",
    ):
        PlanarWorld().add_hand(hand, q)
    q[4] = lim[4, 0]  # on the limit: accepted
    assert PlanarWorld().add_hand(hand, q) == "hand"
