"""Profiles and their parallel/traced/estimated curves against closed forms (§3.2.1)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.geometry import curves as c
from planner.geometry import shapes


def rot(a):
    return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])


@settings(max_examples=25, deadline=None)
@given(r=st.floats(0.002, 0.02), ratio=st.floats(1.0, 4.0), x0=st.floats(-0.01, 0.01))
@example(r=0.015625, ratio=1.0078125, x0=0.0)  # the wall's offset ends within a sample
def test_tall_step_interference_at_x0_minus_r(r, ratio, x0):
    tc = c.traced_curve(shapes.step(ratio * r, x0=x0, length=0.1), r)
    np.testing.assert_allclose(tc.interference_points, [[x0 - r, r]], atol=1e-9)


@settings(max_examples=25, deadline=None)
@given(r=st.floats(0.002, 0.02), ratio=st.floats(0.05, 0.99))
def test_low_step_interference_on_corner_circle(r, ratio):
    h = ratio * r
    tc = c.traced_curve(shapes.step(h, length=0.1), r)
    np.testing.assert_allclose(
        tc.interference_points, [[-np.sqrt(r * r - (r - h) ** 2), r]], atol=1e-9
    )


@settings(max_examples=25, deadline=None)
@given(
    r=st.floats(0.003, 0.02),
    d=st.floats(0.0003, 0.003),
    angle=st.floats(-1.0, 1.0),
    x0=st.floats(-0.005, 0.005),
)
def test_wire_on_plane_two_interference_points(r, d, angle, x0):
    a = d / 2
    tc = c.traced_curve(shapes.wire_on_plane(d, angle, x0=x0, length=0.08), r)
    local = tc.interference_points @ rot(angle)  # into the plane's frame
    expect = [[x0 - 2 * np.sqrt(r * a), r], [x0 + 2 * np.sqrt(r * a), r]]
    np.testing.assert_allclose(local, expect, atol=1e-9)


@pytest.mark.parametrize("width", [0.004, 0.01, 0.016])
def test_narrow_ravine_is_bridged(width):
    r = 0.01
    tc = c.traced_curve(shapes.ravine(width, 0.02), r)
    np.testing.assert_allclose(
        tc.interference_points, [[0.0, np.sqrt(r * r - width * width / 4)]], atol=1e-9
    )
    # the whole groove is unobservable: walls (2 x 20 mm) + bottom
    assert tc.unobservable_length == pytest.approx(0.04 + width, abs=2e-4)


def test_wide_ravine_touches_bottom():
    r = 0.005
    tc = c.traced_curve(shapes.ravine(0.03, 0.02), r)
    # concave bottom corners at (+-0.015, -0.02): interference at (+-(0.015 - r), -0.02 + r)
    np.testing.assert_allclose(
        tc.interference_points, [[-0.015 + r, -0.02 + r], [0.015 - r, -0.02 + r]], atol=1e-9
    )


@settings(max_examples=20, deadline=None)
@given(R=st.floats(0.01, 0.2), r=st.floats(0.001, 0.05))
def test_circle_traced_and_estimated(R, r):
    tc = c.traced_curve(shapes.circle(R), r)
    np.testing.assert_allclose(np.linalg.norm(tc.points, axis=1), R + r, atol=1e-12)
    assert len(tc.interference_points) == 0 and tc.closed
    est = c.estimated_curve(tc, r)
    np.testing.assert_allclose(np.linalg.norm(est.points, axis=1), R, atol=1e-9 * R + 1e-12)
    assert not est.unobservable.any()


def test_estimated_step_is_profile_plus_fingertip_arc():
    r, h = 0.01, 0.02
    tc = c.traced_curve(shapes.step(h), r)
    est = c.estimated_curve(tc, r)
    obs = ~est.unobservable
    # exact on the faces; at the convex corner the traced fan is a polyline, whose bisector
    # normals are off by O(spacing^2 / r) = 1e-6 m at the default spacing r/100
    d = c.distance_to_profile(est.points[obs], shapes.step(h))
    assert np.median(d) < 1e-12 and d.max() < 1e-6
    # the unobservable region is a quarter circle of radius r about the interference point
    U = est.points[est.unobservable]
    np.testing.assert_allclose(np.linalg.norm(U - [-r, r], axis=1), r, atol=1e-9)
    assert est.unobservable_length == pytest.approx(np.pi / 2 * r, rel=1e-3)


def test_estimated_from_plain_points_matches():
    r = 0.01
    tc = c.traced_curve(shapes.step(0.02), r)
    a = c.estimated_curve(tc, r)
    b = c.estimated_curve(tc.points, r)
    np.testing.assert_allclose(a.points, b.points)


def test_parallel_curve_caustics_of_ellipse():
    # Fig. 3.1: ellipse a = 5, b = 2; offsets beyond -b^2/a = -0.8 have caustics.
    e = shapes.ellipse(5.0, 2.0)
    assert len(c.parallel_curve(e, -0.5).caustic_points) == 0
    P = c.parallel_curve(e, -1.0)
    assert len(P.caustic_points) == 4
    # caustics where the radius of curvature equals 1: ρ(t) = (a²s² + b²c²)^1.5 / (ab)
    t = np.linspace(0, 2 * np.pi, 200001)
    rho = (25 * np.sin(t) ** 2 + 4 * np.cos(t) ** 2) ** 1.5 / 10
    cross = np.flatnonzero(np.diff(np.sign(rho - 1.0)))
    pts = np.stack([5 * np.cos(t[cross]), 2 * np.sin(t[cross])], axis=-1)
    nrm = np.stack([2 * np.cos(t[cross]), 5 * np.sin(t[cross])], axis=-1)
    expect = pts - nrm / np.linalg.norm(nrm, axis=1, keepdims=True)
    for q in P.caustic_points:
        assert np.min(np.linalg.norm(expect - q, axis=1)) < 1e-3


@pytest.mark.parametrize(
    "profile",
    [
        shapes.step(0.005),
        shapes.ridge(0.006, 0.003, 0.001),
        shapes.ravine(0.008, 0.004, 0.0005),
        shapes.bump(0.002, 0.006),
        shapes.pit(0.002, 0.004, "gaussian"),
        shapes.cusp(np.pi / 2),
        shapes.rounded_rectangle(0.08, 0.05, 0.01),
        shapes.ellipse(0.05, 0.03),
        shapes.polygon([[0, 0], [0.05, 0], [0.02, 0.04]]),
        shapes.spline([[0, 0], [0.01, 0.003], [0.02, 0]]),
        shapes.wire_on_plane(0.001, 0.3),
    ],
)
def test_traced_points_keep_exactly_tip_radius_from_profile(profile):
    r = 0.004
    tc = c.traced_curve(profile, r)
    d = c.distance_to_profile(tc.points, profile, spacing=profile.length / 200000)
    assert d.min() >= r - 2e-6 and d.max() <= r + 2e-6
    np.testing.assert_allclose(np.linalg.norm(tc.normals, axis=1), 1.0)
    assert np.all(np.diff(tc.s) >= 0)


def test_profile_curvature_and_normals():
    smp = shapes.circle(0.05).sample(0.001)
    np.testing.assert_allclose(smp.curvature, 20.0)
    np.testing.assert_allclose(np.einsum("ij,ij->i", smp.normals, smp.points) / 0.05, 1.0)
    pit = shapes.bump(0.002, 0.01).sample(1e-4)
    assert np.nanmax(pit.curvature[np.isfinite(pit.curvature)]) > 0
    e = shapes.ellipse(0.05, 0.02)
    smp = e.sample(1e-4)
    k_exact = (
        0.05
        * 0.02
        / (
            0.02**2 * smp.points[:, 0] ** 2 / 0.05**2 * 0.05**2 / 0.05**2 * 0
            + (0.02 * smp.points[:, 0] / 0.05) ** 2
            + (0.05 * smp.points[:, 1] / 0.02) ** 2
        )
        ** 1.5
    )
    np.testing.assert_allclose(smp.curvature, k_exact, rtol=1e-6)


def test_ground_truth_features_of_a_wire():
    f = shapes.wire_on_plane(0.00065, 0.0).curvature_features(0.01)
    assert [x.sign for x in f] == [-1, 1, -1]  # a bump pattern, Table 3.1
    assert f[1].end - f[1].start == pytest.approx(np.pi * 0.00065, rel=1e-9)


@settings(max_examples=30, deadline=None)
@given(theta=st.floats(0, 2 * np.pi), a=st.floats(0.01, 0.1), b=st.floats(0.01, 0.1))
def test_polar_angle_lookup(theta, a, b):
    for prof in (shapes.ellipse(a, b), shapes.rounded_rectangle(2 * a, 2 * b, 0.3 * min(a, b))):
        p, n = prof.point_at_polar_angle(np.array([theta]))
        diff = np.angle(np.exp(1j * (np.arctan2(p[0, 1], p[0, 0]) - theta)))
        assert abs(diff) < 1e-3
        assert n @ p[0] > 0  # outward


def test_resample_equal_arclength():
    pts = np.array([[0, 0], [1, 0], [1, 1]], float)
    q = c.resample_equal_arclength(pts, 0.25)
    assert len(q) == 9
    np.testing.assert_allclose(np.linalg.norm(np.diff(q, axis=0), axis=1), 0.25)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: shapes.step(0.0), "non-zero"),
        (lambda: shapes.circle(-1), "radius"),
        (lambda: c.traced_curve(shapes.step(0.01), -0.01), "tip_radius"),
        (lambda: c.traced_curve(shapes.step(0.01), float("nan")), "tip_radius"),
        (lambda: shapes.polyline([[0, 0]]), "at least 2"),
        (lambda: shapes.polyline([[0, 0], [0, 0]]), "duplicates"),
        (lambda: shapes.polygon([[0, 0], [1, 1], [1, 0], [0, 1]]), "edge 0 .* meets edge 2"),
        (lambda: shapes.polygon([[0, 0], [2, 0], [1, 0], [1, 1]]), "crosses"),  # a spike
        (lambda: shapes.polygon([[0, 0], [1, 0], [0, 0]]), "at least 3 vertices"),
        (lambda: shapes.polygon([[0, 0], [1, 0], [2, 0]]), "retraces itself"),
        (lambda: shapes.rounded_rectangle(0.1, 0.05, 0.04), "corner_radius"),
        (lambda: shapes.bump(0.001, 0.01, "square"), "shape"),
        (lambda: c.estimated_curve(np.zeros((3, 3)), 0.01), "shape"),
        (lambda: c.resample_equal_arclength(np.zeros((5, 2)), 0.0), "spacing"),
        (lambda: shapes.step(0.01).point_at_polar_angle(0.0), "closed"),
    ],
)
def test_bad_arguments(call, match):
    with pytest.raises(InvalidParameter, match=match):
        call()


def test_polygon_polar_lookup_at_sharp_corners():
    square = shapes.polygon([[0.05, 0], [0, 0.05], [-0.05, 0], [0, -0.05]])
    p, n = square.point_at_polar_angle(np.array([0.0, np.pi / 4, np.pi / 2]))
    np.testing.assert_allclose(p, [[0.05, 0], [0.025, 0.025], [0, 0.05]], atol=1e-9)
    np.testing.assert_allclose(n, [[1, 0], [np.sqrt(0.5), np.sqrt(0.5)], [0, 1]], atol=1e-9)


@pytest.mark.parametrize("w, h, rc", [(0.1, 0.01, 0.004), (0.1, 0.01, 0.005), (0.04, 0.04, 0.02)])
def test_rounded_rectangle_perimeter(w, h, rc):
    prof = shapes.rounded_rectangle(w, h, rc)
    assert prof.length == pytest.approx(2 * (w + h) - 8 * rc + 2 * np.pi * rc, rel=1e-12)


@pytest.mark.parametrize(
    "profile, expect",
    [
        (shapes.step(0.015), [[-0.01, 0.01]]),
        (shapes.step(0.004), [[-np.sqrt(0.01**2 - 0.006**2), 0.01]]),
        (
            shapes.wire_on_plane(0.00065),
            [[-2 * np.sqrt(0.01 * 0.000325), 0.01], [2 * np.sqrt(0.01 * 0.000325), 0.01]],
        ),
        (
            shapes.wire_on_plane(0.03, length=0.2),
            [[-2 * np.sqrt(0.01 * 0.015), 0.01], [2 * np.sqrt(0.01 * 0.015), 0.01]],
        ),
        (shapes.ravine(0.005, 0.02), [[0.0, np.sqrt(0.01**2 - 0.0025**2)]]),
    ],
    ids=["tall_step", "low_step", "thin_wire", "thick_wire", "narrow_ravine"],
)
@pytest.mark.parametrize("samples", [2e3, 3e4])
def test_coarse_to_fine_path_matches_closed_forms(profile, expect, samples):
    """Dense profiles go through the coarse-to-fine removal test: same exact answers."""
    tc = c.traced_curve(profile, 0.01, spacing=profile.length / samples)
    np.testing.assert_allclose(tc.interference_points, expect, atol=1e-9)
    d = c.distance_to_profile(tc.points[:: max(1, len(tc.points) // 3000)], profile)
    assert d.min() >= 0.01 - 1e-7


@settings(max_examples=25, deadline=None)
@given(
    n=st.integers(3, 9),
    radius=st.floats(0.02, 0.1),
    turn=st.floats(0.0, 2 * np.pi),
    theta=st.floats(0.0, 2 * np.pi),
)
def test_regular_polygon_polar_lookup_closed_form(n, radius, turn, theta):
    """Sharp regular n-gons (clockwise vertices, centred): on the face whose outward normal
    is at ``a``, the point at polar angle theta lies at apothem / cos(theta - a) [m]. Their
    pieces meet 1e-18 m apart at the corners, which the lookup once refused as "not
    star-shaped"."""
    ang = turn - 2 * np.pi * np.arange(n) / n
    poly = shapes.polygon(radius * np.column_stack([np.cos(ang), np.sin(ang)]))
    p, nrm = poly.point_at_polar_angle(np.array([theta]))
    faces = ang - np.pi / n  # outward normal of the face between vertices k and k+1
    off = np.angle(np.exp(1j * (theta - faces)))
    k = int(np.argmin(np.abs(off)))
    apothem = radius * np.cos(np.pi / n)
    expect = apothem / np.cos(off[k]) * np.array([np.cos(theta), np.sin(theta)])
    np.testing.assert_allclose(p[0], expect, atol=1e-6 * radius)
    if abs(abs(off[k]) - np.pi / n) > 1e-3:  # away from a corner: the face's normal
        np.testing.assert_allclose(nrm[0], [np.cos(faces[k]), np.sin(faces[k])], atol=1e-6)
