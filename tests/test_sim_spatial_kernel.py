"""The spatial world's compiled hot path against its general (numpy) reference, and the 3GM's
joint limits as unilateral constraints."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from planner.sim.spatial import Plane, SpatialWorld
from planner.sim.spatial import step_kernel as sk
from planner.sim.spatial.finger_codegen import reduced_dynamics_function
from planner.sim.spatial.scenes import ridge_slide_scene
from planner.sim.spatial.stepping import held_inverse_mass
from robots.three_gm import ThreeGM

GM = ThreeGM()


def _pair(seed=0):
    """Two copies of the ridge scene: ``a`` through the kernel, ``b`` the general path."""
    a = ridge_slide_scene(seed=seed)
    b = ridge_slide_scene(seed=seed)
    b.world.use_kernels = False
    return a, b


def _contact_state(sc, rng):
    """Angles with the tip centre at a random gap in [-1 µm, 20 µm] from the ridge plate."""
    x = sc.ridge.position[0] + rng.uniform(-6e-3, 6e-3)
    y = rng.uniform(-5e-3, 5e-3)
    h, hx, hy, *_ = sc.plate.height_derivatives(x, y)
    n = np.array([-hx, -hy, 1.0]) / np.sqrt(1 + hx * hx + hy * hy)
    gap = rng.uniform(-1e-6, 2e-5)
    c = np.array([x, y, h]) + (sc.tip_radius + gap) * n
    return GM.inverse_kinematics(c, theta0=sc.world.finger.th)


def _set(world, th, thd):
    x = world.finger.x
    x[:] = 0.0
    x[sk.TH : sk.TH + 3], x[sk.THD : sk.THD + 3] = th, thd
    world.finger._refresh_center()
    world._hints.clear()


def _compare(a, b):
    fa, fb = a.finger, b.finger
    np.testing.assert_allclose(fa.th, fb.th, atol=1e-12)
    np.testing.assert_allclose(fa.thd, fb.thd, atol=1e-10)
    ca, cb = a.contacts(), b.contacts()
    assert len(ca) == len(cb)
    for p, q in zip(ca, cb, strict=True):
        assert p.bodies == q.bodies
        np.testing.assert_allclose(p.point, q.point, atol=1e-12)
        np.testing.assert_allclose(p.normal, q.normal, atol=1e-10)
        np.testing.assert_allclose(p.normal_force, q.normal_force, rtol=1e-8, atol=1e-10)
        np.testing.assert_allclose(p.tangential_force, q.tangential_force, atol=1e-9)
        np.testing.assert_allclose(p.slip_velocity, q.slip_velocity, atol=1e-10)
        assert abs(p.gap - q.gap) <= 1e-12
    np.testing.assert_allclose(fa.x[sk.LIM : sk.LIM + 3], fb.x[sk.LIM : sk.LIM + 3], atol=1e-12)


@pytest.mark.parametrize("seed", range(6))
def test_kernel_step_equals_the_general_step_on_random_states(seed):
    rng = np.random.default_rng(seed)
    a, b = _pair()
    for _ in range(8):
        th = _contact_state(a, rng)
        thd = rng.normal(scale=0.05, size=3)
        tau = GM.joint_torques(th, rng.normal(scale=0.3, size=3) + [0, 0, -0.4])
        tau = tau + np.asarray(reduced_dynamics_function(GM)(th, np.zeros(3), np.zeros(3), 0.0)[6])
        for w in (a.world, b.world):
            _set(w, th, thd)
            w.step(tau)
        assert a.world._from_kernel and not b.world._from_kernel
        _compare(a.world, b.world)


@pytest.mark.parametrize("seed", range(4))
def test_kernel_equals_the_general_path_at_a_joint_limit(seed):
    """Random states at a joint's limit, driven into it, in contact or in free space."""
    rng = np.random.default_rng(100 + seed)
    a, b = _pair()
    lim = GM.joint_limits
    kin = reduced_dynamics_function(GM, kinematics=True)
    trial = 0
    while trial < 6:
        th = _contact_state(a, rng) if trial % 2 else GM.center_theta.copy()
        j, side = int(rng.integers(3)), int(rng.integers(2))
        th[j] = lim[j, side] + (1 if side == 0 else -1) * rng.uniform(0, 2e-4)
        if not abs(float(kin(th)[4][0])) > 1e-3:  # the five-bar cannot close there
            continue
        trial += 1
        thd = rng.normal(scale=0.05, size=3)
        thd[j] = (-1 if side == 0 else 1) * rng.uniform(0.05, 0.5)  # into the limit
        tau = np.clip(rng.normal(scale=0.3, size=3), -1, 1)
        for w in (a.world, b.world):
            _set(w, th, thd)
            w.step(tau)
        _compare(a.world, b.world)
        out = a.world.finger.th[j] - lim[j, side]
        assert (out >= -1e-12) if side == 0 else (out <= 1e-12)  # not beyond the limit


