"""Tests of Montana's contact kinematics, the integrator, planar rolling and friction."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.contact import (
    ContactType,
    cone_halfspaces,
    constraint_violations,
    integrate_contact,
    montana_rates,
    planar_cone_edges,
    planar_rolling_arc_length,
    planar_rolling_rates,
    point_contact_margin,
    r_psi,
    soft_finger_margin,
    wrench_basis,
)
from planner.errors import ContactLost, CoordinatePatchExit, InvalidParameter, SingularConfiguration
from planner.geometry import surfaces as S

Z12 = np.zeros((1, 2))


def test_sphere_rolling_on_plane_closed_form():
    r, wy = 0.5, 2.0
    u1d, u2d, psid = montana_rates(
        np.eye(2) / r,
        Z12,
        np.eye(2) * r,
        np.zeros((2, 2)),
        Z12,
        np.eye(2),
        0.0,
        [0, 0, 0],
        [0, wy, 0],
    )
    np.testing.assert_allclose(u1d, [-wy, 0.0])  # M1 u1_dot = r (-wy, 0)
    np.testing.assert_allclose(u2d, [-r * wy, 0.0])
    assert psid == 0.0


@pytest.mark.parametrize("radius", [0.02, 0.5, 3.0])
def test_rolling_on_plane_path_lengths_are_r_theta(radius):
    theta = 0.8
    tr = integrate_contact(
        S.sphere(radius),
        S.plane(),
        [0.1, 0.2],
        [0.0, 0.0],
        0.3,
        ([0, 0, 0], [0.0, theta, 0.0]),
        1.0,
        100,
        length_scale=radius,
    )
    assert tr.path_length1 == pytest.approx(radius * theta, rel=1e-4)
    assert tr.path_length2 == pytest.approx(radius * theta, rel=1e-9)
    assert tr.residual.max() < 1e-9
    np.testing.assert_allclose(tr.psi, 0.3, atol=1e-12)  # no spin, T1 M1 u1_dot = 0 along u


@settings(max_examples=8, deadline=None)
@given(
    r1=st.floats(0.2, 2.0),
    r2=st.floats(0.2, 3.0),
    wx=st.floats(-1, 1),
    wy=st.floats(-1, 1),
    psi=st.floats(-3, 3),
)
def test_sphere_on_sphere_rolling(r1, r2, wx, wy, psi):
    tr = integrate_contact(
        S.sphere(r1),
        S.sphere(r2),
        [0.1, 0.2],
        [-0.2, 0.4],
        psi,
        ([0, 0, 0], [wx, wy, 0.0]),
        0.5,
        40,
        tolerance=1e-7,
    )
    theta = 0.5 * np.hypot(wx, wy)
    expected = theta / (1 / r1 + 1 / r2)
    assert tr.path_length1 == pytest.approx(expected, rel=2e-3, abs=1e-9)
    assert tr.path_length2 == pytest.approx(expected, rel=2e-3, abs=1e-9)


def test_pure_sliding_keeps_the_sliding_bodys_contact_point():
    tr = integrate_contact(
        S.sphere(0.4),
        S.plane(),
        [0.3, -0.2],
        [1.0, 2.0],
        0.7,
        ([0.3, -0.1, 0.0], [0, 0, 0]),
        2.0,
        20,
    )
    np.testing.assert_allclose(tr.u1, np.broadcast_to([0.3, -0.2], tr.u1.shape), atol=1e-12)
    assert tr.path_length2 == pytest.approx(2.0 * np.hypot(0.3, 0.1), rel=1e-9)


def test_spin_changes_only_psi():
    u1d, u2d, psid = montana_rates(
        np.eye(2), Z12, np.eye(2), np.eye(2) * 0.5, Z12, np.eye(2), 0.2, [0, 0, 0], [0, 0, 1.5]
    )
    np.testing.assert_allclose(np.r_[u1d, u2d], 0.0)
    assert psid == pytest.approx(1.5)


def test_combined_motion_on_curved_surfaces_keeps_contact():
    # a bump rolling, sliding and spinning on a sphere: the geometric residual (position,
    # normal and contact angle) validates A.12 including the torsion terms; it must vanish
    # at RK4's order, not stall at a modelling error
    def motion(t):
        return np.array([0.05 * np.cos(t), 0.03, 0.0]), np.array([0.2, -0.4 + 0.1 * t, 0.3])

    res = []
    for steps in (25, 50):
        tr = integrate_contact(
            S.bump(2.0), S.sphere(1.5), [0.2, 1.0], [0.1, 0.3], 0.5, motion, 0.4, steps
        )
        res.append(tr.residual.max())
    assert res[1] < 1e-10 and res[0] / res[1] > 8
    assert np.ptp(tr.psi) > 0.1


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 1000))
def test_sliding_velocity_identity(seed):
    # contact-point velocities on the two bodies differ by exactly the sliding velocity:
    # R_psi (M2 u2_dot) - M1 u1_dot = (vx, vy)
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(2, 2))
    k1 = a @ a.T + np.eye(2)
    k2 = np.diag(rng.uniform(0.1, 2, 2))
    m1, m2 = np.diag(rng.uniform(0.5, 2, 2)), np.diag(rng.uniform(0.5, 2, 2))
    psi = rng.uniform(-np.pi, np.pi)
    v = np.r_[rng.normal(size=2), 0.0]
    w = rng.normal(size=3)
    u1d, u2d, _ = montana_rates(k1, Z12, m1, k2, Z12, m2, psi, v, w)
    np.testing.assert_allclose(r_psi(psi) @ (m2 @ u2d) - m1 @ u1d, v[:2], atol=1e-10)


def test_errors():
    args = (np.eye(2), Z12, np.eye(2), np.eye(2), Z12, np.eye(2), 0.0)
    with pytest.raises(ContactLost, match="vz"):
        montana_rates(*args, [0, 0, 0.1], [0, 0, 0])
    with pytest.raises(InvalidParameter, match="shape"):
        montana_rates(*args, [0, 0], [0, 0, 0])
    with pytest.raises(InvalidParameter, match="finite"):
        montana_rates(np.full((2, 2), np.nan), *args[1:], [0, 0, 0], [0, 0, 0])
    zero = np.zeros((2, 2))
    with pytest.raises(SingularConfiguration, match="singular"):
        montana_rates(zero, Z12, np.eye(2), zero, Z12, np.eye(2), 0.0, [0, 0, 0], [0, 1, 0])
    with pytest.raises(ContactLost, match="vz"):
        integrate_contact(S.sphere(1), S.plane(), [0, 0], [0, 0], 0, ([0, 0, 1], [0, 0, 0]), 1.0, 2)
    with pytest.raises(CoordinatePatchExit, match="left its chart") as info:
        integrate_contact(
            S.sphere(1.0), S.plane(), [1.3, 0], [0, 0], 0, ([0, 0, 0], [0, -1.0, 0]), 1.0, 50
        )
    assert info.value.trajectory.t[-1] < 1.0
    with pytest.raises(InvalidParameter, match="steps: expected an integer >= 1, got 0"):
        integrate_contact(S.sphere(1), S.plane(), [0, 0], [0, 0], 0, ([0, 0, 0], [0, 0, 0]), 1.0, 0)
    with pytest.raises(InvalidParameter, match=r"duration: expected a finite number > 0 \[s\]"):
        integrate_contact(S.sphere(1), S.plane(), [0, 0], [0, 0], 0, ([0, 0, 0], [0, 0, 0]), -1, 2)
    with pytest.raises(InvalidParameter, match=r"u1: expected shape \(2,\)"):
        integrate_contact(S.sphere(1), S.plane(), [0], [0, 0], 0, ([0, 0, 0], [0, 0, 0]), 1.0, 2)


def test_planar_reduction():
    r = 0.02
    u1d, u2d = planar_rolling_rates(
        np.eye(2) / r, np.eye(2) * r, np.zeros((2, 2)), np.eye(2), 0.0, 3.0
    )
    np.testing.assert_allclose(u1d, [-3.0, 0.0])
    np.testing.assert_allclose(u2d, [-3.0 * r, 0.0])
    assert planar_rolling_arc_length(0.5, 1 / r, 0.0) == pytest.approx(r * 0.5)  # s = r theta
    assert planar_rolling_arc_length(1.0, 1.0, 1.0) == pytest.approx(0.5)
    with pytest.raises(SingularConfiguration):
        planar_rolling_arc_length(1.0, 1.0, -1.0)
    assert constraint_violations([0, 0, 0], [0, 1, 0]) == {}
    assert set(constraint_violations([0.1, 0, 0], [0.2, 1, 0.3])) == {
        "no_sliding",
        "no_spin",
        "planar_rolling",
    }
    with pytest.raises(InvalidParameter, match=r"constraints: expected names in \[.*got 'rolling'"):
        constraint_violations([0, 0, 0], [0, 0, 0], ["rolling"])


def test_friction_margins():
    assert point_contact_margin([3.0, 4.0], 10.0, 0.5) == pytest.approx(0.0)
    assert point_contact_margin([[1.0, 0.0]], [1.0], 0.5)[0] == pytest.approx(-0.5)
    # pure spin at the limit: m_z = mu rho f_n
    assert soft_finger_margin([0, 0], 0.5 * 0.01 * 2.0, 2.0, 0.5, 0.01) == pytest.approx(0.0)
    assert soft_finger_margin([0.6, 0.0], 0.008, 2.0, 0.5, 0.01) == pytest.approx(0.0)
    with pytest.raises(
        InvalidParameter, match=r"torsion_length: expected a finite number > 0 \[m\]"
    ):
        soft_finger_margin([0, 0], 0, 1, 0.5, 0.0)
    with pytest.raises(InvalidParameter, match="mu: expected a finite number >= 0, got -0.1"):
        point_contact_margin([0, 0], 1, -0.1)
    with pytest.raises(InvalidParameter, match=r"f_t: expected shape \(..., 2\) \[N\]"):
        point_contact_margin([0, 0, 0], 1, 0.5)


def test_contact_types_and_wrench_bases_of_fig_2_5():
    n = np.array([0.0, 0.0, 2.0])  # normalized inside
    b = wrench_basis(ContactType.FRICTIONLESS, n)
    np.testing.assert_allclose(b[:, 0], [0, 0, 1, 0, 0, 0])
    b = wrench_basis("point_with_friction", n)
    assert b.shape == (6, 3) and np.allclose(b[:3], np.eye(3)) and not b[3:].any()
    b = wrench_basis(ContactType.SOFT_FINGER, [1.0, 0.0, 0.0])
    assert b.shape == (6, 4)
    np.testing.assert_allclose(b[:, 3], [0, 0, 0, 1, 0, 0])  # the moment about the normal
    with pytest.raises(InvalidParameter, match="contact_type: expected one of"):
        wrench_basis("sticky", n)
    with pytest.raises(InvalidParameter, match="normal: expected a non-zero direction"):
        wrench_basis("soft_finger", [0, 0, 0])


@pytest.mark.parametrize("mu", [0.0, 0.3, 1.2])
def test_cone_facets_contain_exactly_the_edges(mu):
    rng = np.random.default_rng(4)
    n2 = rng.normal(size=(5, 2))
    edges = planar_cone_edges(n2, mu)  # (k, 2, 2) exact planar edges: on both facets' planes
    facets = cone_halfspaces(n2, mu)
    for i in range(5):
        vals = facets[i] @ edges[i].T  # (2 facets, 2 edges)
        assert np.all(vals <= 1e-12) and np.allclose(np.min(np.abs(vals), axis=0), 0, atol=1e-12)
    n3 = rng.normal(size=(4, 3))
    f3 = cone_halfspaces(n3, mu, facets=6)
    unit = n3 / np.linalg.norm(n3, axis=1, keepdims=True)
    for i in range(4):  # the normal is inside; every inscribed-pyramid facet passes the apex
        assert np.all(f3[i] @ unit[i] <= -mu * np.cos(np.pi / 6) + 1e-12)
    with pytest.raises(InvalidParameter, match=r"normals: expected shape \(N, 2 or 3\)"):
        cone_halfspaces(np.ones((3, 4)), 0.5)


def test_rolling_on_a_height_field():
    x = np.linspace(-1, 1, 21)
    floor = S.HeightField(x, x, np.zeros((21, 21)))
    tr = integrate_contact(
        S.sphere(0.1), floor, [0.3, 0.0], [0.0, 0.0], 0.0, ([0, 0, 0], [0.0, 1.0, 0.0]), 1.0, 100
    )
    assert tr.path_length2 == pytest.approx(0.1, rel=1e-9)
    assert tr.residual.max() < 1e-9
