"""Tests of robots.three_gm: eqs. C.4-C.11 and 4.1 vs Pinocchio, finite differences, statics."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter, SingularConfiguration
from robots.errors import UnreachableTarget
from robots.three_gm import (
    ThreeGM,
    check_conditioned_workspace,
    closure_constraint,
    solve_closed_loop,
    trapezoid_grid,
    trapezoid_volume,
)
from robots.three_gm.model import configuration

GM = ThreeGM()
INCH = 0.0254


def _random_thetas(seed: int, n: int) -> list[np.ndarray]:
    """Seeded random configurations inside the limits where the loop closes."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        th = rng.uniform(GM.joint_limits[:, 0], GM.joint_limits[:, 1])
        try:
            st_ = GM.state(th)
        except SingularConfiguration:
            continue
        if abs(np.sin(st_.gamma2 - st_.gamma1)) > 0.1:
            out.append(th)
    return out


def _fd_jacobian(th, h=1e-6):
    return np.column_stack(
        [
            (GM.forward_kinematics(th + e) - GM.forward_kinematics(th - e)) / (2 * h)
            for e in np.eye(3) * h
        ]
    )


def test_public_attributes():
    assert set(GM.params) == {"l1", "l2", "l3", "l4", "l5", "h1", "h2", "h3"}
    assert GM.joint_limits.shape == (3, 2)
    assert GM.model.nq == 5


def test_loop_closes_and_matches_eq_c4_c6():
    p = GM.params
    for th in _random_thetas(0, 20):
        st_ = GM.state(th)
        t1, t2, t3 = th
        u = lambda a: np.array([np.cos(a), np.sin(a)])  # noqa: E731
        P1, P2 = p["l1"] * u(t1), np.array([0.0, -p["h1"]]) + p["l2"] * u(t2)
        np.testing.assert_allclose(
            P1 + p["l4"] * u(st_.gamma1), P2 + p["l3"] * u(st_.gamma2), atol=1e-14
        )
        np.testing.assert_allclose([st_.a1, st_.a2], P1 - P2, atol=1e-15)
        E = P1 + p["l5"] * u(st_.gamma1)
        x = GM.forward_kinematics(th)
        np.testing.assert_allclose(x[2], E[1], atol=1e-15)
        rho = np.array([E[0] + p["h2"], -p["h3"]])
        c, s = np.cos(t3), np.sin(t3)
        np.testing.assert_allclose(
            x[:2], [c * rho[0] - s * rho[1], s * rho[0] + c * rho[1]], atol=1e-15
        )


def test_closed_form_matches_pinocchio():
    for th in _random_thetas(1, 15):
        g1, g2 = GM.passive_angles(th)
        q0 = configuration(th, g1, g2)
        k = solve_closed_loop(GM.model, th, q0 + 0.05)  # Pinocchio closes the loop itself
        np.testing.assert_allclose(k.q[[2, 4]], q0[[2, 4]], atol=1e-10)
        np.testing.assert_allclose(k.position, GM.forward_kinematics(th), atol=1e-14)
        np.testing.assert_allclose(k.jacobian, GM.jacobian(th), atol=1e-12)


def test_rigid_constraint_model_vanishes_on_closed_loop():
    import pinocchio as pin

    c = closure_constraint(GM.model, GM.params)
    assert c.residualSize() == 3
    data, cdata = GM.model.createData(), c.createData()
    for th in _random_thetas(6, 5):
        q = configuration(th, *GM.passive_angles(th))
        pin.forwardKinematics(GM.model, data, q)
        c.calc(GM.model, data, cdata)
        np.testing.assert_allclose(cdata.c1Mc2.translation, 0.0, atol=1e-14)
        q[2] += 0.1  # open the loop: the constraint residual is no longer zero
        pin.forwardKinematics(GM.model, data, q)
        c.calc(GM.model, data, cdata)
        assert np.linalg.norm(cdata.c1Mc2.translation) > 1e-3


def test_jacobian_matches_finite_differences():
    for th in _random_thetas(2, 15):
        np.testing.assert_allclose(GM.jacobian(th), _fd_jacobian(th), atol=1e-8)


def test_statics_virtual_work():
    rng = np.random.default_rng(3)
    for th in _random_thetas(4, 10):
        f = rng.normal(size=3)
        tau = GM.joint_torques(th, f)
        dth = rng.normal(size=3) * 1e-7
        dx = GM.forward_kinematics(th + dth) - GM.forward_kinematics(th - dth)
        assert np.isclose(tau @ (2 * dth), f @ dx, rtol=1e-6, atol=1e-16)
        qd = rng.normal(size=3)
        np.testing.assert_allclose(GM.endpoint_velocity(th, qd), GM.jacobian(th) @ qd)


def test_singular_configuration_raises_with_value():
    th = np.deg2rad([90.0, -90.0, 0.0])  # |a| = l1 + l2 + h1: the loop cannot close
    with pytest.raises(SingularConfiguration, match="outside") as info:
        GM.forward_kinematics(th)
    assert abs(info.value.value) > 1.0
    with pytest.raises(SingularConfiguration):
        GM.jacobian(th)


