"""Force closure, ε quality, cones, grasp matrix and stability (planner.grasp)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.contact import planar_cone_edges, pyramid_cone_edges, soft_finger_generators
from planner.errors import InvalidParameter
from planner.grasp import (
    epsilon_quality,
    force_closure,
    force_closure_lp,
    force_closure_two_planar,
    grasp_matrix,
    hand_jacobian,
    joint_torques,
    two_contact_stability,
)
from planner.grasp.quality import epsilon_two_planar


def circle_contacts(theta, radius=1.0, center=(0.0, 0.0)):
    theta = np.asarray(theta, float)
    u = np.stack([np.cos(theta), np.sin(theta)], axis=-1)
    return np.asarray(center) + radius * u, -u


def rigid(points, normals, angle, shift, scale=1.0):
    c, s = np.cos(angle), np.sin(angle)
    R = np.array([[c, -s], [s, c]])
    return scale * points @ R.T + shift, normals @ R.T


# ----------------------------------------------------------------------- closed forms
@pytest.mark.parametrize("mu", [0.0, 0.2, 0.5, 1.0, 2.0])
def test_circle_closure_iff_separation_exceeds_pi_minus_twice_atan_mu(mu):
    rng = np.random.default_rng(1)
    t = rng.uniform(0, 2 * np.pi, size=(400, 2))
    sep = np.abs(np.angle(np.exp(1j * (t[:, 0] - t[:, 1]))))  # in [0, pi]
    expected = sep > np.pi - 2 * np.arctan(mu)
    keep = np.abs(sep - (np.pi - 2 * np.arctan(mu))) > 1e-9
    for (a, b), e in zip(t[keep], expected[keep], strict=True):
        p, n = circle_contacts([a, b], radius=0.05)
        assert force_closure(p, n, mu) == e


@pytest.mark.parametrize("mu", [0.1, 0.5, 1.0, 3.0])
def test_antipodal_epsilon_closed_form(mu):
    # tetrahedron of 4 symmetric wrenches: every face at mu / sqrt((1+mu^2)(2+mu^2))
    p, n = circle_contacts([0.3, 0.3 + np.pi], radius=0.07, center=(1.0, -2.0))
    expected = mu / np.sqrt((1 + mu**2) * (2 + mu**2))
    assert epsilon_quality(p, n, mu) == pytest.approx(expected, rel=1e-12)
    # the general hull path agrees with the closed form
    assert epsilon_quality(p, n, mu, torque_scale=0.07) == pytest.approx(expected, rel=1e-9)


def test_frictionless_two_contacts_never_closure():
    p, n = circle_contacts([0.0, np.pi])
    assert not force_closure(p, n, 0.0)
    assert epsilon_quality(p, n, 0.0) == 0.0


def test_three_frictionless_contacts_on_triangle_not_closure_but_four_with_friction_are():
    p, n = circle_contacts([0, 2 * np.pi / 3, 4 * np.pi / 3])
    assert not force_closure(p, n, 0.0)  # a circle can spin freely
    assert force_closure(p, n, 0.3)
    assert 0 < epsilon_quality(p, n, 0.3) < 1


def test_spatial_point_contacts():
    # three contacts around a sphere's equator with friction: force closure
    t = np.array([0, 2 * np.pi / 3, 4 * np.pi / 3])
    p = np.stack([np.cos(t), np.sin(t), np.zeros(3)], axis=1)
    assert force_closure(p, -p, 0.5)
    assert epsilon_quality(p, -p, 0.5) > 0
    # two spatial point contacts can never resist a torque about their line
    assert not force_closure(p[:2] * [1, 1, 0] + [0, 0, 0], -p[:2], 2.0)
    assert not force_closure(
        np.array([[1.0, 0, 0], [-1.0, 0, 0]]), np.array([[-1.0, 0, 0], [1.0, 0, 0]]), 2.0
    )


def test_lp_and_closed_form_agree_on_thousands_of_random_grasps():
    rng = np.random.default_rng(7)
    n_checked = 0
    pts = rng.normal(size=(3000, 2, 2))
    ang = rng.uniform(0, 2 * np.pi, size=(3000, 2))
    nrm = np.stack([np.cos(ang), np.sin(ang)], axis=-1)
    mu = rng.uniform(0.05, 1.5, size=3000)
    for k in range(3000):
        fc = bool(force_closure_two_planar(pts[k, 0], nrm[k, 0], pts[k, 1], nrm[k, 1], mu[k]))
        eps = float(epsilon_two_planar(pts[k, 0], nrm[k, 0], pts[k, 1], nrm[k, 1], mu[k]))
        assert fc == (eps > 0)
        if k < 300:  # the LP is slower: a subset
            assert force_closure_lp(pts[k], nrm[k], mu[k]) == fc
            n_checked += 1
        # the hull path (generic torque scale) agrees too
        e_hull = epsilon_quality(
            pts[k], nrm[k], mu[k], torque_scale=np.linalg.norm(pts[k, 1] - pts[k, 0]) / 2
        )
        assert e_hull == pytest.approx(eps, abs=1e-9)
    assert n_checked == 300


def test_lp_agrees_with_hull_for_three_and_four_contacts():
    rng = np.random.default_rng(3)
    for k in (3, 4):
        for _ in range(60):
            t = rng.uniform(0, 2 * np.pi, size=k)
            p, n = circle_contacts(t)
            mu = rng.uniform(0.0, 0.8)
            assert force_closure_lp(p, n, mu) == force_closure(p, n, mu)


# ----------------------------------------------------------------------- invariances
@settings(max_examples=40, deadline=None)
@given(
    t=st.lists(st.floats(0, 2 * np.pi), min_size=2, max_size=4),
    mu=st.floats(0.05, 2.0),
    angle=st.floats(-np.pi, np.pi),
    shift=st.tuples(st.floats(-5, 5), st.floats(-5, 5)),
    scale=st.floats(0.01, 100),
)
def test_closure_and_epsilon_invariant_under_rigid_motion_and_scaling(t, mu, angle, shift, scale):
    rng = np.random.default_rng(0)
    p, _ = circle_contacts(t)
    p = p + rng.normal(scale=0.05, size=p.shape)
    n = -p / np.linalg.norm(p, axis=1, keepdims=True)
    p2, n2 = rigid(p, n, angle, np.array(shift), scale)
    e1, e2 = epsilon_quality(p, n, mu), epsilon_quality(p2, n2, mu)
    if min(e1, e2) > 1e-7 or max(e1, e2) == 0:
        assert force_closure(p, n, mu) == force_closure(p2, n2, mu)
    assert e1 == pytest.approx(e2, abs=1e-7)


def test_spatial_epsilon_invariant_under_rotation():
    rng = np.random.default_rng(5)
    t = np.array([0.1, 2.2, 4.0])
    p = np.stack([np.cos(t), np.sin(t), rng.normal(scale=0.2, size=3)], axis=1)
    n = -p / np.linalg.norm(p, axis=1, keepdims=True)
    from scipy.spatial.transform import Rotation

    R = Rotation.from_rotvec([0.3, -1.1, 0.7]).as_matrix()
    e1 = epsilon_quality(p, n, 0.6)
    e2 = epsilon_quality(p @ R.T + [1, 2, 3], n @ R.T, 0.6)
    assert e1 > 0
    assert e1 == pytest.approx(e2, rel=1e-9)


# ----------------------------------------------------------------------- cones
def test_cone_edges_lie_on_the_cone():
    n = np.array([[0.0, 1.0], [1.0, 1.0]]) / [[1.0], [np.sqrt(2)]]
    e = planar_cone_edges(n, 0.7)
    for i in range(2):
        for j in range(2):
            fn = e[i, j] @ n[i]
            ft = abs(n[i, 0] * e[i, j, 1] - n[i, 1] * e[i, j, 0])  # 2-D cross product
            assert ft == pytest.approx(0.7 * fn)
            assert np.linalg.norm(e[i, j]) == pytest.approx(1.0)
    e3 = pyramid_cone_edges([[0, 0, 1.0]], 0.5, facets=6)
    assert e3.shape == (1, 6, 3)
    assert np.allclose(np.linalg.norm(e3[0, :, :2], axis=1) / e3[0, :, 2], 0.5)


def test_soft_finger_generators_inside_elliptic_limit_surface():
    g = soft_finger_generators([[0.0, 0.0, 1.0]], 0.4, 0.01, facets=8)
    f, m = g[0, :, :3], g[0, :, 3:]
    fn = f[:, 2]
    lhs = np.linalg.norm(f[:, :2], axis=1) ** 2 / 0.4**2 + m[:, 2] ** 2 / 0.01**2
    assert np.all(lhs <= fn**2 + 1e-12)


# ----------------------------------------------------------------------- grasp matrix
def test_grasp_matrix_maps_forces_to_wrench_and_its_transpose_to_velocities():
    rng = np.random.default_rng(2)
    p = rng.normal(size=(3, 2))
    f = rng.normal(size=(3, 2))
    G = grasp_matrix(p, torque_reference=[0.0, 0.0])
    tau = np.sum(p[:, 0] * f[:, 1] - p[:, 1] * f[:, 0])
    assert np.allclose(G @ f.ravel(), [*f.sum(axis=0), tau])
    # G^T twist = contact velocities: finite difference of a rigid motion (eq. 2.6)
    v, w, h = np.array([0.3, -0.2]), 0.7, 1e-7
    c, s = np.cos(w * h), np.sin(w * h)
    moved = p @ np.array([[c, -s], [s, c]]).T + v * h
    assert np.allclose(G.T @ [*v, w], ((moved - p) / h).ravel(), atol=1e-6)


def test_spatial_grasp_matrix_finite_difference_and_soft_finger_columns():
    rng = np.random.default_rng(4)
    p = rng.normal(size=(2, 3))
    G = grasp_matrix(p, torque_reference=np.zeros(3))
    v, w, h = rng.normal(size=3), rng.normal(size=3), 1e-7
    from scipy.spatial.transform import Rotation

    moved = p @ Rotation.from_rotvec(w * h).as_matrix().T + v * h
    assert np.allclose(G.T @ np.concatenate([v, w]), ((moved - p) / h).ravel(), atol=1e-6)
    n = -p / np.linalg.norm(p, axis=1, keepdims=True)
    Gs = grasp_matrix(p, np.zeros(3), normals=n, soft_finger=True)
    assert Gs.shape == (6, 8)
    assert np.allclose(Gs[3:, 3], n[0])


def test_hand_jacobian_statics():
    J1, J2 = np.arange(6.0).reshape(2, 3), np.ones((2, 3))
    J = hand_jacobian([J1, J2])
    assert J.shape == (4, 6) and np.allclose(J[2:, 3:], J2) and np.allclose(J[:2, 3:], 0)
    tau = joint_torques([J1, J2], [[1.0, 0.0], [0.0, 2.0]])
    assert np.allclose(tau, np.concatenate([J1.T @ [1, 0], J2.T @ [0, 2]]))


# ----------------------------------------------------------------------- stability
def test_yoshikawa_nagai_fig_2_11():
    # (b) stable: contact line inside both cones; (a) unstable: outside one
    stable = two_contact_stability([[0, 0], [1, 0.2]], [[1, 0], [-1, 0]], 0.5)
    assert stable.stable and stable.margin > 0
    assert np.all(stable.tangential_ratio <= 0.5)
    unstable = two_contact_stability([[0, 0], [1, 0.8]], [[1, 0], [-1, 0]], 0.5)
    assert not unstable.stable and unstable.margin < 0
    assert unstable.margin == pytest.approx(np.arctan(0.5) - np.arctan(0.8))


# ----------------------------------------------------------------------- errors
def test_bad_inputs_raise_invalid_parameter():
    p, n = circle_contacts([0, np.pi])
    with pytest.raises(InvalidParameter, match=r"mu: expected a finite number >= 0, got -1.0"):
        force_closure(p, n, -1.0)
    with pytest.raises(InvalidParameter, match="shape"):
        force_closure(p[:, :1], n, 1.0)
    with pytest.raises(InvalidParameter, match="at least 2"):
        epsilon_quality(p[:1], n[:1], 1.0)
    with pytest.raises(InvalidParameter, match="non-zero"):
        force_closure(p, [[0, 0], [1, 0]], 1.0)
    with pytest.raises(InvalidParameter, match="points: row 0 is not finite"):
        epsilon_quality([[np.nan, 0], [1, 0]], n, 1.0)
    with pytest.raises(InvalidParameter, match=r"torque_scale: expected a finite number > 0 \[m\]"):
        epsilon_quality(p, n, 1.0, torque_scale=0.0)
    with pytest.raises(InvalidParameter, match="facets: expected an integer >= 3, got 2"):
        pyramid_cone_edges([[0, 0, 1.0]], 0.5, facets=2)


def test_contact_models_of_fig_2_5():
    # two spatial point contacts cannot resist a torque about their line; soft fingers can
    p = np.array([[0.05, 0.0, 0.0], [-0.05, 0.0, 0.0]])
    n = -p / 0.05
    assert not force_closure(p, n, 0.8)
    assert force_closure(p, n, 0.8, contact="soft_finger", torsion_length=0.005)
    e_small = epsilon_quality(p, n, 0.8, contact="soft_finger", torsion_length=0.001)
    e_large = epsilon_quality(p, n, 0.8, contact="soft_finger", torsion_length=0.01)
    assert 0 < e_small < e_large
    # frictionless contacts ignore mu
    t = np.array([0.0, 2.1, 4.2])
    q = np.c_[np.cos(t), np.sin(t)]
    assert force_closure(q, -q, 0.5) and not force_closure(q, -q, 0.5, contact="frictionless")
    with pytest.raises(
        InvalidParameter,
        match=r"contact: expected one of \['frictionless', 'point_with_friction', 'soft_finger'\]",
    ):
        force_closure(q, -q, 0.5, contact="sticky")
    with pytest.raises(
        InvalidParameter, match=r"torsion_length: expected a finite number > 0 \[m\]"
    ):
        force_closure(p, n, 0.5, contact="soft_finger")


def test_hand_jacobian_of_the_planar_hand_by_finite_differences():
    from robots.planar_hand import PlanarHand

    hand = PlanarHand()
    q = hand.neutral()
    Jh = hand_jacobian([hand.jacobian(q, "left"), hand.jacobian(q, "right")])
    dq = np.random.default_rng(0).normal(size=6)
    h = 1e-7
    tips0, tips1 = hand.fingertip_positions(q), hand.fingertip_positions(q + h * dq)
    xdot = np.concatenate([(tips1[f] - tips0[f]) / h for f in ("left", "right")])
    assert np.allclose(Jh @ dq, xdot, atol=1e-5)  # eq. 2.5
    f = np.array([[0.3, -0.1], [-0.2, 0.4]])
    tau = joint_torques([hand.jacobian(q, "left"), hand.jacobian(q, "right")], f)
    assert tau @ dq == pytest.approx(f.ravel() @ (Jh @ dq))  # virtual work
