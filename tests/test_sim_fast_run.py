"""The planar world's compiled run loop gives the reference loop's log, to the bit.

``world.run(...)`` (``loop="auto"``: :mod:`planner.sim.planar.fast_run`) against
``world.run(..., loop="python")`` (one Python iteration per step, the same compiled step) on
the bundled scenes, with the preset controller in the kernel and with Python controllers
(every step, at a lower rate, with a ``stop`` callback), and against the all-Python
reference (``compiled=False``) to round-off.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.geometry import shapes
from planner.sim import PlanarWorld, SensorSettings
from planner.sim.planar import scenes

SCENES = {
    "pinch": lambda **kw: scenes.pinch_scene(squeeze=1.96, friction=1.0, **kw),
    "pinch_drop": lambda **kw: scenes.pinch_scene(squeeze=0.2, friction=0.3, **kw),
    "palm_roll": scenes.palm_roll_scene,
    "hold_slide": scenes.palm_hold_slide_scene,
    "incline_box": lambda **kw: scenes.incline_scene("box", angle=0.6, friction=0.5),
    "incline_disc": lambda **kw: scenes.incline_scene("disc", angle=0.3, friction=0.4),
}


def _events(log):
    return [(e.t, e.kind, e.message, e.data) for e in log.events]


def assert_same_log(a, b, atol: float = 0.0) -> None:
    """Every array of two logs equal (bit for bit with atol = 0), same events and status."""
    xa, xb = a.arrays(), b.arrays()
    assert xa.keys() == xb.keys()
    for key, va in xa.items():
        vb = xb[key]
        assert va.shape == vb.shape, key
        if va.dtype.kind == "f" and atol > 0:
            np.testing.assert_allclose(va, vb, rtol=0, atol=atol, err_msg=key)
        else:
            np.testing.assert_array_equal(va, vb, err_msg=key)
    if atol == 0:
        assert _events(a) == _events(b)
    else:
        assert [(e.kind, e.message) for e in a.events] == [(e.kind, e.message) for e in b.events]
        np.testing.assert_allclose([e.t for e in a.events], [e.t for e in b.events], atol=1e-12)
    assert (a.status, a.reason) == (b.status, b.reason)


@pytest.mark.parametrize("name", sorted(SCENES))
def test_preset_scenes_equal_the_reference_loop(name):
    logs, draws = [], []
    for loop in ("auto", "python"):
        world, ctrl, _ = SCENES[name]()
        logs.append(world.run(0.4, ctrl, loop=loop))
        draws.append(world.rng.random())  # the generator advanced by the same draws
        assert world.time == logs[-1].t[-1]
    assert_same_log(*logs)
    assert draws[0] == draws[1]
    assert logs[0].events, "the scenes make contact: events are compared"


def test_world_state_after_a_compiled_run_continues_like_the_reference():
    """Run, then step by step: the world's bookkeeping (touches, limits, active pairs, the
    last step's contacts) is handed back, so a second run continues identically."""
    out = []
    for loop in ("auto", "python"):
        world, ctrl, _ = SCENES["pinch_drop"]()
        world.run(0.06, ctrl, loop=loop)  # touched, not yet dropped
        contacts = [(c.bodies, c.normal_force, c.gap) for c in world.contacts()]
        second = world.run(0.3, ctrl, loop=loop)
        out.append((contacts, second, world._touch, world._dropped, world._limits_on))
    assert out[0][0] == out[1][0]
    assert_same_log(out[0][1], out[1][1])
    assert out[0][2:] == out[1][2:]
    assert "object_dropped" in [e.kind for e in out[0][1].events]


def _recorded_hand_world():
    """The flat-pad hand of the gait's regression recording at a recorded mid-gait posture
    (``tests/data/gait_controller_replay.pkl.gz``), a ball dropped on its palm."""
    import gait_replay

    data = gait_replay.load()
    hand = gait_replay.make_controller(data).hand
    call = data["windows"][3]["calls"][0]
    q = np.asarray(call["obs"]["q"], float)
    world = PlanarWorld(seed=7)
    world.add_hand(hand, q)
    r = 0.02
    world.add_body(shapes.circle(r), (0.0, r + 2e-3, 0.0), 0.05, friction=0.8, name="ball")
    assert not world.penetrations()
    return world, q, np.asarray(call["tau"], float)


