"""Exact contact geometry of catalogue outlines (closest points, candidates)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from planner.geometry import shapes
from planner.geometry.primitives import Line
from planner.geometry.profiles import Profile
from planner.sim.planar.contacts import Pose, candidates
from planner.sim.planar.outline import closest_point, compile_outline


def _brute(profile, p, n=200001):
    P, _, _ = profile.evaluate(np.linspace(0, profile.length, n))
    return float(np.min(np.hypot(P[:, 0] - p[0], P[:, 1] - p[1])))


@settings(max_examples=40, deadline=None, derandomize=True)
@given(x=st.floats(-0.08, 0.08), y=st.floats(-0.08, 0.08))
def test_closest_point_on_ellipse_is_exact(x, y):
    prof = shapes.ellipse(0.04, 0.02)
    ol = compile_outline(prof)
    d, qx, qy, nx, ny = closest_point(ol, x, y)
    # q lies on the ellipse, p = q + d n, and no sampled point is closer
    assert (qx / 0.04) ** 2 + (qy / 0.02) ** 2 == pytest.approx(1.0, abs=1e-12)
    assert np.allclose([qx + d * nx, qy + d * ny], [x, y], atol=1e-12)
    assert abs(d) <= _brute(prof, (x, y)) + 1e-12
    inside = (x / 0.04) ** 2 + (y / 0.02) ** 2 < 1
    assert (d < 0) == inside or abs(d) < 1e-12


@settings(max_examples=40, deadline=None, derandomize=True)
@given(x=st.floats(-0.05, 0.05), y=st.floats(-0.03, 0.03))
@example(x=0.04819155758670261, y=0.028938207251689316)  # beyond a corner
def test_closest_point_on_rounded_rectangle_is_exact(x, y):
    prof = shapes.rounded_rectangle(0.04, 0.02, 0.005)
    d, qx, qy, nx, ny = closest_point(compile_outline(prof), x, y)
    assert np.allclose([qx + d * nx, qy + d * ny], [x, y], atol=1e-12)
    # the brute force is never closer, and farther by at most its sampling error: a sample
    # lies within one spacing h of the true closest point along the outline, and a point t
    # along it from there is at most sqrt(d^2 + (1 + |d| kappa) t^2) away (|p - c(t)|^2 has
    # slope 0 at the closest point and second derivative 2 (1 - (p - c) . c'') <= 2 (1 +
    # |d| kappa) there; kappa <= 1/0.005 on the corners). The flat sides' hypot(d, h) was
    # off by 7e-14 m at (0.048, 0.029), 36 mm beyond a corner: found by Hypothesis
    h = prof.length / 200000
    brute = _brute(prof, (x, y))
    sampling = math.hypot(d, h * math.sqrt(1.0 + abs(d) / 0.005)) - abs(d)
    assert -1e-12 <= brute - abs(d) <= sampling + 1e-12


def test_candidates_closed_forms():
    disc = compile_outline(shapes.circle(0.05))
    a = 0.3
    plane = compile_outline(shapes.plane(a, 0.5))
    c = candidates(disc, Pose(0.0, 0.049, 0.0), plane, Pose(0.0, 0.0, 0.0), 0.01)
    assert len(c) == 1
    assert c[0][0] == pytest.approx(0.049 * math.cos(a) - 0.05, abs=1e-15)
    assert np.allclose(c[0][5:7], [-math.sin(a), math.cos(a)])
    box = compile_outline(shapes.rounded_rectangle(0.04, 0.02))
    flat = compile_outline(shapes.plane(0.0, 0.5))
    c = candidates(box, Pose(0.0, 0.0101, 0.0), flat, Pose(0.0, 0.0, 0.0), 0.01)
    assert len(c) == 2 and all(abs(k[0] - 1e-4) < 1e-15 for k in c)  # the two corners
    ell = compile_outline(shapes.ellipse(0.04, 0.02))
    th = 0.3
    c = candidates(ell, Pose(0.0, 0.0201, th), flat, Pose(0.0, 0.0, 0.0), 0.01)
    support = math.sqrt((0.04 * math.sin(th)) ** 2 + (0.02 * math.cos(th)) ** 2)
    assert len(c) == 1 and c[0][0] == pytest.approx(0.0201 - support, abs=1e-14)
    # two ellipses stacked: gap between the tips of their minor axes
    c = candidates(ell, Pose(0.0, 0.0401, 0.0), ell, Pose(0.0, 0.0, 0.0), 0.01)
    assert len(c) == 1 and c[0][0] == pytest.approx(1e-4, abs=1e-14)
    # disc in a concave arc fillet is found from the disc's side
    far = candidates(disc, Pose(1.0, 1.0, 0.0), flat, Pose(0.0, 0.0, 0.0), 0.01)
    assert far == []


def test_open_outline_ends_are_unsigned():
    """A one-sided face: behind it only within its slab; beyond its ends the distance is
    unsigned (PS's repro: the pad's corner 9 cm behind the palm was a phantom penetration)."""
    palm = compile_outline(shapes.plane(0.0, 0.16))  # y = 0, x in [-0.08, 0.08], facing +y
    d, qx, qy, nx, ny = closest_point(palm, 0.0, -0.003)  # within the slab, behind: inside
    assert d == pytest.approx(-0.003, abs=1e-15) and (qx, qy, nx, ny) == (0.0, 0.0, 0.0, 1.0)
    d, qx, qy, nx, ny = closest_point(palm, 0.09, -0.05)  # beyond the end, below the line
    assert d == pytest.approx(math.hypot(0.01, 0.05), abs=1e-15) and (qx, qy) == (0.08, 0.0)
    assert np.allclose([qx + d * nx, qy + d * ny], [0.09, -0.05], atol=1e-15)
    pad = compile_outline(Profile((Line((-0.005, 0.0), (0.005, 0.0)),), name="pad"))
    n = (-0.876903, 0.480667)
    a = math.atan2(-n[0], n[1])
    where = Pose(-0.03 + 0.005 * math.cos(a), 0.0745 + 0.005 * math.sin(a), a)
    assert candidates(pad, where, palm, Pose(0.0, 0.0, 0.0), 1e-3) == []
    # a disc through the palm's end: overlap = |centre - end| - r, normal from the end
    disc = compile_outline(shapes.circle(0.01))
    c = candidates(disc, Pose(0.085, -0.002, 0.0), palm, Pose(0.0, 0.0, 0.0), 1e-3)
    d = math.hypot(0.005, 0.002)
    assert len(c) == 1 and c[0][0] == pytest.approx(d - 0.01, abs=1e-15)
    assert np.allclose(c[0][5:7], [0.005 / d, -0.002 / d], atol=1e-15)
    assert np.allclose(c[0][3:5], [0.08, 0.0], atol=1e-15)


def _star_polygon(radii, angles) -> list[tuple[float, float]]:
    """A polygon with vertices at increasing ``angles`` [rad] and ``radii`` [m] (sharp
    convex corners and deep reflex notches both occur); simple when no angular gap, the
    closing one included, exceeds pi (callers check: shapely's ``is_valid``)."""
    return [(r * math.cos(a), r * math.sin(a)) for r, a in zip(radii, angles, strict=True)]


star = st.integers(3, 9).flatmap(
    lambda n: st.tuples(
        st.lists(st.floats(0.01, 0.05), min_size=n, max_size=n),
        st.lists(st.floats(0.1, 1.0), min_size=n, max_size=n),
    )
)


def _signed_distances(vertices, px, py):
    """(Python path, compiled kernel) signed distances of (px, py) to the polygon [m]."""
    from planner.sim.planar.geometry_kernel import closest
    from planner.sim.planar.packed_outlines import PackedOutlines

    ol = compile_outline(shapes.polygon(vertices))
    packed = PackedOutlines.from_outlines([ol])
    return closest_point(ol, px, py)[0], closest(packed.F, packed.I, 0, px, py)[0]


@settings(max_examples=150, deadline=None, derandomize=True)
@given(
    shape=star,
    corner=st.integers(0, 8),
    dist=st.floats(1e-4, 0.03),
    direction=st.floats(-math.pi, math.pi),
)
@example(  # a round 25 mm fingertip on a triangle's 60 deg corner (2026-11-25 gait fault)
    shape=([0.04, 0.04, 0.04], [1.0, 1.0, 1.0]), corner=0, dist=0.025, direction=0.9
)
def test_polygon_corners_are_signed_by_inside_or_outside(shape, corner, dist, direction):
    """Near any corner, sharp or reflex: |d| is the distance to the outline and d < 0 exactly
    inside (shapely's verdict), in the Python path and the compiled kernel alike. A sharp
    corner's normal cone holds points behind one of its faces: until 2026-11-25 those came
    out at -|d| (a 50 mm phantom penetration of a fingertip touching a triangle's corner)."""
    from shapely.geometry import Point, Polygon

    radii, steps = shape
    angles = np.cumsum(steps)
    angles = angles * (2 * math.pi / (angles[-1] + steps[0]))
    vertices = _star_polygon(radii, angles)
    vx, vy = vertices[corner % len(vertices)]
    px, py = vx + dist * math.cos(direction), vy + dist * math.sin(direction)
    poly = Polygon(vertices)
    assume(poly.is_valid)  # an angular gap past pi crosses the outline (not an outline)
    exact = poly.exterior.distance(Point(px, py))
    if exact < 1e-9:
        return  # on the outline: no sign to check
    inside = poly.contains(Point(px, py))
    for d in _signed_distances(vertices, px, py):
        assert abs(d) == pytest.approx(exact, abs=1e-12)
        assert (d < 0) == inside


def test_a_fingertip_on_a_sharp_corner_is_touching_not_deep():
    """The gait fault's geometry: a 25 mm disc whose centre is in a 60 deg corner's normal
    cone, partly behind one face's line, touches the corner (gap 0), never 50 mm deep -
    at every corner of a turned triangle (which face wins the distance tie is round-off)."""
    r = 0.04
    disc = compile_outline(shapes.circle(0.025))
    for turn in np.linspace(0.0, 2 * math.pi / 3, 7, endpoint=False):
        corners = turn + np.array([0.0, 2 * math.pi / 3, 4 * math.pi / 3])
        tri = compile_outline(shapes.polygon(_star_polygon([r] * 3, corners)))
        for c in corners:
            for a in c + np.radians(np.linspace(-59.0, 59.0, 13)):  # within the cone
                centre = Pose(
                    r * math.cos(c) + 0.025 * math.cos(a),
                    r * math.sin(c) + 0.025 * math.sin(a),
                    0.0,
                )
                gaps = [g[0] for g in candidates(disc, centre, tri, Pose(0.0, 0.0, 0.0), 1e-3)]
                assert gaps and min(gaps) == pytest.approx(0.0, abs=1e-12)
