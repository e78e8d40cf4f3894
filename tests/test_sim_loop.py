"""The shared run loop: control rate, zero-order hold, events, every fault path, the log."""

from __future__ import annotations

import json

import numpy as np
import pytest

from planner.errors import ContactLost, InvalidParameter
from planner.geometry import shapes
from planner.sim import PlanarWorld, SensorSettings, run
from planner.sim.planar.scenes import pinch_scene


def _free_world(**kw):
    world = PlanarWorld(sensors=SensorSettings.ideal(), **kw)
    world.add_fixed(shapes.plane(0.0, 1.0), friction=0.5, name="floor")
    world.add_body(shapes.circle(0.01), (0.0, 0.03, 0.0), 0.1, name="ball")
    return world


def test_controller_runs_at_its_rate_with_zero_order_hold():
    world, _, _ = pinch_scene()
    calls = []

    def ctrl(t, obs):
        calls.append(t)
        return np.full(6, 0.001 * len(calls))

    log = world.run(0.05, ctrl, control_rate=200.0)
    assert len(calls) == 10
    assert np.allclose(np.diff(calls), 0.005)
    # torques change only at control instants and are held in between
    changes = np.flatnonzero(np.any(np.diff(log.tau[:-1], axis=0) != 0, axis=1)) + 1
    assert np.allclose(log.t[changes] % 0.005, 0.0, atol=1e-9) or np.allclose(
        (log.t[changes] % 0.005) - 0.005, 0.0, atol=1e-9
    )


def test_contact_events_and_landing():
    world = _free_world()
    log = world.run(0.2)
    kinds = [e.kind for e in log.events]
    assert kinds.count("contact_made") == 1
    made = next(e for e in log.events if e.kind == "contact_made")
    assert "ball" in made.message and "floor" in made.message
    assert 0.05 < made.t < 0.1  # free fall of 2 cm: t = sqrt(2 * 0.02 / g) = 0.064 s
    assert log.status == "ok" and log.reason == ""


def test_controller_error_stops_cleanly():
    world, _, _ = pinch_scene()

    def ctrl(t, obs):
        if t > 0.005:
            raise ContactLost("lost the disc")
        return np.zeros(6)

    log = world.run(0.1, ctrl)
    assert log.status == "failed" and "lost the disc" in log.reason
    assert log.events[-1].kind == "stopped"
    assert log.t[-1] < 0.01 and len(log.t) == len(log.q)


@pytest.mark.parametrize(
    "bad, what",
    [(np.zeros(5), "shape"), (np.full(6, np.nan), "non-finite")],
)
def test_bad_controller_output_stops_cleanly(bad, what):
    world, _, _ = pinch_scene()
    log = world.run(0.1, lambda t, obs: bad)
    assert log.status == "failed" and what in log.reason


@pytest.mark.parametrize("bad", ["abc", ["a"] * 6, {"tau": 0}, object(), [True] * 6, [[1, 2], [3]]])
@pytest.mark.parametrize("loop", ["auto", "python"])
def test_non_numeric_controller_output_stops_cleanly(bad, loop):
    """A string, a list of strings, a dict, an object (each a crash escaping ``run`` until
    2026-11-25), booleans or a ragged list: ``stopped``, status "failed", in both loops."""
    world, _, _ = pinch_scene()
    log = world.run(0.01, lambda t, obs: bad, loop=loop)
    assert log.status == "failed" and "non-numeric command" in log.reason
    assert log.events[-1].kind == "stopped" and log.events[-1].message == log.reason
    assert len(log.t) == 1


def test_non_numeric_controller_output_stops_a_spatial_run():
    from planner.sim.spatial.scenes import ridge_slide_scene

    sc = ridge_slide_scene(travel=0.002)
    log = sc.world.run(0.01, lambda t, obs: "abc")
    assert log.status == "failed" and "non-numeric command 'abc'" in log.reason
    assert log.events[-1].kind == "stopped"


def test_blow_up_guard():
    world = PlanarWorld(gravity=(0.0, 0.0), sensors=SensorSettings.ideal())
    world.add_body(shapes.circle(0.01), (0, 0, 0), 1.0, velocity=(2e3, 0, 0), name="b")
    log = world.run(0.1)
    assert log.status == "failed" and "runaway" in log.reason
    assert log.reason.endswith("(b, component 0)")  # which coordinate ran away
    assert [e.kind for e in log.events][-2:] == ["blow_up", "stopped"]
    world._v[0, 0] = np.nan  # corrupt the state on purpose
    log = world.run(0.1)
    assert log.status == "failed" and "non-finite" in log.reason


def test_user_stop_is_clean():
    world = _free_world()
    log = world.run(1.0, stop=lambda t, w: "landed" if w.contacts() else None)
    assert log.status == "ok" and log.reason == "landed"
    assert log.events[-1].kind == "stopped" and log.t[-1] < 0.5


def test_save_npz_round_trip(tmp_path):
    world = _free_world()
    log = world.run(0.1, progress=False)
    path = log.save_npz(tmp_path / "run.npz")
    data = np.load(path)
    assert np.array_equal(data["t"], log.t)
    assert np.array_equal(data["pose/ball"], log.poses["ball"])
    events = json.loads(str(data["events"]))
    assert events[0]["kind"] == "contact_made"
    assert str(data["status"]) == "ok"


def test_progress_bar_runs():
    world = _free_world()
    log = world.run(0.2, progress=True)
    assert len(log.t) == 201


def test_bad_run_arguments():
    world = _free_world()
    with pytest.raises(InvalidParameter, match="duration"):
        run(world, -1.0)
    with pytest.raises(InvalidParameter, match="control_rate"):
        world.run(1.0, control_rate=0.0)


def test_blow_up_guard_names_the_joint_that_ran_away():
    import re

    world, _, _ = pinch_scene()
    world.qd[4] = -3e3  # the right finger's joint 2 [rad/s]; it kicks the rest via the disc
    log = world.run(0.1)
    assert log.status == "failed"
    m = re.fullmatch(r"runaway velocity (\S+) > 1000 \(joint (\d), (\S+) rad/s\)", log.reason)
    assert m is not None, log.reason
    k = int(m.group(2))
    assert k == int(np.argmax(np.abs(world.qd)))
    assert float(m.group(1)) == float(m.group(3)) == float(f"{abs(world.qd[k]):.3g}")