class _PD:
    """A Python controller that reads every sensor (encoders, gauges, tactile images)."""

    def __init__(self, q_ref, tau_ff):
        self.q_ref, self.tau_ff, self.seen = q_ref, tau_ff, []

    def __call__(self, t, obs):
        tactile = {k: float(v.sum()) for k, v in obs.tactile.items()}
        self.seen.append((t, obs.q.copy(), obs.qd.copy(), obs.tip_forces.copy(), tactile))
        return 0.5 * self.tau_ff + 0.05 * (self.q_ref - obs.q) - 0.002 * obs.qd


@pytest.mark.parametrize("rate, stop_at", [(1000.0, None), (300.0, None), (1000.0, 0.2)])
def test_python_controllers_equal_the_reference_loop(rate, stop_at):
    runs = []
    for loop in ("auto", "python"):
        world, q, tau = _recorded_hand_world()
        ctrl = _PD(q, tau)
        stop = None if stop_at is None else (lambda t, w: "enough" if t > stop_at else None)
        log = world.run(0.3, ctrl, control_rate=rate, stop=stop, loop=loop)
        runs.append((log, ctrl.seen, world.rng.random()))
    (la, sa, ra), (lb, sb, rb) = runs
    assert_same_log(la, lb)
    assert ra == rb and len(sa) == len(sb)
    for x, y in zip(sa, sb, strict=True):
        assert x[0] == y[0] and x[4] == y[4]
        for u, v in zip(x[1:4], y[1:4], strict=True):
            np.testing.assert_array_equal(u, v)
    if stop_at is not None:
        assert la.reason == "enough" and la.t[-1] == pytest.approx(stop_at, abs=2e-3)
    assert "contact_made" in [e.kind for e in la.events]


@pytest.mark.parametrize("name", ["pinch", "hold_slide", "incline_disc"])
def test_compiled_loop_equals_the_python_reference_to_round_off(name):
    """The compiled loop against ``compiled=False`` (Python step, Python loop)."""
    world, ctrl, _ = SCENES[name]()
    fast = world.run(0.1, ctrl)
    world, ctrl, _ = SCENES[name]()
    world.compiled = False
    ref = world.run(0.1, ctrl)
    assert_same_log(fast, ref, atol=1e-9)


def test_faults_inside_the_compiled_loop():
    """Blow-up, a bad command and a saturating preset end or mark the run as the loop does."""
    world = PlanarWorld(gravity=(0.0, 0.0), sensors=SensorSettings.ideal())
    world.add_body(shapes.circle(0.01), (0, 0, 0), 1.0, velocity=(2e3, 0, 0), name="b")
    a = world.run(0.1)
    world = PlanarWorld(gravity=(0.0, 0.0), sensors=SensorSettings.ideal())
    world.add_body(shapes.circle(0.01), (0, 0, 0), 1.0, velocity=(2e3, 0, 0), name="b")
    b = world.run(0.1, loop="python")
    assert_same_log(a, b)
    assert a.status == "failed" and [e.kind for e in a.events][-2:] == ["blow_up", "stopped"]
    logs = []
    for loop in ("auto", "python"):
        world, ctrl, _ = scenes.pinch_scene(squeeze=40.0)  # beyond the joints' torque limits
        logs.append(world.run(0.05, ctrl, loop=loop))
    assert_same_log(*logs)
    assert "torque_saturated" in [e.kind for e in logs[0].events]


def test_stop_is_checked_after_every_step():
    world, ctrl, _ = scenes.pinch_scene()
    log = world.run(1.0, ctrl, stop=lambda t, w: "t" if t >= 0.0105 else None)
    assert log.reason == "t" and math.isclose(log.t[-1], 0.011, abs_tol=1e-12)


