"""Tests of parametric surfaces: closed forms of App. A and §3.2.3, FD checks, invariants."""

import casadi as ca
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.geometry import surfaces as S

RNG = np.random.default_rng(7)


@settings(max_examples=25, deadline=None)
@given(r=st.floats(0.01, 100.0), u=st.floats(-1.4, 1.4), v=st.floats(-3.1, 3.1))
def test_sphere_eq_a10(r, u, v):
    s = S.sphere(r)
    np.testing.assert_allclose(s.curvature_matrix(u, v), np.eye(2) / r, atol=1e-9 / r)
    np.testing.assert_allclose(s.torsion(u, v), [[0.0, -np.tan(u) / r]], atol=1e-9 / r)
    np.testing.assert_allclose(s.metric(u, v), np.diag([r, r * np.cos(u)]), atol=1e-9 * r)
    k1, k2 = s.principal_curvatures(u, v)
    assert k1 == pytest.approx(1 / r) and k2 == pytest.approx(1 / r)


def test_sphere_frame_is_eq_a9_with_y_and_z_in_their_right_places():
    u, v, r = 0.4, -1.1, 2.0
    s = S.sphere(r)
    frame = s.gauss_frame(u, v)
    x = [-np.sin(u) * np.cos(v), np.sin(u) * np.sin(v), np.cos(u)]
    y = [-np.sin(v), -np.cos(v), 0.0]
    z = [np.cos(u) * np.cos(v), -np.cos(u) * np.sin(v), np.sin(u)]
    np.testing.assert_allclose(frame, np.column_stack([x, y, z]), atol=1e-12)
    np.testing.assert_allclose(s.point(u, v), r * np.array(z), atol=1e-12)


def test_shapes_scalars_and_arrays():
    s = S.sphere(1.0)
    assert s.point(0.1, 0.2).shape == (3,)
    assert s.gauss_frame(0.1, 0.2).shape == (3, 3)
    assert s.curvature_matrix(0.1, 0.2).shape == (2, 2)
    assert s.torsion(0.1, 0.2).shape == (1, 2)
    assert s.metric(0.1, 0.2).shape == (2, 2)
    u = np.linspace(-1, 1, 5)
    assert s.gauss_frame(u, 0.3).shape == (5, 3, 3)
    assert s.torsion(u[:, None], u[None, :]).shape == (5, 5, 1, 2)
    k1, k2 = s.principal_curvatures(u, u)
    assert k1.shape == k2.shape == (5,)
    g = s.evaluate(u, 0.0)
    np.testing.assert_allclose(g.curvature_matrix, s.curvature_matrix(u, 0.0))


def bump_closed_form(u, v, a):
    d = 1 + a * u**2
    c = np.sqrt(1 + 4 * a**2 * u**2 / d**4)
    x = np.array([np.cos(v) / c, np.sin(v) / c, -2 * a * u / (c * d**2)])
    y = np.array([-np.sin(v), np.cos(v), 0.0])
    z = np.array([2 * a * u / (c * d**2) * np.cos(v), 2 * a * u / (c * d**2) * np.sin(v), 1 / c])
    k = np.diag(
        [2 * a * d * (1 - 3 * a * u**2) / (c * (d**4 + 4 * a**2 * u**2)), 2 * a / (c * d**2)]
    )
    return np.column_stack([x, y, z]), k


@pytest.mark.parametrize("u", [-0.8, -0.3, -0.05, 0.05, 0.2, 0.7])
@pytest.mark.parametrize("a", [0.5, 15.0])
def test_bump_eq_3_14_and_3_17(u, a):
    # eq. 3.14 prints x_z = +2au/(cd^2): x = f_u/|f_u| has z-component h'(u)/c = -2au/(cd^2),
    # and x must be orthogonal to z, so the OCR'd sign is wrong; the closed form uses -.
    b = S.bump(a)
    frame, k = bump_closed_form(u, 0.6, a)
    np.testing.assert_allclose(b.gauss_frame(u, 0.6), frame, atol=1e-12)
    np.testing.assert_allclose(b.curvature_matrix(u, 0.6), k, rtol=1e-9, atol=1e-12)


