"""The exact circular-cone contact problem and the exact sphere-surface geometry."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.geometry.surfaces import HeightField, ridge, sphere, step, wire_on_plane
from planner.sim.spatial import Plane, Plate, PlateFeature, solve_contact
from planner.sim.spatial.closest import PlacedSurface, _newton_graph
from planner.sim.spatial.friction_cone import residual, solve_contacts


def _spd(rng, scale=1.0):
    A = rng.normal(size=(3, 3))
    return scale * (A @ A.T + 0.05 * np.eye(3))


@settings(max_examples=300, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), mu=st.floats(0.0, 3.0), gap=st.floats(-1.0, 1.0))
@example(seed=0, mu=1e-14, gap=0.0)  # frictionless at lambda_n = 2.6
def test_solution_satisfies_signorini_and_the_circular_cone(seed, mu, gap):
    rng = np.random.default_rng(seed)
    W, u = _spd(rng), rng.normal(size=3)
    sol = solve_contact(W, u, gap, mu)
    scale = 1.0 + np.abs(sol.impulse).sum() + np.abs(u).sum() + abs(gap)
    assert residual(W, u, gap, mu, sol.impulse) <= 1e-10 * scale
    lam, v = sol.impulse, sol.velocity
    if sol.mode == "stick":
        assert np.hypot(*v[1:]) <= 1e-12 * scale  # no creep
        assert abs(v[0] + gap) <= 1e-12 * scale
    if sol.mode == "slide":
        # on the cone; below mu = 1e-14 the contact is frictionless (solve_impulse: a
        # friction force under 1e-14 lambda_n is not resolved)
        tiny = 1e-14 * max(1.0, lam[0])
        assert np.hypot(*lam[1:]) == pytest.approx(mu * lam[0], rel=1e-10, abs=tiny)
        assert abs(v[0] + gap) <= 1e-10 * scale  # no hovering: the gap is closed exactly
        if mu > 1e-14 and lam[0] > 1e-12 and np.hypot(*v[1:]) > 1e-9:  # friction opposes slip
            cos = -(lam[1:] @ v[1:]) / (np.hypot(*lam[1:]) * np.hypot(*v[1:]) + 1e-300)
            assert cos == pytest.approx(1.0, abs=1e-9)
    if sol.mode == "separate":
        assert np.all(lam == 0)


def test_isotropic_sliding_closed_form():
    # W = diag(a, b, b): lambda_n = -u_n / a, slip along the free slip,
    # |u_t+| = |u_t| - mu b lambda_n
    a, b, mu = 2.0, 5.0, 0.2
    W = np.diag([a, b, b])
    u = np.array([-1.0, 3.0, 4.0])
    sol = solve_contact(W, u, 0.0, mu)
    assert sol.mode == "slide"
    assert sol.impulse[0] == pytest.approx(0.5, rel=1e-15)
    assert np.hypot(*sol.velocity[1:]) == pytest.approx(5.0 - mu * b * 0.5, rel=1e-14)
    np.testing.assert_allclose(sol.velocity[1:] / np.hypot(*sol.velocity[1:]), [0.6, 0.8])


def test_frictionless_and_separating_cases():
    W = np.diag([1.0, 2.0, 2.0])
    s = solve_contact(W, np.array([-1.0, 1.0, 0.0]), 0.0, 0.0)
    np.testing.assert_allclose(s.impulse, [1.0, 0.0, 0.0])
    s = solve_contact(W, np.array([-1.0, 1.0, 0.0]), 2.0, 0.5)  # closes only part of the gap
    assert s.mode == "separate"


@settings(max_examples=50, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), mu=st.floats(0.05, 1.5))
def test_coupled_contacts_each_satisfy_their_cone(seed, mu):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(6, 6))
    W = A @ A.T + 0.5 * np.eye(6)
    u = rng.normal(size=6)
    lam, _ = solve_contacts(W, u, np.zeros(2), np.array([mu, mu]))
    for i in range(2):
        s = slice(3 * i, 3 * i + 3)
        u_i = u[s] + W[s] @ lam - W[s, s] @ lam[s]
        assert residual(W[s, s], u_i, 0.0, mu, lam[s]) <= 1e-9 * (1 + np.abs(lam).sum())


# ---------------------------------------------------------------- geometry
def test_plane_foot_is_exact_for_any_tilt():
    """Exact to rounding: a few units in the last place of the operands (0.5 m), not a
    fixed 1e-16 - the dot products round differently with the CPU's FMA/SIMD kernels (one
    machine's BLAS gave 2 ulp of 0.44 m, above 1e-16)."""
    p = PlacedSurface(Plane.tilted(0.3, (0.0, 0.0, 0.1)))
    c = np.array([0.2, -0.1, 0.5])
    f = p.foot(c)
    n = np.array([math.sin(0.3), 0.0, math.cos(0.3)])
    ulps = 4 * np.spacing(np.abs(c).max())  # [m]
    np.testing.assert_allclose(f.normal, n, rtol=0, atol=4 * np.spacing(1.0))
    assert f.distance == pytest.approx((c - [0, 0, 0.1]) @ n, rel=0, abs=ulps)
    assert (f.point - [0, 0, 0.1]) @ n == pytest.approx(0.0, abs=ulps)