def test_compiled_observation_equals_the_sensor_models():
    """The observation's compiled reading is :func:`read_joints` and the gauges' measure."""
    import copy

    from planner.sim.observation import read_forces, read_joints
    from planner.sim.planar.sensing import _read, _true_tip_forces

    world, ctrl, _ = SCENES["hold_slide"]()
    world.run(0.05, ctrl)
    world.qd[:] = np.linspace(-0.3, 0.4, 6)  # away from zero: the velocity quantization acts
    rng = copy.deepcopy(world.rng)
    q, qd, f = _read(world)
    q_ref, qd_ref = read_joints(world.sensors, world.q, world.qd)
    f_ref = read_forces(world.sensors, _true_tip_forces(world), rng)
    np.testing.assert_array_equal(q, q_ref)
    np.testing.assert_array_equal(qd, qd_ref)
    np.testing.assert_array_equal(f, f_ref)
    assert np.abs(f).max() > 0.1 and world.rng.random() == rng.random()


def test_python_controller_on_a_world_without_hand():
    logs, calls = [], []
    for loop in ("auto", "python"):
        world, _, _ = SCENES["incline_disc"]()
        seen = []
        logs.append(world.run(0.05, lambda t, obs, s=seen: s.append(t), 500.0, loop=loop))
        calls.append(seen)
    assert_same_log(*logs)
    assert calls[0] == calls[1] and len(calls[0]) == 25


def test_other_sensor_models_are_read_from_python():
    """A preset with a sensor model the kernel does not know runs as a Python controller."""
    from robots.sensors import Encoder

    class CoarseEncoder(Encoder):
        def measure(self, angle):
            return np.round(np.asarray(angle, float) / self.resolution) * self.resolution

    sensors = SensorSettings(encoder=CoarseEncoder(resolution=0.01))
    logs = []
    for loop in ("auto", "python"):
        world, ctrl, _ = scenes.pinch_scene(sensors=sensors)
        logs.append(world.run(0.1, ctrl, loop=loop))
    assert_same_log(*logs)


def test_loop_choice_is_checked_and_chunks_keep_the_progress_bar():
    from planner.errors import InvalidParameter

    world, ctrl, _ = SCENES["pinch"]()
    with pytest.raises(InvalidParameter, match="loop"):
        world.run(0.1, ctrl, loop="numba")
    log = world.run(1.2, ctrl, progress=True)  # more than one chunk of the compiled loop
    assert len(log.t) == 1201 and log.status == "ok"


def test_many_bodies():
    """A pile of discs (event buffer sized by the bodies, many pairs, contact events)."""
    logs = []
    for loop in ("auto", "python"):
        world = PlanarWorld(sensors=SensorSettings.ideal())
        world.add_fixed(shapes.plane(0.0, 1.0), friction=0.5, name="floor")
        for k in range(12):
            x, y = 0.021 * (k % 4) - 0.03, 0.011 + 0.025 * (k // 4)
            world.add_body(shapes.circle(0.01), (x, y, 0.0), 0.01, friction=0.5)
        logs.append(world.run(0.15, loop=loop))
    assert_same_log(*logs)
    assert [e.kind for e in logs[0].events].count("contact_made") >= 12


@pytest.mark.parametrize("loop", ["auto", "python"])
def test_a_jam_after_a_compiled_run_is_a_new_jammed_event(loop, monkeypatch):
    """A jam (position projection that cannot remove every penetration) is reported once
    when it begins. The compiled kernel's steps never jam (it hands every projection back
    to Python), so a jam in a Python step after a compiled run begins anew: a second
    ``jammed`` event, as in the reference loop (the compiled loop used to keep the first
    jam's state and miss it). The jam is forced on chosen Python steps."""
    import planner.sim.planar.world as world_module

    forced = {"on": False}
    real = world_module.step_fast

    def jamming_step(world, tau):
        res = real(world, tau)
        if forced["on"]:
            world.jam = 1e-3
        return res

    monkeypatch.setattr(world_module, "step_fast", jamming_step)
    world, ctrl, _ = SCENES["pinch"]()
    kinds = []
    for _ in range(2):
        forced["on"] = True
        world.step()
        kinds += [e.kind for e in world.drain_events()]
        forced["on"] = False
        log = world.run(0.05, ctrl, loop=loop)
        kinds += [e.kind for e in log.events]
    assert kinds.count("jammed") == 2