def test_bump_apex_is_a_removable_singularity():
    b = S.bump(15.0)
    np.testing.assert_allclose(b.curvature_matrix(0.0, 1.0), 30 * np.eye(2), rtol=1e-6, atol=1e-9)
    assert np.all(np.isfinite(b.gauss_frame(0.0, 1.0)))
    np.testing.assert_allclose(
        S.pit(15.0).curvature_matrix(0.3, 1.0), -b.curvature_matrix(0.3, 1.0), atol=1e-12
    )


@settings(max_examples=20, deadline=None)
@given(r=st.floats(0.01, 50.0), u=st.floats(-3.0, 3.0), v=st.floats(-5.0, 5.0))
def test_cylinder_principal_curvatures(r, u, v):
    k1, k2 = S.cylinder(r).principal_curvatures(u, v)
    assert k1 == pytest.approx(1 / r) and k2 == pytest.approx(0.0, abs=1e-9 / r)
    p1, p2 = S.cylinder(r).principal_directions(u, v)
    assert abs(p1[2]) < 1e-9 and abs(abs(p2[2]) - 1) < 1e-9  # k2 runs along the axis


def random_rotation(rng):
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 10_000), shift=st.floats(-0.3, 0.3))
def test_curvatures_invariant_under_rigid_motion_and_shift(seed, shift):
    rng = np.random.default_rng(seed)
    rot, t = random_rotation(rng), rng.normal(size=3)
    base = S.bump(4.0)

    def moved(u, v):
        p = base.surface_map(u - shift, v)
        return [sum(rot[i, j] * p[j] for j in range(3)) + t[i] for i in range(3)]

    m = S.ParametricSurface(
        moved, ((-0.7, 1.3), (0, np.pi)), orientation=lambda u, v: ca.sign(u - shift)
    )
    u = rng.uniform(0.05, 0.9, 6) * rng.choice([-1, 1], 6)
    v = rng.uniform(0.1, 3.0, 6)
    np.testing.assert_allclose(
        m.curvature_matrix(u + shift, v), base.curvature_matrix(u, v), rtol=1e-8, atol=1e-8
    )
    np.testing.assert_allclose(
        m.gauss_frame(u + shift, v), rot @ base.gauss_frame(u, v), atol=1e-10
    )


@pytest.mark.parametrize(
    "surf", [S.bump(3.0), S.ridge(1.0, 0.7, bend_radius=4.0), S.sphere(1.5), S.step(0.5, 0.4)]
)
def test_forms_against_finite_differences(surf):
    (u0, u1), (v0, v1) = surf.domain
    u = RNG.uniform(max(u0, -1) * 0.8, min(u1, 1) * 0.8, 5)
    u = np.where(np.abs(u) < 0.05, 0.1, u)
    v = RNG.uniform(max(v0, -1) * 0.8 + 0.1, min(v1, 1) * 0.8, 5)
    h = 1e-6
    fu_fd = (surf.point(u + h, v) - surf.point(u - h, v)) / (2 * h)
    fv_fd = (surf.point(u, v + h) - surf.point(u, v - h)) / (2 * h)
    fu, fv = surf.tangents(u, v)
    np.testing.assert_allclose(fu, fu_fd, atol=1e-6)
    np.testing.assert_allclose(fv, fv_fd, atol=1e-6)
    frame = surf.gauss_frame(u, v)
    dz = np.stack(
        [
            (surf.normal(u + h, v) - surf.normal(u - h, v)) / (2 * h),
            (surf.normal(u, v + h) - surf.normal(u, v - h)) / (2 * h),
        ],
        axis=-1,
    )
    dx = np.stack(
        [
            (surf.gauss_frame(u + h, v)[..., 0] - surf.gauss_frame(u - h, v)[..., 0]),
            (surf.gauss_frame(u, v + h)[..., 0] - surf.gauss_frame(u, v - h)[..., 0]),
        ],
        axis=-1,
    ) / (2 * h)
    minv = np.linalg.inv(surf.metric(u, v))
    k_fd = np.swapaxes(frame[..., :2], -1, -2) @ dz @ minv
    t_fd = np.swapaxes(frame[..., 1:2], -1, -2) @ dx @ minv
    np.testing.assert_allclose(surf.curvature_matrix(u, v), k_fd, atol=1e-5)
    np.testing.assert_allclose(surf.torsion(u, v), t_fd, atol=1e-5)