@pytest.mark.parametrize(
    ("feature", "surface"),
    [
        (PlateFeature("ridge", 1e-3, 2e-3), ridge(1e-3, 2e-3)),
        (PlateFeature("step", 1e-3, 2e-3), step(1e-3, 2e-3)),
        (PlateFeature("wire", 2e-3, rounding=1.5e-3), wire_on_plane(1e-3, 1.5e-3)),
    ],
)
def test_plate_profiles_equal_the_catalogue_cross_sections(feature, surface):
    """The plate's closed-form profiles are the catalogue's (Table 3.1) surfaces."""
    u = np.linspace(*(0.95 * surface.domain[0]), 41)
    pts = surface.point(u, np.zeros_like(u))
    plate = Plate((feature,))
    for x, z in pts[:, [0, 2]]:
        assert plate.height_derivatives(float(x), 0.3)[0] == pytest.approx(z, abs=1e-12)


@pytest.mark.parametrize("kind", ["ridge", "ravine", "step", "bump", "pit", "wire", "cusp"])
def test_plate_derivatives_match_finite_differences(kind):
    f = PlateFeature(kind, 1e-3, 2e-3, position=(1e-3, -2e-3), across=0.4)
    plate = Plate((f, PlateFeature("ridge", 0.5e-3, 3e-3, across=1.2)))
    rng = np.random.default_rng(3)
    e = 1e-7
    for x, y in rng.uniform(-6e-3, 6e-3, size=(25, 2)):
        h, hx, hy, hxx, hxy, hyy = plate.height_derivatives(x, y)
        if math.hypot(hx, hy) > 3.0:  # near the wire's equator: slope -> inf, FD useless
            continue
        fx = [plate.height_derivatives(x + s * e, y) for s in (1, -1)]
        fy = [plate.height_derivatives(x, y + s * e) for s in (1, -1)]
        assert hx == pytest.approx((fx[0][0] - fx[1][0]) / (2 * e), rel=1e-4, abs=1e-6)
        assert hy == pytest.approx((fy[0][0] - fy[1][0]) / (2 * e), rel=1e-4, abs=1e-6)
        assert hxx == pytest.approx((fx[0][1] - fx[1][1]) / (2 * e), rel=1e-4, abs=1e-2)
        assert hxy == pytest.approx((fy[0][1] - fy[1][1]) / (2 * e), rel=1e-4, abs=1e-2)
        assert hyy == pytest.approx((fy[0][2] - fy[1][2]) / (2 * e), rel=1e-4, abs=1e-2)


