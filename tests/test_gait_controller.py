"""The gait controller against its recording: same torques, trace and events on real
observations (recorded with the pre-optimization controller on ball_with_ridge), and its
compiled pieces against the library functions they replace."""

from __future__ import annotations

import gait_replay
import numpy as np
import pytest
from conftest import benchmark_module
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.control.grasp_stability import epsilon_two_contacts
from planner.grasp import epsilon_two_planar


@pytest.fixture(scope="module")
def recording():
    return gait_replay.load()


def test_recording_covers_every_phase_and_events(recording):
    kinds = {w["kind"] for w in recording["windows"]}
    assert kinds == {1, 2, 3}
    events = {c["event"] for w in recording["windows"] for c in w["calls"]}
    assert len(events - {None}) >= 1


def test_replay_gives_the_recorded_torques_trace_and_events(recording):
    ctrl = gait_replay.make_controller(recording)
    n = 0
    for call, tau, row, event in gait_replay.replay(ctrl, recording):
        np.testing.assert_allclose(tau, call["tau"], rtol=0, atol=1e-9)
        np.testing.assert_allclose(np.array(row, float), np.array(call["trace"], float),
                                   rtol=0, atol=1e-9)  # fmt: skip
        assert event == call["event"]
        n += 1
    assert n == sum(len(w["calls"]) for w in recording["windows"])
    assert len(ctrl.step_times) == n


def test_sensing_update_matches_the_estimate_written_out(recording):
    """The compiled sensing against the closed forms of planar.sensing's docstring."""
    import math

    ctrl = gait_replay.make_controller(recording)
    sensing, r, R = ctrl.sensing, ctrl.r, ctrl.sensing.radius
    for w in recording["windows"][:3]:
        for c in w["calls"][::10]:
            obs = gait_replay.observation(c["obs"])
            e = sensing.update(obs, "pad")
            tipL, tipR = sensing._tip(0, obs.q), sensing._tip(1, obs.q)
            phiL = float(np.sum(obs.q[:3]))
            img = obs.tactile["left"]
            if img.sum() * sensing.array.pitch**2 > 0.02:
                u = float(img.sum(axis=0) @ sensing.array.u / img.sum())
                assert e.u == pytest.approx(u, abs=1e-12)
            pL = tipL + e.u * np.array([math.cos(phiL), math.sin(phiL)])
            nL = np.array([math.sin(phiL), -math.cos(phiL)])
            centre = pL - R * nL
            d = (centre - tipR) / np.linalg.norm(centre - tipR)
            np.testing.assert_allclose(e.p, [pL, tipR + r * d], atol=1e-12)
            np.testing.assert_allclose(e.n, [nL, -d], atol=1e-12)
            np.testing.assert_allclose(e.centre, centre, atol=1e-12)
            np.testing.assert_allclose(e.normal_force, -np.sum(obs.tip_forces * e.n, axis=1),
                                       atol=1e-12)  # fmt: skip


finite = st.floats(-1.0, 1.0, allow_nan=False)


@settings(max_examples=300, deadline=None, derandomize=True)
@given(p=st.lists(finite, min_size=4, max_size=4), a=st.lists(st.floats(-4, 4), min_size=2,
       max_size=2), mu=st.floats(0.0, 2.0))  # fmt: skip
def test_compiled_epsilon_equals_the_library(p, a, mu):
    pts = np.array(p).reshape(2, 2)
    n = np.array([[np.cos(a[0]), np.sin(a[0])], [np.cos(a[1]), np.sin(a[1])]])
    ref = float(epsilon_two_planar(pts[0], -n[0], pts[1], -n[1], mu))
    assert epsilon_two_contacts(pts, n, mu, -1.0) == pytest.approx(ref, abs=1e-12)
    assert epsilon_two_contacts(pts, -n, mu, 1.0) == pytest.approx(ref, abs=1e-12)


def test_compiled_epsilon_of_an_antipodal_grasp():
    """Two opposite contacts on a unit-radius disc: closure for mu > 0, none for mu = 0."""
    pts = np.array([[-1.0, 0.0], [1.0, 0.0]])
    outward = np.array([[-1.0, 0.0], [1.0, 0.0]])
    assert epsilon_two_contacts(pts, outward, 0.5, -1.0) > 0.0
    assert epsilon_two_contacts(pts, outward, 0.0, -1.0) == 0.0
    same = np.array([[-1.0, 0.0], [-1.0, 0.0]])  # both fingers push the same way
    assert epsilon_two_contacts(pts, same, 0.5, -1.0) == 0.0


# ---------------------------------------------------------------- the kernel's scalar laws
num = st.floats(-5.0, 5.0, allow_nan=False)


@settings(max_examples=200, deadline=None, derandomize=True)
@given(v=st.lists(num, min_size=8, max_size=8))
def test_kernel_internal_force_equals_the_library(v):
    from planner.control.internal_force import sensed_internal_force
    from planner.exploration.planar.controller_kernel import _internal_force

    ref = sensed_internal_force(v[0:2], v[2:4], v[4:6], v[6:8])
    # numba's hypot (libm) and CPython's math.hypot may differ in the last bit
    assert _internal_force(*v) == pytest.approx(ref, rel=1e-14, abs=1e-14)
    assert _internal_force(1.0, 2.0, 1.0, 2.0, *v[4:]) == 0.0  # coincident points


