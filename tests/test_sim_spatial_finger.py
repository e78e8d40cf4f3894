"""The 3GM in the spatial world: dynamics vs Pinocchio, the ridge slide, OWTS, faults."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from planner.sim.spatial import OWTSReading, Plane, SpatialWorld, tcs_rotation
from planner.sim.spatial.finger import FingerDynamics
from planner.sim.spatial.finger_codegen import reduced_dynamics_function
from planner.sim.spatial.scenes import centre_path_error, ridge_slide_scene
from robots.three_gm import ThreeGM, closure_constraint

GM = ThreeGM()


def _configs(n=8, seed=0):
    rng = np.random.default_rng(seed)
    c = GM.center_theta
    return [c + rng.uniform(-0.25, 0.25, 3) for _ in range(n)], rng


def test_reduced_dynamics_equal_pinocchio_constraint_dynamics():
    """M_r θ̈ + b_r = τ is Pinocchio's constraintDynamics with the closure constraint."""
    fd = FingerDynamics(GM)
    m = fd.model
    d = m.createData()
    cm = closure_constraint(m, GM.params)
    cms, cds = [cm], [cm.createData()]
    pin.initConstraintDynamics(m, d, cms, cds)
    prox = pin.ProximalSettings(1e-14, 1e-10, 200)
    thetas, rng = _configs()
    for th in thetas:
        thd, tau = rng.normal(size=3), rng.normal(scale=0.2, size=3)
        st = fd.evaluate(th, thd)
        full = np.zeros(5)
        full[[1, 3, 0]] = tau
        a = pin.constraintDynamics(m, d, st.q, st.v, full, cms, cds, prox)
        np.testing.assert_allclose(
            a[[1, 3, 0]], np.linalg.solve(st.M, tau - st.b), rtol=1e-7, atol=1e-8
        )
        np.testing.assert_allclose(st.J, GM.jacobian(th), atol=1e-14)
        np.testing.assert_allclose(st.center, GM.forward_kinematics(th), atol=1e-15)


def test_generated_dynamics_equal_the_pinocchio_path():
    fd = FingerDynamics(GM)
    fn = reduced_dynamics_function(GM)
    thetas, rng = _configs(seed=1)
    for th in thetas:
        thd, tau = rng.normal(size=3), rng.normal(scale=0.2, size=3)
        st = fd.evaluate(th, thd)
        c, J, Jw, Minv, thd_f, g1, b, M, _ = (np.array(x) for x in fn(th, thd, tau, 1e-3))
        np.testing.assert_allclose(c, st.center, atol=1e-15)
        np.testing.assert_allclose(J, st.J, atol=1e-14)
        np.testing.assert_allclose(Jw, st.Jw, atol=1e-13)
        np.testing.assert_allclose(M, st.M, rtol=1e-12, atol=1e-18)
        np.testing.assert_allclose(b, st.b, rtol=1e-10, atol=1e-14)
        np.testing.assert_allclose(
            thd_f, thd + 1e-3 * np.linalg.solve(st.M, tau - st.b), rtol=1e-10
        )
        assert float(g1[0]) == pytest.approx(st.gamma1, abs=1e-14)


def test_tcs_pole_is_the_distal_link():
    fd = FingerDynamics(GM)
    th = GM.center_theta + 0.1
    st = fd.evaluate(th, np.zeros(3))
    d = fd.model.createData()
    pin.framesForwardKinematics(fd.model, d, st.q)
    R = tcs_rotation(st.gamma1, th[2])
    np.testing.assert_allclose(
        R[:, 2], d.oMf[fd.model.getFrameId("endpoint")].rotation[:, 0], atol=1e-15
    )
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-15)