def test_non_orthogonal_graph_of_a_sphere_cap():
    r = 2.0
    cap = S.ParametricSurface(
        lambda u, v: [u, v, ca.sqrt(r**2 - u**2 - v**2)], ((-1, 1), (-1, 1)), name="cap"
    )
    u, v = np.array([0.3, -0.5, 0.7]), np.array([0.6, 0.2, -0.4])
    assert np.all(cap.orthogonality(u, v) > 0.01)
    np.testing.assert_allclose(
        cap.curvature_matrix(u, v), np.broadcast_to(np.eye(2) / r, (3, 2, 2)), atol=1e-9
    )
    frame = cap.gauss_frame(u, v)
    np.testing.assert_allclose(
        np.swapaxes(frame, -1, -2) @ frame, np.broadcast_to(np.eye(3), (3, 3, 3)), atol=1e-12
    )
    # M maps parameter rates to frame velocities: [x y]^T (f_u du + f_v dv) = M (du, dv)
    fu, fv = cap.tangents(u, v)
    m = cap.metric(u, v)
    np.testing.assert_allclose(np.einsum("nij,ni->nj", frame[..., :2], fu), m[..., 0], atol=1e-12)
    np.testing.assert_allclose(m[..., 1, 0], 0.0, atol=1e-12)


@settings(max_examples=15, deadline=None)
@given(r=st.floats(0.1, 5.0), d=st.floats(-0.05, 3.0))
def test_parallel_surface_of_sphere(r, d):
    p = S.sphere(r).parallel(d)
    u, v = np.array([0.2, -0.9]), np.array([1.0, -2.5])
    np.testing.assert_allclose(np.linalg.norm(p.point(u, v), axis=-1), r + d, rtol=1e-12)
    k1, k2 = p.principal_curvatures(u, v)
    np.testing.assert_allclose(k1, 1 / (r + d), rtol=1e-9)


def test_parallel_curvature_formula_and_caustics():
    b, rf = S.bump(15.0), 1.0
    u = np.array([-0.6, -0.2, 0.1, 0.5])
    k1, k2 = b.principal_curvatures(u, 0.5)
    kp1, kp2 = b.parallel(0.05).principal_curvatures(u, 0.5)
    np.testing.assert_allclose(
        np.sort([kp1, kp2], axis=0),
        np.sort([k1 / (1 + 0.05 * k1), k2 / (1 + 0.05 * k2)], axis=0),
        rtol=1e-6,
    )
    np.testing.assert_allclose(b.parallel(rf).normal(u, 0.5), b.normal(u, 0.5), atol=1e-12)
    np.testing.assert_array_equal(b.caustic_mask(u, 0.5, rf), k1 < -1 / rf)
    assert b.caustic_mask(0.45, 0.5, rf) and not b.caustic_mask(0.1, 0.5, rf)