def test_rotation_tcs_to_wcs_eq_4_1():
    for th in _random_thetas(5, 5):
        R = GM.rotation_tcs_to_wcs(th)
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-14)
        assert np.isclose(np.linalg.det(R), 1.0)
        a, b = np.pi / 2 + GM.passive_angles(th)[0], np.pi / 2 - th[2]
        Rz = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
        Rx = np.array([[1, 0, 0], [0, np.cos(b), -np.sin(b)], [0, np.sin(b), np.cos(b)]])
        np.testing.assert_allclose(R, Rz @ Rx, atol=1e-15)


def test_gravity_torque_eq_c11():
    th = np.array([0.3, 1.2, 0.1])
    tau = GM.gravity_torque(th, 0.2)
    np.testing.assert_allclose(tau, [0.2 * 9.81 * GM.params["l5"] * np.cos(0.3), 0, 0])
    with pytest.raises(
        InvalidParameter, match=r"mass: expected a finite number >= 0 \[kg\], got -1.0"
    ):
        GM.gravity_torque(th, -1.0)


def test_limits_at_workspace_centre():
    th = GM.center_theta
    np.testing.assert_allclose(GM.forward_kinematics(th), GM.workspace_center, atol=1e-12)
    assert np.isclose(GM.force_capacity(th), 9.0)
    # one encoder count moves the endpoint by at most 0.05 mm at the centre
    steps = [
        np.linalg.norm(GM.forward_kinematics(th + e) - GM.forward_kinematics(th))
        for e in np.eye(3) * GM.encoder_resolution
    ]
    assert max(steps) == pytest.approx(0.05e-3, rel=1e-3)


@settings(max_examples=30, deadline=None)
@given(st.floats(0, 1), st.floats(0, 1), st.floats(0, 1))
def test_ik_round_trip_in_trapezoid(a, b, c):
    from robots.three_gm.params import WORKSPACE_HALF_ANGLE, WORKSPACE_RADII, WORKSPACE_Z

    rho = WORKSPACE_RADII[0] + a * (WORKSPACE_RADII[1] - WORKSPACE_RADII[0])
    ang = (2 * b - 1) * WORKSPACE_HALF_ANGLE
    z = WORKSPACE_Z[0] + c * (WORKSPACE_Z[1] - WORKSPACE_Z[0])
    x = np.array([rho * np.cos(ang), rho * np.sin(ang), z])
    th = GM.inverse_kinematics(x)
    assert GM.within_limits(th)
    np.testing.assert_allclose(GM.forward_kinematics(th), x, atol=1e-10)
    assert GM.in_conditioned_workspace(x)


def test_ik_unreachable_and_bad_input():
    with pytest.raises(UnreachableTarget, match="cannot reach"):
        GM.inverse_kinematics([1.0, 0.0, 0.0])
    with pytest.raises(InvalidParameter, match=r"theta: expected shape \(3,\) \[rad\]"):
        GM.forward_kinematics([0.1, 0.2])
    with pytest.raises(InvalidParameter, match=r"params: expected keys in \['l1'.*got 'l9'"):
        ThreeGM({"l9": 0.1})
    with pytest.raises(InvalidParameter, match=r"l1: expected a finite number > 0 \[m\], got -0.1"):
        ThreeGM({"l1": -0.1})
    with pytest.raises(InvalidParameter, match=r"h1: expected a number in \(-inf, inf\) \[m\]"):
        ThreeGM({"h1": float("nan")})
    with pytest.raises(InvalidParameter, match=r"joint_limits: expected shape \(N, 2\)"):
        ThreeGM(joint_limits=[[0.0, 1.0, 2.0]] * 3)
    with pytest.raises(InvalidParameter, match="joint_limits: expected lower < upper"):
        ThreeGM(joint_limits=[[1.0, 0.0]] * 3)


def test_conditioned_workspace_matches_appendix_c2():
    assert trapezoid_volume() / INCH**3 == pytest.approx(112.0)
    w = check_conditioned_workspace(GM, trapezoid_grid(4))
    assert w.reachable.all()
    assert w.condition.max() < 7.0
    assert w.force_capacity.min() > 4.0


def test_ik_round_trip_anywhere_in_joint_space():
    """Targets from random non-singular configurations, not only the trapezoid (multi-start)."""
    rng = np.random.default_rng(11)
    done = 0
    while done < 40:
        th = rng.uniform(GM.joint_limits[:, 0], GM.joint_limits[:, 1])
        try:
            x = GM.forward_kinematics(th)
        except SingularConfiguration:
            continue
        sol = GM.inverse_kinematics(x)
        assert GM.within_limits(sol)
        np.testing.assert_allclose(GM.forward_kinematics(sol), x, atol=1e-10)
        done += 1