def test_gravity_compensated_finger_holds_still():
    w = SpatialWorld()
    th0 = GM.center_theta
    w.add_finger(GM, th0)
    fn = reduced_dynamics_function(GM)

    def hold(t, obs):
        return np.array(fn(w.finger.th, np.zeros(3), np.zeros(3), 0.0)[6])  # b_r(θ, 0)

    log = w.run(0.5, hold, oracle=True)
    assert np.abs(log.q - th0).max() <= 1e-9
    assert log.status == "ok"


@pytest.fixture(scope="module")
def ridge_run():
    sc = ridge_slide_scene(speed=0.02, travel=0.014)
    log = sc.world.run(sc.duration, sc.controller)
    return sc, log


def test_ridge_slide_centre_on_the_exact_offset(ridge_run):
    sc, log = ridge_run
    assert log.status == "ok"
    pe = centre_path_error(sc, log)
    assert pe.lost_steps == 0  # no step loses contact while sliding
    assert pe.steps > 500
    assert pe.max <= 1e-6 and pe.rms <= 1e-7
    x = log.poses[sc.finger][:, 0]
    assert x[-1] - sc.ridge.position[0] > 2 * sc.ridge.width  # the ridge was crossed


def test_ridge_slide_friction_is_mu_fn_against_the_slip(ridge_run):
    sc, log = ridge_run
    fn = log.normal_force[:, 0]
    ft = log.tangential_force[:, 0]
    slip = log.slip_velocity[:, 0]
    sliding = (fn > 0) & (np.linalg.norm(slip, axis=1) > 1e-9)
    assert sliding.sum() > 400
    np.testing.assert_allclose(
        np.linalg.norm(ft[sliding], axis=1), sc.friction * fn[sliding], rtol=1e-9
    )
    cos = -np.sum(ft[sliding] * slip[sliding], axis=1) / (
        np.linalg.norm(ft[sliding], axis=1) * np.linalg.norm(slip[sliding], axis=1)
    )
    np.testing.assert_allclose(cos, 1.0, atol=1e-8)
    assert np.median(fn[sliding]) == pytest.approx(sc.normal_force, rel=0.1)


def test_owts_reading_tracks_the_contact_normal(ridge_run):
    sc, _ = ridge_run
    w = sc.world
    obs = w.observe()
    tau = sc.controller(w.time, obs)
    w.step(tau)
    w.step(tau)  # two steps without observing: 10 samples at 5 kHz are pending
    reading = w.observe().owts
    assert isinstance(reading, OWTSReading)
    assert len(reading.t) == 10 and np.all(np.diff(reading.t) == pytest.approx(2e-4))
    assert reading.in_contact.all()
    c = w.contacts()[0]
    R = tcs_rotation(w.finger.gamma1, w.finger.th[2])
    true_n = R.T @ (-c.normal)
    ang = np.degrees(np.arccos(np.clip(reading.normal @ true_n, -1, 1)))
    assert ang.max() < 3.0  # 0.5 deg (1 sigma) noise + 12-bit A/D
    np.testing.assert_allclose(np.linalg.norm(reading.point, axis=1), sc.tip_radius, rtol=1e-12)


def test_observation_is_sensor_data_and_seeded():
    def readings(seed):
        w = SpatialWorld(seed=seed)
        w.add_surface(Plane((0, 0, GM.workspace_center[2] - 0.008)), friction=0.5)
        w.add_finger(GM, GM.center_theta)
        for _ in range(3):
            w.step(GM.joint_torques(GM.center_theta, [0, 0, -0.5]))
        return w.observe()

    a, b, c = readings(1), readings(1), readings(2)
    np.testing.assert_array_equal(a.owts.voltages, b.owts.voltages)
    assert not np.array_equal(a.owts.voltages, c.owts.voltages)
    res = GM.encoder_resolution
    np.testing.assert_allclose(a.q / res, np.round(a.q / res), atol=1e-6)
    assert a.truth is None and a.fingers == ("finger",) and a.tip_forces.shape == (1, 3)
    assert a.tip_forces[0, 2] < 0  # the tip pushes down on the plane