@settings(max_examples=60, deadline=None)
@given(x=st.floats(-6e-3, 6e-3), y=st.floats(-5e-3, 5e-3), d=st.floats(1e-3, 7e-3))
def test_plate_foot_is_the_nearest_point(x, y, d):
    plate = Plate(
        (PlateFeature("ridge", 1e-3, 3e-3), PlateFeature("bump", 0.5e-3, 2e-3, (2e-3, 1e-3)))
    )
    surf = PlacedSurface(plate)
    c = np.array([x, y, plate.height_derivatives(x, y)[0] + d])
    f = surf.foot(c)
    # c - p is along the normal, and no sampled surface point is closer
    r = c - f.point
    assert np.linalg.norm(np.cross(r, f.normal)) <= 1e-12
    assert f.distance == pytest.approx(np.linalg.norm(r), abs=1e-15)
    g = np.linspace(-d, d, 61)
    X, Y = np.meshgrid(x + g, y + g)
    P = np.stack([X, Y, plate.height(X, Y)], -1).reshape(-1, 3)
    assert f.distance <= np.min(np.linalg.norm(P - c, axis=1)) + 1e-12


def test_parametric_and_height_field_feet():
    s = PlacedSurface(sphere(0.05))
    c = np.array([0.03, 0.04, 0.05])
    f = s.foot(c)
    assert f.distance == pytest.approx(np.linalg.norm(c) - 0.05, abs=1e-14)
    np.testing.assert_allclose(f.normal, c / np.linalg.norm(c), atol=1e-12)
    x = np.linspace(-0.02, 0.02, 41)
    X, Y = np.meshgrid(x, x, indexing="ij")
    hf = PlacedSurface(HeightField(x, x, 0.1 * X**2 + 0.05 * Y))
    c = np.array([0.003, -0.002, 0.01])
    f = hf.foot(c)
    r = c - f.point
    assert np.linalg.norm(np.cross(r, f.normal)) <= 1e-12
    assert hf.foot(np.array([0.5, 0.0, 0.0])) is None  # outside the sampled rectangle


def test_pose_places_the_surface():
    T = np.eye(4)
    T[:3, :3] = [[1, 0, 0], [0, 0, -1], [0, 1, 0]]  # surface z -> world -y
    T[:3, 3] = [0.0, 0.1, 0.0]
    f = PlacedSurface(Plane(), T).foot(np.array([0.3, 0.0, 0.2]))
    np.testing.assert_allclose(f.normal, [0, -1, 0], atol=1e-15)
    assert f.distance == pytest.approx(0.1)
    with pytest.raises(InvalidParameter, match="pose"):
        PlacedSurface(Plane(), np.eye(3))


def test_bad_features_are_rejected():
    with pytest.raises(InvalidParameter, match="kind"):
        PlateFeature("dimple", 1e-3)
    with pytest.raises(InvalidParameter, match="height"):
        PlateFeature("ridge", -1e-3)
    with pytest.raises(InvalidParameter, match="rounding"):
        PlateFeature("wire", 2e-3, rounding=0.5e-3)
    with pytest.raises(InvalidParameter, match="normal"):
        Plane(normal=(0, 0, 0))


def test_path_features_are_finite_and_bent():
    path = ((0.0, 0.0), (0.01, 0.0), (0.02, 0.01))
    plate = Plate((PlateFeature("ridge", 1e-3, 2e-3, path=path),))
    h = lambda x, y: plate.height_derivatives(x, y)[0]  # noqa: E731
    assert h(0.005, 0.0) == pytest.approx(1e-3)  # on the first segment
    assert h(0.015, 0.005) == pytest.approx(1e-3)  # on the bent second one
    assert h(-0.002, 0.0) == pytest.approx(1e-3 * math.exp(-0.5))  # round end cap
    assert h(0.005, 0.004) == pytest.approx(1e-3 * math.exp(-2.0))  # across the first one
    e = 1e-7
    for x, y in np.random.default_rng(1).uniform(-0.005, 0.025, (100, 2)):
        d = plate.height_derivatives(x, y)
        gx = (h(x + e, y) - h(x - e, y)) / (2 * e)
        gy = (h(x, y + e) - h(x, y - e)) / (2 * e)
        assert d[1] == pytest.approx(gx, abs=1e-6) and d[2] == pytest.approx(gy, abs=1e-6)
    with pytest.raises(InvalidParameter, match="path"):
        PlateFeature("step", 1e-3, path=path)