def test_joint_limit_is_a_unilateral_constraint_with_an_event():
    """θ3 driven into its upper limit in free space (θ1, θ2 held by a PD): held there, not
    beyond, with one event."""
    th0 = GM.center_theta

    def drive(t, obs):
        pd = 2.0 * (th0 - obs.q) - 0.2 * obs.qd
        return np.array([pd[0], pd[1], 0.05])

    for kernels in (True, False):
        w = SpatialWorld(gravity=(0, 0, 0))
        w.add_surface(Plane((0, 0, -1.0)), friction=0.5)  # far below: the kernel path runs
        w.use_kernels = kernels
        w.add_finger(GM, th0)
        hi = GM.joint_limits[2, 1]
        log = w.run(1.5, drive)
        assert log.status == "ok"
        assert log.q[:, 2].max() <= hi + 1e-12
        assert log.q[-1, 2] == pytest.approx(hi, abs=1e-12)
        assert abs(log.qd[-1, 2]) <= 1e-9  # at rest against the limit
        ev = [e for e in log.events if e.kind == "joint_limit"]
        assert len(ev) == 1 and ev[0].data["joint"] == 2 and ev[0].data["side"] == "upper"
        assert w._from_kernel is kernels


def test_held_inverse_mass_is_the_constrained_one():
    """P = Z (Zᵀ M Z)⁻¹ Zᵀ with Z the free joints' columns (closed form)."""
    rng = np.random.default_rng(3)
    A = rng.normal(size=(3, 3))
    M = A @ A.T + 3 * np.eye(3)
    for held in ([0], [2], [0, 1]):
        free = [i for i in range(3) if i not in held]
        Z = np.eye(3)[:, free]
        want = Z @ np.linalg.inv(Z.T @ M @ Z) @ Z.T
        np.testing.assert_allclose(held_inverse_mass(np.linalg.inv(M), held), want, atol=1e-14)


def test_kinematics_function_equals_the_dynamics_outputs():
    dyn = reduced_dynamics_function(GM)
    kin = reduced_dynamics_function(GM, kinematics=True)
    rng = np.random.default_rng(2)
    for _ in range(10):
        th = GM.center_theta + rng.normal(scale=0.2, size=3)
        c, J, Jw, _, _, g1, b, _, s = (np.array(o) for o in dyn(th, np.zeros(3), np.zeros(3), 0))
        kc, kJ, kJw, kg1, ks, grav = (np.array(o) for o in kin(th))
        for u, v in ((c, kc), (J, kJ), (Jw, kJw), (g1, kg1), (s, ks), (b, grav)):
            np.testing.assert_allclose(u, v, rtol=1e-13, atol=1e-16)


def test_clones_do_not_share_buffers():
    f = reduced_dynamics_function(GM, kinematics=True)
    g = f.clone()
    assert f.buffer.ctypes.data != g.buffer.ctypes.data
    a = np.array(f(GM.center_theta)[0])
    g(GM.center_theta + 0.1)
    np.testing.assert_array_equal(f.outputs[0], a)


def test_compiled_readings_equal_the_numpy_readers():
    """Encoders, force sensor and OWTS through one compiled call: the same numbers (and the
    same random draws) as read_joints/read_forces/OWTSRecorder.read."""
    a, b = _pair(seed=4)
    for w in (a.world, b.world):
        w.run(0.3, a.controller if w is a.world else b.controller)
    assert a.world._from_kernel and not b.world._from_kernel
    for _ in range(3):
        oa, ob = a.world.observe(), b.world.observe()
        np.testing.assert_allclose(oa.q, ob.q, atol=1e-12)
        np.testing.assert_allclose(oa.qd, ob.qd, atol=1e-9)
        np.testing.assert_allclose(oa.tip_forces, ob.tip_forces, atol=1e-9)
        np.testing.assert_allclose(oa.owts.voltages, ob.owts.voltages, atol=1e-9)
        np.testing.assert_allclose(oa.owts.normal, ob.owts.normal, atol=1e-6)
        assert oa.owts.in_contact.tolist() == ob.owts.in_contact.tolist()
        for w in (a.world, b.world):
            w.step(np.zeros(3))


def test_compiled_controller_equals_its_numpy_law():
    sc = ridge_slide_scene()
    log = sc.world.run(0.2, sc.controller)
    assert log.status == "ok"
    obs = sc.world.observe()
    ref = ridge_slide_scene().controller
    ref._state[:] = sc.controller._state
    got = sc.controller(0.2, obs)
    want = ref.reference(0.2, obs.q, obs.qd, obs.owts.normal, obs.owts.in_contact)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(sc.controller.normal, ref.normal, atol=1e-14)