@settings(max_examples=200, deadline=None, derandomize=True)
@given(v=st.lists(num, min_size=4, max_size=4), kp=st.floats(0, 2), kv=st.floats(0, 1),
       limit=st.floats(1e-3, 1.0))  # fmt: skip
def test_kernel_rolling_moment_equals_eq_2_8(v, kp, kv, limit):
    from planner.control.rolling_pd import RollingGains, rolling_moment
    from planner.exploration.planar.controller_kernel import _rolling_moment

    ref = rolling_moment(*v, RollingGains(kp, kv, limit))
    assert _rolling_moment(*v, kp, kv, limit) == ref
    assert abs(ref) <= limit


@settings(max_examples=200, deadline=None, derandomize=True)
@given(beta=num, phi=num, r=st.floats(1e-3, 0.05))
def test_kernel_arclength_equals_the_sensing(beta, phi, r):
    from planner.exploration.planar.controller_kernel import _arclength
    from planner.exploration.planar.sensing import round_contact_arclength

    assert _arclength(beta, phi, r) == round_contact_arclength(beta, phi, r)


def test_controller_interface_kept(recording):
    """What the phase machine uses: theta after start, stop(), event data, images."""
    ctrl = gait_replay.make_controller(recording)
    w = recording["windows"][0]
    ctrl.start(gait_replay.replay_segment(w), w["t0"])
    assert ctrl.theta == w["theta0"]
    assert ctrl.stop(w["t0"], None) is None
    events = [(c, e) for c, _, _, e in gait_replay.replay(ctrl, recording) if e is not None]
    assert events and all(isinstance(e, str) for _, e in events)
    assert ctrl.images and ctrl.images[0][1].shape == (8, 8)


def test_plain_numpy_controller_gives_the_same_torques(recording):
    """The benchmark's naive controller (numpy + Pinocchio + qpsolvers) on the recording."""
    NaiveGaitController = benchmark_module("naive_gait").NaiveGaitController

    ctrl = gait_replay.make_controller(recording, NaiveGaitController)
    calls = [w["calls"][:40] for w in recording["windows"]]
    short = {**recording, "windows": [{**w, "calls": c} for w, c in
                                      zip(recording["windows"], calls, strict=True)]}  # fmt: skip
    for call, tau, _, event in gait_replay.replay(ctrl, short):
        np.testing.assert_allclose(tau, call["tau"], rtol=0, atol=1e-7)
        assert event == call["event"]


def test_replay_with_the_step_run_from_python(recording):
    """Without the C entry (a DAQP build the step cannot bind) Python runs the step."""
    from planner.exploration.planar import controller_kernel as ck

    ctrl = gait_replay.make_controller(recording)
    assert ctrl.step.c_entry is not None
    ctrl._ks[ck.K_STEP_FN] = 0.0
    ctrl._python_step = True
    calls = [w["calls"][:30] for w in recording["windows"]]
    short = {**recording, "windows": [{**w, "calls": c} for w, c in
                                      zip(recording["windows"], calls, strict=True)]}  # fmt: skip
    for call, tau, _, event in gait_replay.replay(ctrl, short):
        np.testing.assert_allclose(tau, call["tau"], rtol=0, atol=1e-9)
        assert event == call["event"]


def test_phase1_rolling_reference_is_the_phases_own_first_reading(recording):
    """Phase 1 does not depend on the contact estimate the last phase left: its rolling
    reference (eq. 2.4) is its own first touching reading. A stale centroid 7 mm off (phase
    3's pad ended with it at the array's edge on a ridge) gives the recorded torques and a
    first estimate equal to the segment's theta0 (before: a 7.9 deg jump)."""
    ctrl = gait_replay.make_controller(recording)
    # phases 1 whose pad touches from the first call on (a pad that does not touch yet
    # places its contact at the last estimate, stale or not)
    windows = [w for w in recording["windows"] if w["kind"] == 1 and w["calls"][0]["trace"][3]]
    assert len(windows) >= 2
    for w in windows:
        ctrl.sensing.est.u = w["pre"]["u"]
        ctrl._last_tau = w["pre"]["last_tau"].copy()
        if w["sense"] is not None:
            obs, source = w["sense"]
            ctrl.sensing.update(gait_replay.observation(obs), source)
        ctrl.sensing.est.u = ctrl.sensing.est.u + 7e-3  # stale
        ctrl.start(gait_replay.replay_segment(w), w["t0"])
        for i, c in enumerate(w["calls"]):
            tau = np.array(ctrl(c["t"], gait_replay.observation(c["obs"])))
            np.testing.assert_allclose(tau, c["tau"], rtol=0, atol=1e-9)
            if i == 0:
                assert ctrl.theta == pytest.approx(w["theta0"], abs=1e-12)