@pytest.mark.parametrize("warm", [False, True])
def test_foot_near_a_sharp_crest_is_the_nearest_point(warm):
    """A ball beside a cusp crest: Newton from the centre's (x, y) does not converge there
    (it used to return a point 0.9 mm *inside* the ball); the foot is the crest, found from
    the nearest grid sample, by the reference and by the kernel, cold or warm."""
    from planner.sim.spatial import step_kernel as sk
    from planner.sim.spatial.kernel import pack_plate

    plate = Plate((PlateFeature("cusp", 3e-3, 3e-3, (-0.014, 0.0), 0.0),))
    r, cx = 0.008, -0.012
    xs = np.linspace(-0.03, 0.01, 400001)
    hs = plate.height(xs, 0.0)
    z = 0.00826993588513399
    clearance = float(np.min(np.hypot(xs - cx, hs - z))) - r  # dense sampling: ~0.5 mm
    c = np.array([cx, 0.0, z])
    hint = (cx, 0.0) if warm else None
    foot = PlacedSurface(plate).foot(c, hint)
    assert foot.distance - r == pytest.approx(clearance, abs=1e-9)
    assert foot.point[0] == pytest.approx(xs[np.argmin(np.hypot(xs - cx, hs - z))], abs=1e-6)
    F, P = pack_plate(plate)
    prm = np.zeros(sk.PARAM_SIZE)
    prm[sk.P_ROT : sk.P_ROT + 9] = np.eye(3).ravel()
    x = np.zeros(sk.STATE_SIZE)
    if warm:
        x[sk.HINT], x[sk.HINT + 1], x[sk.HINT_OK] = cx, 0.0, 1.0
    out = np.zeros(6)
    dist = sk._foot(F, P, plate.base, prm, x, *c, out)
    assert dist == pytest.approx(foot.distance, abs=1e-12)
    np.testing.assert_allclose(out[:3], foot.point, atol=1e-12)


def test_a_foot_left_on_a_wire_is_given_up_for_the_plate_below():
    """A warm start on a wire's flank converges to a local foot there, although the ball
    has moved over the flat plate: that foot is farther than the plate straight below, so
    it cannot be the nearest. Both the reference and the kernel now restart from the grid
    and find the plate (a 3GM sliding off a wire kept its foot on the flank and sank 7 mm
    into the plate, found by a blind acceptance test)."""
    from planner.sim.spatial import step_kernel as sk
    from planner.sim.spatial.kernel import pack_plate

    plate = Plate((PlateFeature("wire", 0.0016, 0.002, (0.0, 0.0), 0.0),))
    r = 0.008
    c = np.array([-0.0075, 0.0, r - 0.002])  # 2 mm into the plate, beside the wire
    hint = (-0.0006, 0.0)  # on the wire's flank facing the ball
    placed = PlacedSurface(plate)
    p, _, _, converged = _newton_graph(placed.query.hd, c, *hint)
    assert converged and p[2] > 1e-3  # warm Newton alone stays on the flank, 1.3 mm up
    foot = placed.foot(c, hint)
    assert foot.distance == pytest.approx(c[2], abs=1e-12)  # the plate straight below
    np.testing.assert_allclose(foot.point, [c[0], 0.0, 0.0], atol=1e-12)
    F, P = pack_plate(plate)
    prm = np.zeros(sk.PARAM_SIZE)
    prm[sk.P_ROT : sk.P_ROT + 9] = np.eye(3).ravel()
    x = np.zeros(sk.STATE_SIZE)
    x[sk.HINT], x[sk.HINT + 1], x[sk.HINT_OK] = *hint, 1.0
    out = np.zeros(6)
    assert sk._foot(F, P, plate.base, prm, x, *c, out) == pytest.approx(c[2], abs=1e-12)
    np.testing.assert_allclose(out[:3], foot.point, atol=1e-12)