def test_no_contact_gives_zero_owts_normal():
    w = SpatialWorld()
    w.add_finger(GM, GM.center_theta)
    w.step()
    r = w.observe().owts
    assert not r.in_contact.any() and np.all(r.normal == 0)


def test_singular_configuration_ends_the_run_cleanly():
    w = SpatialWorld(gravity=(0, 0, 0))
    w.add_finger(GM, GM.center_theta, theta_dot=(0.0, 40.0, 0.0))  # drives the loop open
    log = w.run(1.0)
    kinds = [e.kind for e in log.events]
    assert "singular" in kinds and log.status == "failed"
    assert log.t[-1] < 1.0


def test_torque_saturation_is_reported_and_clipped():
    w = SpatialWorld()
    w.add_finger(GM, GM.center_theta)
    log = w.run(0.003, lambda t, obs: np.array([100.0, 0.0, 0.0]))
    assert any(e.kind == "torque_saturated" for e in log.events)
    assert log.tau[1, 0] == pytest.approx(GM.torque_limits[0])


def test_sticking_fingertip_does_not_creep():
    """Pressed down with 0.5 N and pushed sideways with 0.1 N < mu f_n: no slip at all."""
    z0 = GM.workspace_center[2] - 0.008
    w = SpatialWorld()
    w.add_surface(Plane((0, 0, z0)), friction=0.5)
    w.add_finger(GM, GM.center_theta)
    fn = reduced_dynamics_function(GM)

    def push(t, obs):
        out = fn(w.finger.th, np.zeros(3), np.zeros(3), 0.0)
        return np.array(out[1]).T @ np.array([0.1, 0.0, -0.5]) + np.array(out[6])

    log = w.run(1.0, push)
    on = log.normal_force[:, 0] > 0
    late = np.flatnonzero(on)[50:]
    slip = np.linalg.norm(log.slip_velocity[late, 0], axis=1)
    assert slip.max() <= 1e-12
    pts = log.contact_point[late, 0]
    assert np.linalg.norm(pts - pts[0], axis=1).max() <= 1e-9


