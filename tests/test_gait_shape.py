"""The posed-outline estimator of non-round objects (planner/exploration/planar/outline_pose.py,
shape_tracking.py) and the phase-1 NLP with the outline's palm clearance."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.exploration.planar.outline_pose import (
    Outline,
    Readings,
    clip_halfplane,
    contacts,
    fit_pose,
    nearest_on_polygon,
    residuals,
    residuals_reference,
)

A = 0.055  # half-width of the 11 cm square [m]
R_TIP = 0.0125
SQUARE = Outline(np.array([[A, A], [-A, A], [-A, -A], [A, -A]]))


def _area(P):
    x, y = P[:, 0], P[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def exact_readings(pose, pad_tilt: float, u: float, tip_at: float) -> Readings:
    """Readings of a square at ``pose`` resting on the palm: the pad touching its support
    vertex at ``u`` from the pad centre (the pad ``pad_tilt`` [rad] off the left face: > 0
    onto the upper-left corner), the round tip on the right face at fraction ``tip_at`` of
    its length."""
    W = SQUARE.posed(pose)
    phi = -0.5 * math.pi + float(pose[2]) - pad_tilt
    n = np.array([math.sin(phi), -math.cos(phi)])
    t = np.array([math.cos(phi), math.sin(phi)])
    corner = W[int(np.argmax(W @ n))]
    # the face whose outward normal (e_y, -e_x) points most to +x (counter-clockwise points)
    k = max(range(4), key=lambda i: (W[(i + 1) % 4] - W[i])[1])
    a, b = W[k], W[(k + 1) % 4]
    e = (b - a) / np.linalg.norm(b - a)
    normal = np.array([e[1], -e[0]])
    q = a + tip_at * (b - a)
    return Readings(pad_point=corner - u * t, pad_angle=phi, pad_u=u, pad_half_width=0.01,
                    pad_u_max=0.00875, tip_centre=q + R_TIP * normal, tip_radius=R_TIP)  # fmt: skip


def resting(x: float, theta: float) -> np.ndarray:
    W = SQUARE.posed((0.0, 0.0, theta))
    return np.array([x, -W[:, 1].min(), theta])


def test_square_from_exact_contacts_recovers_its_pose():
    pose = resting(0.004, math.radians(-16.0))
    rd = exact_readings(pose, math.radians(-8.0), 0.004, 0.4)  # the lower-left corner
    assert np.abs(residuals(SQUARE, pose, rd)).max() < 1e-15
    fit = fit_pose(SQUARE, rd, pose + [0.005, -0.004, 0.04])
    assert fit.success
    np.testing.assert_allclose(fit.pose, pose, atol=1e-9)
    assert fit.cost < 1e-12


@settings(max_examples=20, deadline=None)
@given(
    x=st.floats(-0.01, 0.01),
    theta=st.floats(math.radians(-35), math.radians(-5)),
    tilt=st.floats(math.radians(5), math.radians(30)),
    u=st.floats(-0.006, 0.006),
    tip_at=st.floats(0.2, 0.8),
    dx=st.floats(-0.003, 0.003),
    dth=st.floats(-0.05, 0.05),
)
def test_pose_recovered_over_poses(x, theta, tilt, u, tip_at, dx, dth):
    """Any tilted resting pose with the pad on its upper-left corner: recovered to 1e-9 from
    a guess 3 mm / 3 deg off."""
    pose = resting(x, theta)
    rd = exact_readings(pose, tilt, u, tip_at)
    fit = fit_pose(SQUARE, rd, pose + [dx, -dx, dth])
    assert fit.success
    np.testing.assert_allclose(fit.pose, pose, atol=1e-9)


def test_noise_gives_a_bounded_error():
    """0.1 mm of noise on the encoders' points and 0.3 mm on the tactile centroid: the pose
    within 1 mm and 1.5 deg (seeded)."""
    rng = np.random.default_rng(0)
    pose = resting(0.002, math.radians(-20.0))
    rd = exact_readings(pose, math.radians(12.0), 0.003, 0.5)
    assert np.abs(residuals(SQUARE, pose, rd)).max() < 1e-15
    worst = np.zeros(3)
    for _ in range(20):
        noisy = Readings(pad_point=rd.pad_point + rng.normal(0, 1e-4, 2), pad_angle=rd.pad_angle,
                         pad_u=rd.pad_u + rng.normal(0, 3e-4), pad_half_width=0.01,
                         pad_u_max=0.00875, tip_centre=rd.tip_centre + rng.normal(0, 1e-4, 2),
                         tip_radius=R_TIP)  # fmt: skip
        fit = fit_pose(SQUARE, noisy, pose)
        worst = np.maximum(worst, np.abs(fit.pose - pose))
    assert worst[0] < 1e-3 and worst[1] < 1e-3 and worst[2] < math.radians(1.5)


def test_rotation_prior_selects_among_symmetric_poses():
    """Palm and a pad flat on a face fix the square only up to sliding along the face: the
    prior (weighted) picks the rotation, the contacts the rest."""
    pose = resting(0.0, 0.0)
    rd = Readings(pad_point=np.array([-A, 0.05]), pad_angle=-math.pi / 2, pad_half_width=0.01,
                  tip_centre=np.array([A + R_TIP, 0.03]), tip_radius=R_TIP)  # fmt: skip
    fit = fit_pose(SQUARE, rd, [0.002, 0.057, 0.1], theta_prior=0.0, theta_weight=0.01)
    np.testing.assert_allclose(fit.pose, pose, atol=1e-6)


def test_face_beyond_the_pad_edge_touches_the_edge():
    """A corner beyond the pad's end: the pad's edge point lies on the face (the strip
    clipping), and the centroid reads the outermost taxel."""
    pose = resting(0.0, math.radians(-10.0))
    W = SQUARE.posed(pose)
    phi = -math.pi / 2 + math.radians(20.0)
    t = np.array([math.cos(phi), math.sin(phi)])
    n = np.array([math.sin(phi), -math.cos(phi)])
    corner = W[int(np.argmax(W @ n))]
    pad_point = corner - 0.015 * t  # the corner 15 mm from the pad centre, beyond its 10 mm
    rd = Readings(pad_point=pad_point, pad_angle=phi, pad_u=0.00875, pad_half_width=0.01,
                  pad_u_max=0.00875)  # fmt: skip
    r = residuals(SQUARE, pose, rd)
    assert r[0] < -1e-3  # the pad's line is clear of the face within its strip
    assert r[1] == pytest.approx(0.0, abs=1e-12)


def test_clip_and_nearest_closed_forms():
    P = SQUARE.points
    half = clip_halfplane(P, np.array([1.0, 0.0]), 0.0)
    assert _area(half) == pytest.approx(2 * A * A, rel=1e-12)
    diag = clip_halfplane(P, np.array([1.0, 1.0]) / math.sqrt(2), 0.0)
    assert _area(diag) == pytest.approx(2 * A * A, rel=1e-12)
    assert len(clip_halfplane(P, np.array([1.0, 0.0]), -1.0)) == 0
    q, d = nearest_on_polygon(P, (0.1, 0.02))
    np.testing.assert_allclose(q, [A, 0.02])
    assert d == pytest.approx(0.1 - A)
    q, d = nearest_on_polygon(P, (0.1, 0.1))
    assert d == pytest.approx(math.hypot(0.1 - A, 0.1 - A))


def test_contacts_of_a_resting_square():
    pose = resting(0.0, 0.0)
    rd = Readings(tip_centre=np.array([A + R_TIP, 0.04]), tip_radius=R_TIP)
    c = contacts(SQUARE, pose, rd)
    np.testing.assert_allclose(c["tip"], [A, 0.04], atol=1e-15)
    np.testing.assert_allclose(c["tip_normal"], [1.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(c["palm"], [0.0, 0.0], atol=1e-15)


def test_outline_from_profile_and_roundness():
    from planner.geometry import shapes

    sq = Outline.from_profile(shapes.rounded_rectangle(0.11, 0.11, 0.0))
    assert _area(sq.points) == pytest.approx(0.11**2, rel=1e-9)
    # (max - min) / mean distance from the centre: (sqrt 2 - 1) A / mean, mean in (A, sqrt 2 A)
    assert (math.sqrt(2) - 1) / math.sqrt(2) < sq.roundness() < math.sqrt(2) - 1
    assert Outline.from_profile(shapes.circle(0.05)).roundness() < 1e-9
    assert len(sq.hull(16)) == 4
    with pytest.raises(InvalidParameter, match="points"):
        Outline(np.zeros((2, 2)))


def test_tracker_only_for_non_round_nominals():
    from planner.exploration.planar.shape_tracking import ShapeTracker
    from planner.geometry import shapes
    from robots.planar_hand import PlanarHand

    hand = PlanarHand()
    assert ShapeTracker.of(None, hand) is None
    assert ShapeTracker.of(shapes.circle(0.05), hand) is None
    tr = ShapeTracker.of(shapes.rounded_rectangle(0.11, 0.11, 0.0), hand)
    np.testing.assert_allclose(tr.pose, [0.0, A, 0.0], atol=1e-12)
    P = tr.palm_points((0.0, A))
    assert P.shape == (16, 2)
    assert P[:, 1].min() == pytest.approx(-A)


# ---------------------------------------------------------------- the NLP on a square
@pytest.fixture(scope="module")
def square_plan():
    from planner.exploration.planar.heuristics import start_grasp_candidates
    from planner.trajectory import RollingNLP
    from robots.planar_hand import PlanarHand

    hand = PlanarHand()
    R, r = 0.05, 0.025
    bl, br, q, _ = start_grasp_candidates(hand, (0, R), R, 0.8, None, 0.15)[0]
    V = np.array([[R, R], [-R, R], [-R, -R], [R, -R]])  # a square resting on the palm
    nlp = RollingNLP(hand, knots=6, palm_points=4, travel=0.03)
    plan = nlp.solve(q, np.array([0.0, R]), R, r, 0.8, np.array([bl, br]), 0.0, palm_points=V)
    return plan, V, R, r, nlp


def test_square_nlp_keeps_the_outline_above_the_palm(square_plan):
    from planner.trajectory.rolling_nlp import SET_DOWN

    plan, V, *_ = square_plan
    assert plan.success and plan.rotation < -math.radians(10)
    th, c = plan.theta, plan.centre
    low = np.array([min(c[k, 1] + math.sin(th[k]) * v[0] + math.cos(th[k]) * v[1] for v in V)
                    for k in range(len(th))])  # fmt: skip
    assert low.min() > -1e-6
    assert low[-1] <= SET_DOWN + 1e-6
    # pivoting on its corner the square's centre is lifted (the circle's plan would not)
    assert c[:, 1].max() > c[0, 1] + 5e-3


def test_square_nlp_rolls_equal_arclengths(square_plan):
    plan, V, R, r, nlp = square_plan
    th, b, u = plan.theta, plan.beta, plan.u
    phiR = plan.q[:, 3:6].sum(axis=1)
    # eq. (2.4) integrated: object arclength = fingertip arclength at both contacts
    np.testing.assert_allclose(R * ((b[:, 0] - th) - b[0, 0]), u - u[0], atol=1e-6)
    s_obj = R * ((b[:, 1] - th) - b[0, 1])
    s_tip = r * ((b[:, 1] - phiR) - (b[0, 1] - phiR[0]))
    np.testing.assert_allclose(s_obj + s_tip, 0.0, atol=1e-6)


def test_square_nlp_needs_its_points(square_plan):
    *_, nlp = square_plan
    plan = square_plan[0]
    with pytest.raises(InvalidParameter, match="palm_points"):
        nlp.solve(plan.q[0], plan.centre[0], 0.05, 0.025, 0.8, plan.beta[0], 0.0)


# ------------------------------------------------- the NLP on the polygon (contact modes)
@pytest.fixture(scope="module")
def polygon_plan():
    from planner.exploration.planar.heuristics import best_margin_ik, pad_angle
    from planner.trajectory import OutlineNLP
    from robots.planar_hand import PlanarHand, gait_hand_params

    hand = PlanarHand(gait_hand_params())
    r = hand.params.right.tip_radius
    yl, yr = 0.08, 0.05  # the pad flat on the left face, the tip on the right face
    qL = hand.inverse_kinematics("left", np.array([-A, yl]), angle=pad_angle(math.pi, -math.pi / 2))
    qR = best_margin_ik(hand, "right", np.array([A + r, yr]), around=math.pi / 2)
    q = np.r_[qL, qR]
    contact = {"pad_point": np.array([-A, yl - A]), "pad_face": True,
               "tip_normal": np.array([1.0, 0.0]), "tip_offset": A,
               "tip_range": (-A + 0.002, A - 0.002)}  # fmt: skip
    nlp = OutlineNLP(hand, 4, knots=6)
    plan = nlp.solve(q, np.array([0.0, A, 0.0]), contact, SQUARE.points, r, 0.9)
    return plan, nlp, hand, contact, r


def test_polygon_nlp_constraints_hold_at_the_solution(polygon_plan):
    plan, nlp, *_ = polygon_plan
    assert plan.success and plan.rotation < -math.radians(10)
    X, p = nlp.last_solution
    g = np.asarray(nlp.constraints(X.ravel(), p)).ravel()
    assert np.all(g >= nlp._lbg - 1e-6) and np.all(g <= nlp._ubg + 1e-6)


def test_polygon_nlp_rolls_and_pivots(polygon_plan):
    """Checked with the hand's own kinematics: the pad's contact point stays on the pad's
    line at a fixed place (no slip), the pad turns with the face, the tip rolls along the
    right face (eq. 2.4 on a line) and the square stays above the palm."""
    plan, nlp, hand, contact, r = polygon_plan
    X, _ = nlp.last_solution
    u, a, phis, ths = [], [], [], []
    for x, y, th, *q in X:
        L, Rt = hand.fingertip_pose(q, "left"), hand.fingertip_pose(q, "right")
        c, s = math.cos(th), math.sin(th)
        w = np.array([x, y]) + np.array([[c, -s], [s, c]]) @ contact["pad_point"]
        t = np.array([math.cos(L.angle), math.sin(L.angle)])
        n = np.array([math.sin(L.angle), -math.cos(L.angle)])
        assert n @ (w - L.position) == pytest.approx(0.0, abs=1e-7)
        m = np.array([c, s])  # the right face's outward normal, turned
        assert m @ (Rt.position - (x, y)) - A == pytest.approx(r, abs=1e-7)
        u.append(t @ (w - L.position))
        a.append(np.array([-s, c]) @ (Rt.position - (x, y)))
        phis.append((L.angle - th, Rt.angle))
        ths.append(th)
        low = (SQUARE.posed((x, y, th)))[:, 1].min()
        assert low > -1e-6
    u, a, phis, ths = np.array(u), np.array(a), np.array(phis), np.array(ths)
    np.testing.assert_allclose(u, u[0], atol=1e-7)
    np.testing.assert_allclose(phis[:, 0], phis[0, 0], atol=1e-7)
    np.testing.assert_allclose((a - a[0]) + r * ((ths - ths[0]) - (phis[:, 1] - phis[0, 1])),
                               0.0, atol=1e-7)  # fmt: skip


# ------------------------------------------------------------ the explorer's outline path
def test_polyline_path_closed_forms():
    from planner.exploration.planar.outline_segments import PolylinePath

    path = PolylinePath(SQUARE.points[::-1])  # clockwise input is turned counter-clockwise
    assert path.length == pytest.approx(8 * A)
    s = path.arclength_of((A + 0.01, 0.02))  # on the right face, 0.02 above its middle
    p, t = path.at(s)
    np.testing.assert_allclose(p, [A, 0.02], atol=1e-12)
    np.testing.assert_allclose(t, [0.0, 1.0], atol=1e-12)  # counter-clockwise: up
    np.testing.assert_allclose(path.at(s + path.length)[0], p, atol=1e-12)
    # the outward normal, averaged over a window: the face's away from corners, the
    # corner's bisector on it
    assert path.normal_angle(s, 0.005) == pytest.approx(0.0, abs=1e-12)
    corner = path.arclength_of((A, A))
    assert path.normal_angle(corner, 0.005) == pytest.approx(math.pi / 4, abs=1e-9)
    top = path.point_at_angle((0.0, 0.0), math.pi / 2 - 0.1)
    assert path.at(top)[0][1] == pytest.approx(A)


@pytest.mark.parametrize("fn", ["compiled", "reference"])
@pytest.mark.parametrize("order", [0, 1, 2, 3])
def test_an_outline_beside_the_pad_meets_it_at_the_highest_tied_corner(fn, order):
    """The square beside the pad's strip (|x - 0.07| <= 0.01, the square's right face at
    x = 0.055 across its edge): its two corners on that face are equally near; the pad
    residual is that of the highest along the pad's normal ``(0, -1)`` (``y = -A``):
    ``A + y_pad``, whichever corner comes first in the outline, in both implementations
    (the compiled one and NumPy's picked different corners: 0.11 m apart)."""
    pts = np.roll(SQUARE.points, order, axis=0)
    rd = Readings(pad_point=np.array([0.07, -0.06]), pad_angle=0.0, pad_half_width=0.01,
                  pad_u_max=0.00875, palm=False)  # fmt: skip
    f = residuals if fn == "compiled" else residuals_reference
    r = f(Outline(pts), (0.0, 0.0, 0.0), rd)
    assert r == pytest.approx([A - 0.06], abs=1e-15)


#: outlines for the compiled residuals' comparison: the square, a hexagon, a sampled circle
_OUTLINES = (
    SQUARE,
    Outline(0.04 * np.array([[math.cos(a), math.sin(a)] for a in np.arange(6) * math.pi / 3])),
    Outline(0.05 * np.array([[math.cos(a), math.sin(a)] for a in np.linspace(0, 6.28, 90)])),
)


@settings(max_examples=60, deadline=None)
@example(
    which=0,
    pose=(0.0, 0.0, -2.4375),
    pad=(-0.08984375, 0.0, -2.4375),
    u=math.nan,
    tip=None,
    use_pad=True,
    palm=False,
    prior=None,
)  # a face across the strip's edge
@given(
    which=st.integers(0, 2),
    pose=st.tuples(st.floats(-0.03, 0.03), st.floats(0.0, 0.08), st.floats(-3.2, 3.2)),
    pad=st.tuples(st.floats(-0.09, -0.02), st.floats(0.0, 0.1), st.floats(-2.6, -0.5)),
    u=st.one_of(st.just(math.nan), st.floats(-0.01, 0.01)),
    tip=st.one_of(st.none(), st.tuples(st.floats(0.0, 0.1), st.floats(0.0, 0.1))),
    use_pad=st.booleans(),
    palm=st.booleans(),
    prior=st.one_of(st.none(), st.floats(-3.0, 3.0)),
)
def test_compiled_residuals_equal_the_numpy_reference(which, pose, pad, u, tip, use_pad, palm,
                                                      prior):  # fmt: skip
    """The compiled residuals (pad window clipped, pad beside the outline, centroid, tip,
    palm, prior) are the numpy reference's to rounding, for any pose and reading."""
    rd = Readings(pad_point=np.array(pad[:2]) if use_pad else None, pad_angle=pad[2], pad_u=u,
                  pad_half_width=0.01, pad_u_max=0.00875,
                  tip_centre=None if tip is None else np.array(tip), tip_radius=R_TIP,
                  palm=palm)  # fmt: skip
    outline = _OUTLINES[which]
    a = residuals(outline, pose, rd, prior, 0.05)
    b = residuals_reference(outline, pose, rd, prior, 0.05)
    assert a.shape == b.shape
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-13)


def test_fit_jacobian_is_scipys_three_point_difference():
    """The fits' compiled Jacobian is scipy's ``approx_derivative(method="3-point")`` of the
    same residuals, to the bit (a fit with it follows the same iterates)."""
    from scipy.optimize._numdiff import approx_derivative

    from planner.exploration.planar.outline_pose import _Residuals

    rd = exact_readings(resting(0.01, 0.2), 0.1, 0.002, 0.4)
    f = _Residuals(SQUARE, rd, 0.15, 0.05)
    for pose in ([0.01, 0.06, 0.2], [-0.002, 0.0, -0.7], [0.0, 0.03, 0.0]):
        x = np.array(pose)
        np.testing.assert_array_equal(f.jacobian(x), approx_derivative(f, x, method="3-point"))