def test_3gm_sliding_off_a_wire_stays_on_the_plate():
    """The blind acceptance test's run: a raster over a 1.6 mm wire; the true fingertip
    centre (forward kinematics of the logged joints) never goes below the plate under it
    by more than the projection tolerance, and the contact is never lost."""
    from planner.exploration.surface import explore_surface
    from planner.exploration.surface.plates import plate_height
    from robots.three_gm import ThreeGM

    plate = Plate((PlateFeature("wire", 0.0016, 0.002, (0.002, 0.0), math.radians(10)),))
    box = ((-0.018, 0.018), (-0.018, 0.018))
    res = explore_surface(plate, region=box, line_spacing=0.05, seed=5, duration=4.0)
    gm, T = ThreeGM(), np.asarray(res.pose)
    X = np.array([gm.forward_kinematics(q) for q in res.log.q])
    P = (X - T[:3, 3]) @ T[:3, :3]
    inside = (np.abs(P[:, 0]) < 0.018) & (np.abs(P[:, 1]) < 0.018)
    clearance = P[:, 2] - plate_height(plate)(P[:, 0], P[:, 1]) - 0.008
    assert clearance[inside].min() > -1e-6  # was -7.1 mm
    assert not any(e.kind == "contact_lost" for e in res.events)


def _coupled_residuals(W, u, lam, mu):
    out = []
    for i in range(2):
        s = slice(3 * i, 3 * i + 3)
        out.append(residual(W[s, s], u[s] + W[s] @ lam - W[s, s] @ lam[s], 0.0, mu, lam[s]))
    return out


def test_cycling_gauss_seidel_restarts_relaxed():
    """Plain block Gauss-Seidel cycles on this strongly coupled pair (found by Hypothesis:
    residual 0.2 after 2000 sweeps); the relaxed restart solves it to round-off."""
    rng = np.random.default_rng(905)
    A = rng.normal(size=(6, 6))
    W, u, mu = A @ A.T + 0.5 * np.eye(6), rng.normal(size=6), 1.5
    lam, modes = solve_contacts(W, u, np.zeros(2), np.array([mu, mu]))
    assert max(_coupled_residuals(W, u, lam, mu)) <= 1e-12
    assert lam[0] > 0 and lam[3] >= 0 and len(modes) == 2


def test_alart_curnier_root_when_the_sweeps_are_cut_short():
    """Two sweeps per relaxation cannot converge here: the verified Alart-Curnier root does."""
    rng = np.random.default_rng(905)
    A = rng.normal(size=(6, 6))
    W, u, mu = A @ A.T + 0.5 * np.eye(6), rng.normal(size=6), 1.5
    lam, _ = solve_contacts(W, u, np.zeros(2), np.array([mu, mu]), max_sweeps=2)
    assert max(_coupled_residuals(W, u, lam, mu)) <= 1e-10


def test_unsolved_coupled_problem_is_an_infeasible_problem_not_a_wrong_answer(monkeypatch):
    import planner.sim.spatial.friction_cone as fc
    from planner.errors import InfeasibleProblem

    monkeypatch.setattr(fc, "_alart_curnier", lambda *a: None)
    rng = np.random.default_rng(905)
    A = rng.normal(size=(6, 6))
    W, u = A @ A.T + 0.5 * np.eye(6), rng.normal(size=6)
    with pytest.raises(InfeasibleProblem, match="did not converge") as err:
        fc.solve_contacts(W, u, np.zeros(2), np.array([1.5, 1.5]), max_sweeps=2)
    assert set(err.value.problem) == {"W", "u_free", "gap_rates", "mu", "rates"}