def test_kernel_path_equals_the_general_path():
    """The scalar kernels (numba when installed) give the general numpy path's trajectory."""
    logs = []
    for kernels in (True, False):
        sc = ridge_slide_scene(speed=0.02, travel=0.014, seed=3)
        sc.world.use_kernels = kernels
        logs.append(sc.world.run(0.25, sc.controller))
    a, b = logs
    np.testing.assert_allclose(a.q, b.q, atol=1e-12)
    np.testing.assert_allclose(a.normal_force, b.normal_force, rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(a.poses["finger"], b.poses["finger"], atol=1e-12)
    from planner.sim.spatial.bodies import quat_from_matrix

    w = sc.world
    q = w.pose("finger")[3:]
    np.testing.assert_allclose(q, quat_from_matrix(w.finger.tcs()), atol=1e-15)


@pytest.mark.parametrize("sheath", [0.0, 0.5])
def test_owts_kernel_equals_robots_sampler_and_decoder(sheath):
    from planner.sim.spatial.sensing import OWTSRecorder
    from robots.sensors import OWTS, OWTSSampler, RadialNonlinearity

    rng = np.random.default_rng(5)
    rows = []
    for _ in range(7):
        n = rng.normal(size=3)
        n[2] = abs(n[2]) + 0.5
        rows.append([*(n / np.linalg.norm(n)), rng.uniform(0, 1), *rng.normal(size=3) * 0.1])
    rows += [[0.0] * 7, [1.0, 0.0, 0.01, 0.5, 0.0, 0.0, 0.0]]  # no contact, outside the field
    sensor = OWTS(offsets=(0.02, -0.01))
    nl = RadialNonlinearity(0.1, -0.05, sensor.field_of_detection / sensor.scale)
    rec = [
        OWTSRecorder(OWTSSampler(sensor, rng, nl, sheath_gain=sheath), np.random.default_rng(1))
        for _ in range(2)
    ]
    for r in rows:
        rec[0].push(0.0, r)
    got = rec[0].read()
    v, p, n = rec[1].read_reference(rows)
    np.testing.assert_array_equal(got.voltages, v)
    np.testing.assert_allclose(got.point, p, atol=1e-17)
    np.testing.assert_allclose(got.normal, n, atol=1e-15)
    assert got.in_contact.tolist() == [True] * 7 + [False, False]


def test_plate_kernel_equals_the_plate():
    from planner.sim.spatial import Plate, PlateFeature
    from planner.sim.spatial.kernel import pack_plate, plate_eval

    feats = [PlateFeature(k, 1e-3, 2e-3, (1e-3, -1e-3), 0.3) for k in ("ridge", "ravine", "step")]
    feats += [PlateFeature(k, 1e-3, 2e-3, (-2e-3, 1e-3)) for k in ("bump", "pit", "cusp", "wire")]
    path = ((-4e-3, 0.0), (1e-3, 2e-3), (4e-3, -3e-3))
    feats += [PlateFeature(k, 1e-3, 2e-3, path=path) for k in ("ridge", "wire", "cusp")]
    feats += [PlateFeature("ravine", 1e-3, 2e-3, path=((1e-3, 1e-3),))]
    plate = Plate(tuple(feats), base=0.01)
    F, P = pack_plate(plate)
    for x, y in np.random.default_rng(0).uniform(-6e-3, 6e-3, (200, 2)):
        np.testing.assert_allclose(
            plate_eval(F, P, plate.base, x, y),
            plate.height_derivatives(x, y),
            rtol=1e-13,
            atol=1e-16,
        )


def test_fingertip_pressed_into_a_corner_holds_two_contacts():
    """Two contacts (floor and wall) on one tip: block Gauss-Seidel over exact cones."""
    c = GM.workspace_center
    w = SpatialWorld()
    w.add_surface(Plane((0, 0, c[2] - 0.008)), friction=0.5, name="floor")
    w.add_surface(Plane((c[0] + 0.008, 0, 0), (-1, 0, 0)), friction=0.5, name="wall")
    w.add_finger(GM, GM.center_theta)
    fn = reduced_dynamics_function(GM)

    def push(t, obs):
        out = fn(w.finger.th, np.zeros(3), np.zeros(3), 0.0)
        return np.array(out[1]).T @ np.array([0.4, 0.1, -0.5]) + np.array(out[6])

    log = w.run(0.3, push)
    assert log.status == "ok"
    assert np.all(log.contact_count[1:] == 2)
    assert np.all(log.normal_force[1:, :2] > 0)
    assert np.abs(log.gap[1:, :2]).max() <= 1e-12
    # sticking to the Gauss-Seidel tolerance (1e-13 relative on the impulses)
    assert np.linalg.norm(log.slip_velocity[1:, :2], axis=2).max() <= 1e-10
    x = log.poses["finger"][:, :3]
    assert np.abs(x[1:] - x[-1]).max() <= 1e-12  # no creep


@pytest.mark.parametrize("k, delta", [(0, 5.0), (1, -3.0), (2, 4.0)])
def test_a_start_outside_the_joint_limits_is_refused_naming_the_joint(k, delta):
    """``add_finger`` accepted θ1 = 5 rad (the audit of issue 15); at a limit it is fine."""
    from planner.errors import InvalidParameter

    th = np.array(GM.center_theta, float)
    th[k] = GM.joint_limits[k, 0 if delta < 0 else 1] + delta
    lo, hi = GM.joint_limits[k]
    with pytest.raises(InvalidParameter, match=rf"theta\[{k}\]: joint theta{k + 1} starts at .* "
                       rf"outside its limits \[{lo:.6g}, {hi:.6g}\] rad"):  # fmt: skip
        SpatialWorld().add_finger(GM, th)
    assert SpatialWorld().add_finger(GM, GM.center_theta) == "finger"