def test_kernel_log_equals_the_general_log():
    """The compiled record writes the rows WorldBase.record would write."""
    a, b = _pair(seed=3)
    la = a.world.run(0.2, a.controller)
    lb = b.world.run(0.2, b.controller)
    for name in ("t", "q", "qd", "tau", "contact_count", "contact_pair", "normal_force"):
        np.testing.assert_allclose(getattr(la, name), getattr(lb, name), rtol=1e-8, atol=1e-10)
    for name in ("contact_point", "contact_normal", "gap", "tangential_force", "slip_velocity"):
        np.testing.assert_allclose(getattr(la, name), getattr(lb, name), atol=1e-9)
    np.testing.assert_allclose(la.velocities["finger"], lb.velocities["finger"], atol=1e-9)
    np.testing.assert_allclose(la.poses["finger"], lb.poses["finger"], atol=1e-12)
    assert la.pairs == lb.pairs


def test_contact_and_joint_limit_together():
    """The tip pressed on a plane and pushed sideways while θ3 is driven into its limit: the
    coupled problem (cone + limit row) gives the same steps on both paths, the limit holds,
    the contact sticks or slides within the cone."""
    th = GM.center_theta.copy()
    th[2] = GM.joint_limits[2, 1] - 1e-5
    z = GM.forward_kinematics(th)[2] - 0.008
    fn = reduced_dynamics_function(GM, kinematics=True)
    worlds = []
    for kernels in (True, False):
        w = SpatialWorld()
        w.add_surface(Plane((0, 0, z)), friction=0.5)
        w.use_kernels = kernels
        w.add_finger(GM, th)
        worlds.append(w)
    a, b = worlds
    both = 0
    for _ in range(300):
        _, J, _, _, _, grav = (np.array(o) for o in fn(a.finger.th))
        tau = J.reshape(3, 3).T @ np.array([0.0, 0.3, -0.5]) + grav.ravel() + [0, 0, 0.02]
        a.step(tau)
        b.step(tau)
        _compare(a, b)
        held = a.finger.x[sk.LIM + 2] != 0.0
        both += bool(held and a.contacts())
        assert a.finger.th[2] <= GM.joint_limits[2, 1] + 1e-12
        for c in a.contacts():
            assert np.linalg.norm(c.tangential_force) <= 0.5 * c.normal_force * (1 + 1e-9)
    assert both > 100
    assert [e.data["joint"] for e in a.drain_events() if e.kind == "joint_limit"] == [2]


@settings(max_examples=15, deadline=None, derandomize=True)
@given(
    tau=st.lists(st.floats(-0.6, 0.6), min_size=3, max_size=3),
    kernels=st.booleans(),
)
@example(tau=[-0.25241959510961104, -0.25241959510961104, -0.6], kernels=False)  # a runaway
@example(tau=[-0.25241959510961104, -0.25241959510961104, -0.6], kernels=True)
def test_joints_never_leave_their_limits(tau, kernels):
    """Any constant torque, in free space: every joint stays within its limits (to 1e-12
    rad) until the run ends or the five-bar becomes singular."""
    w = SpatialWorld()
    w.add_surface(Plane((0, 0, -1.0)), friction=0.5)
    w.use_kernels = kernels
    w.add_finger(GM, GM.center_theta)
    log = w.run(0.4, lambda t, obs: np.array(tau))
    lim = GM.joint_limits
    assert np.all(log.q >= lim[:, 0] - 1e-12) and np.all(log.q <= lim[:, 1] + 1e-12)
    assert log.status == "ok" or any(e.kind == "singular" for e in log.events)


def test_a_step_toward_alignment_ends_singular_before_the_loop_jumps():
    """Under a constant torque the free five-bar's links l3 and l4 close on alignment:
    sin(gamma2 - gamma1) 0.14, 0.082, 0.0029 at 1 ms steps. The step to 0.0029 came nearer
    zero than it moved (bodies.aligning): the run ends "singular" there, in both paths,
    where the next step ran away (rates 78 -> 391 rad/s; the loop closed on its other
    branch 160 mm away)."""
    from planner.sim.spatial.bodies import aligning

    assert aligning(0.082, 0.0029) and aligning(0.01, -0.01) and aligning(0.5, 5e-7)
    assert not aligning(0.14, 0.082) and not aligning(0.99, 0.98)
    tau = np.array([-0.25241959510961104, -0.25241959510961104, -0.6])
    ends = []
    for kernels in (False, True):
        w = SpatialWorld()
        w.add_surface(Plane((0, 0, -1.0)), friction=0.5)
        w.use_kernels = kernels
        w.add_finger(GM, GM.center_theta)
        log = w.run(0.4, lambda t, obs: tau)
        assert log.status == "failed"
        assert [e.kind for e in log.events][-2:] == ["singular", "stopped"]
        assert "sin(gamma2 - gamma1) = 0.00293" in log.reason
        assert np.abs(log.qd).max() < 100.0  # no runaway before it
        ends.append(log.q[-1])
    assert np.array_equal(ends[0], ends[1])
