"""The gait's gravity (``GaitSettings.gravity``): a vertical hand (9.81 m/s^2 towards the
palm, the default) or a horizontal one (0): the world, the phase-1 squeeze and the scenario
key follow it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.errors import InvalidParameter
from planner.exploration import explore_object
from planner.exploration.planar import GaitSettings
from planner.exploration.planar.carry_squeeze import carrying_squeeze, phase1_squeeze
from planner.geometry import shapes


@pytest.mark.parametrize("bad", [-1.0, math.nan, math.inf, 101.0, None])
def test_a_bad_gravity_is_named(bad):
    with pytest.raises(InvalidParameter, match=r"^gravity: "):
        GaitSettings(gravity=bad)


def test_the_default_hand_stands_in_a_vertical_plane():
    assert GaitSettings().gravity == 9.81
    assert GaitSettings(gravity=0.0).gravity == 0.0


def test_the_phase1_squeeze_carries_the_weight_of_the_settings_gravity():
    """The carrying squeeze is linear in the load ``m g`` (no lift): twice the gravity,
    twice the squeeze above the floor; none in a horizontal plane (the commanded one)."""
    high = np.radians([[150.1, 21.1], [129.3, 9.4]])  # needs more than 1 N at 9.81
    s1, s2, s0 = (GaitSettings(gravity=g) for g in (9.81, 19.62, 0.0))
    mu = s1.planning_mu
    need = max(carrying_squeeze(*row, mu, s1.object_mass * 9.81) for row in high)
    assert phase1_squeeze(high, s1, 0.0) == pytest.approx((1 + s1.carry_margin) * need)
    assert phase1_squeeze(high, s2, 0.0) == pytest.approx(
        min((1 + s2.carry_margin) * 2 * need, s2.max_squeeze)
    )
    assert phase1_squeeze(high, s0, 0.0) == s0.internal_force


@pytest.mark.parametrize("g", [9.81, 0.0])
def test_contact_impulses_balance_the_weight_of_the_settings_gravity(g):
    """Impulse-momentum on the object over a short gait run: the contact forces' impulse
    (the fingers' and the palm's, from the simulator log; on body b of each pair, minus
    ``N n + T t`` with ``t`` the normal turned +90 deg) equals ``m dv - m g_vec T`` with
    ``g_vec = (0, -g)`` the gravity the settings give the world; while the fingers carry
    the ball off the palm it averages ``m g`` upwards (0.49 N at 9.81, none at 0)."""
    s = GaitSettings(gravity=g)
    res = explore_object(shapes.circle(0.05), duration=0.3, settings=s)
    assert res.status == "ok" and res.rotation < 0  # grasped and turning clockwise
    log = res.log
    n, nf, tf = log.contact_normal, log.normal_force[..., None], log.tangential_force[..., None]
    t = np.stack([-n[..., 1], n[..., 0]], axis=-1)
    on_object = np.where((log.contact_pair >= 0)[..., None], -(nf * n + tf * t), 0.0).sum(axis=1)
    i0, i1 = 10, len(log.t) - 1
    dt = np.diff(log.t)
    impulse = (on_object[i0 + 1 : i1 + 1] * dt[i0:i1, None]).sum(axis=0)
    v = log.velocities["object"]
    span = log.t[i1] - log.t[i0]
    m = s.object_mass
    expected = m * (v[i1, :2] - v[i0, :2]) - m * np.array([0.0, -g]) * span
    assert impulse == pytest.approx(expected, abs=1e-9)
    # the momentum change is small: the impulse is the weight's, m g T up, to within 5 %
    # of the vertical hand's weight
    assert impulse[1] == pytest.approx(m * g * span, abs=0.05 * m * 9.81 * span)
    assert abs(impulse[0]) < 0.01 * span


def test_the_scenario_key_reaches_the_settings():
    from planner.kinds.gait import Config

    circle = {"shape": "circle", "radius": 0.05}
    text = {"name": "g", "kind": "gait", "object": circle, "gravity": 0.0}
    assert Config.model_validate(text).settings().gravity == 0.0
    del text["gravity"]
    assert Config.model_validate(text).settings().gravity == 9.81
