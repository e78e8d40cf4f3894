"""The planar hand's actuator envelope (planner.sim.planar.actuator): closed form and a
free finger driven at a constant torque."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from planner.sim import PlanarWorld, SensorSettings
from planner.sim.planar.actuator import RATED_SPEED, delivered, delivered_array
from robots.planar_hand import PlanarHand
from robots.planar_hand.model import VELOCITY_LIMIT

torques = st.floats(-2.0, 2.0, allow_nan=False)
speeds = st.floats(-50.0, 50.0, allow_nan=False)


def test_rated_speed_is_the_models_velocity_limit():
    assert RATED_SPEED == VELOCITY_LIMIT == 5.0


@given(torques, speeds)
def test_envelope_only_removes_driving_torque(tau, qd):
    out = delivered(tau, qd)
    if tau * qd <= 0.0 or abs(qd) <= RATED_SPEED:  # braking or below the rated speed
        assert out == tau
    elif abs(qd) >= 2 * RATED_SPEED:  # beyond the no-load speed: nothing
        assert out == 0.0
    else:  # the linear torque-speed line between them
        assert out == pytest.approx(tau * (2 - abs(qd) / RATED_SPEED), rel=1e-12)
    assert abs(out) <= abs(tau) and out * tau >= 0.0  # never more, never reversed


def test_envelope_is_continuous_at_its_knees():
    for v in (RATED_SPEED, 2 * RATED_SPEED):
        for s in (1.0, -1.0):
            lo, hi = delivered(s, s * (v - 1e-9)), delivered(s, s * (v + 1e-9))
            assert lo == pytest.approx(hi, abs=1e-8)


@given(st.lists(st.tuples(torques, speeds), min_size=1, max_size=6))
def test_array_form_equals_the_scalar_one(pairs):
    tau, qd = np.array(pairs).T
    assert np.array_equal(delivered_array(tau, qd), [delivered(a, b) for a, b in pairs])


def _free_finger(compiled: bool):
    """A right finger with no gravity, palm or object, its distal joint driven at 5 mN m
    from the middle of its range (without the envelope it reaches about 20 rad/s before
    its joint stop)."""
    world = PlanarWorld(dt=2e-3, gravity=(0.0, 0.0), sensors=SensorSettings.ideal(),
                        compiled=compiled)  # fmt: skip
    hand = PlanarHand()
    lo, hi = hand.joint_limits[5]
    q = np.array([0.5, -0.3, -0.8, -0.5, 0.3, 0.5 * (lo + hi)])
    world.add_hand(hand, q, palm=False)
    tau = np.zeros(6)
    tau[5] = 5e-3
    return world.run(0.4, lambda t, obs: tau)


def test_a_free_finger_tops_out_at_the_no_load_speed():
    log = _free_finger(compiled=True)
    speed = np.abs(log.qd[:, 5])
    assert speed.max() > 1.5 * RATED_SPEED  # the envelope's sloped part was reached
    assert speed.max() <= 2 * RATED_SPEED + 0.5  # one step's gain beyond the no-load speed
    ref = _free_finger(compiled=False)  # the reference (Python) step applies it too
    assert np.allclose(ref.qd, log.qd, atol=1e-9)