def test_feature_catalogue_profiles():
    w = S.wire_on_plane(1.0, 0.3)
    k1, _ = w.principal_curvatures(np.array([0.0, 1.0, 2.5, -2.5, 4.0]), 0.0)
    np.testing.assert_allclose(k1, [1.0, 1.0, -1 / 0.3, -1 / 0.3, 0.0], atol=1e-9)
    assert S.cusp(2.0, 0.1).principal_curvatures(0.0, 0.0)[0] == pytest.approx(20.0)
    assert S.ridge(1.0, 0.5).principal_curvatures(0.0, 3.0)[0] == pytest.approx(4.0)
    assert S.ravine(1.0, 0.5).principal_curvatures(0.0, 3.0)[0] == pytest.approx(-4.0)
    for surf in (S.ridge(bend_radius=3.0), S.step(), S.cusp(), w, S.bump(2.0)):
        u = np.linspace(*np.clip(surf.domain[0], -2, 2), 7)[1:-1]
        assert np.all(surf.orthogonality(u, 0.3) < 1e-12)
        assert np.all(surf.normal(u, 0.3)[..., 2] > 0)  # outward = up


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: S.sphere(-1.0), r"radius: expected a finite number > 0 \[m\], got -1.0"),
        (lambda: S.sphere("x"), r"radius: expected a finite number > 0 \[m\], got 'x'"),
        (lambda: S.bump(-1.5), r"a: expected a number in \(-1, inf\) \[1/m\^2\], got -1.5"),
        (lambda: S.cylinder(0.0), r"radius: expected .* got 0.0"),
        (lambda: S.ridge(width=np.nan), r"width: expected a finite number > 0 \[m\], got nan"),
        (lambda: S.ParametricSurface(lambda u, v: [u, v, 0], ((1, 0), (0, 1))), "min < max"),
        (lambda: S.sphere(1.0).point(np.nan, 0.0), "finite"),
        (lambda: S.sphere(1.0).point(np.zeros(3), np.zeros(2)), "broadcast"),
        (
            lambda: S.ParametricSurface(lambda u, v: [u, v], ((0, 1), (0, 1))).point(0.5, 0.5),
            "3 coordinates",
        ),
    ],
)
def test_bad_input(make, match):
    with pytest.raises(InvalidParameter, match=match):
        make()


def test_casadi_functions_are_symbolic_and_match_numeric():
    b = S.bump(4.0)
    u, v = ca.SX.sym("u"), ca.SX.sym("v")
    k = b.functions["curvature_matrix"](u, v)
    dk = ca.Function("dk", [u, v], [ca.jacobian(k[0, 0], u)])  # usable in optimization
    h = 1e-6
    fd = (b.curvature_matrix(0.3 + h, 1.0)[0, 0] - b.curvature_matrix(0.3 - h, 1.0)[0, 0]) / (2 * h)
    assert float(dk(0.3, 1.0)) == pytest.approx(fd, rel=1e-5)
    g = b.local_geometry(0.3, 1.0)
    np.testing.assert_allclose(g.curvature_matrix, b.curvature_matrix(0.3, 1.0), atol=1e-12)
    np.testing.assert_allclose(g.torsion, b.torsion(0.3, 1.0), atol=1e-12)
    np.testing.assert_allclose(g.gauss_frame, b.gauss_frame(0.3, 1.0), atol=1e-12)


def test_bump_parallel_surface_eq_3_18_corrected():
    # eq. 3.18 as OCR'd carries a stray "sin v" in the y row; from eq. 3.10 and 3.14 both
    # horizontal rows are (u + 2 a r u / (d^2 c)) (cos v, sin v)
    a, r = 15.0, 1.0
    u, v = np.array([-0.6, 0.3, 0.8]), 0.7
    d = 1 + a * u**2
    c = np.sqrt(1 + 4 * a**2 * u**2 / d**4)
    rho = u + 2 * a * r * u / (d**2 * c)
    expected = np.stack([rho * np.cos(v), rho * np.sin(v), 1 / d + r / c], -1)
    np.testing.assert_allclose(S.bump(a).parallel(r).point(u, v), expected, atol=1e-12)
