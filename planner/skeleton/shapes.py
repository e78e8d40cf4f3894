"""Synthetic feature outlines with known medial axes, for tests, scenarios and benchmarks.

A *ridge* is the set of points within ``width / 2`` of a centre line (shapely ``buffer``
with round caps and joins), so its medial axis is the centre line itself (straight, curved,
sharply turning, branching ridges; a ring is the buffer of a circle). Rectangles and
ellipses have closed-form medial axes. Outlines are sampled at a uniform arc-length
``spacing`` and may carry isotropic Gaussian noise.
"""

from __future__ import annotations

import numpy as np
import shapely

from planner import checks
from planner.errors import InvalidParameter


def sample_outline(
    geom: shapely.Geometry,
    spacing: float,
    noise: float = 0.0,
    rng: np.random.Generator | None = None,
) -> np.ndarray:
    """Samples every ``spacing`` along every ring of a (multi)polygon, in trace order.

    Args:
        geom: shapely Polygon or MultiPolygon [m].
        spacing: arc-length step [m] (> 0).
        noise: standard deviation of isotropic Gaussian noise added to each sample [m].
        rng: random generator (required when ``noise > 0``).

    Returns:
        (M, 2) samples [m]; ring after ring (exterior first, then holes).
    """
    spacing = checks.positive("spacing", spacing, "m")
    noise = checks.nonnegative("noise", noise, "m")
    rings = []
    for poly in shapely.get_parts(geom):
        rings.append(poly.exterior)
        rings.extend(poly.interiors)
    out = []
    for ring in rings:
        # linear interpolation along the cumulative length: O(samples + vertices), where
        # shapely.line_interpolate_point walks the ring again for every sample
        xy = shapely.get_coordinates(ring)
        cum = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xy, axis=0).T))])
        n = max(int(round(cum[-1] / spacing)), 4)
        d = np.arange(n) * (cum[-1] / n)
        out.append(np.column_stack([np.interp(d, cum, xy[:, 0]), np.interp(d, cum, xy[:, 1])]))
    pts = np.concatenate(out)
    if noise > 0:
        if rng is None:
            raise InvalidParameter("noise > 0 needs rng (a numpy.random.Generator)")
        pts = pts + rng.normal(0.0, noise, size=pts.shape)
    return pts


def ridge_polygon(centerline: np.ndarray | list, width: float) -> shapely.Geometry:
    """The ridge of ``width`` around a centre line (or several, for branching ridges).

    Args:
        centerline: (N, 2) polyline [m], or a list of such polylines (branches).
        width: ridge width [m] (> 0).

    Returns:
        shapely Polygon [m] (round caps and joins: its medial axis is the centre line).
    """
    width = checks.positive("width", width, "m")
    lines = centerline if isinstance(centerline, list) else [centerline]
    geoms = [
        shapely.LineString(checks.points("centerline", c, dims=(2,), min_count=2)) for c in lines
    ]
    # simplify(0) first: GEOS 3.14 buffer can drop parts of dense collinear polylines
    geom = shapely.union_all(
        [shapely.buffer(shapely.simplify(x, 0.0), width / 2, quad_segs=32) for x in geoms]
    )
    return geom


def arc_centerline(
    radius: float,
    sweep_deg: float,
    n: int = 64,
    center: tuple[float, float] = (0.0, 0.0),
    start_deg: float = 0.0,
) -> np.ndarray:
    """(n, 2) points on a circular arc of ``radius`` [m] sweeping ``sweep_deg`` degrees."""
    t = np.deg2rad(start_deg + np.linspace(0.0, sweep_deg, n))
    return np.column_stack([center[0] + radius * np.cos(t), center[1] + radius * np.sin(t)])


def ring_polygon(
    radius: float, width: float, center: tuple[float, float] = (0.0, 0.0)
) -> shapely.Geometry:
    """An annulus of mid radius ``radius`` and ``width`` [m]; its medial axis is the circle."""
    radius = checks.positive("radius", radius, "m")
    width = checks.positive("width", width, "m")
    if width >= 2 * radius:
        raise InvalidParameter(f"ring: width {width} must be < 2 * radius = {2 * radius}")
    c = shapely.Point(center)
    return c.buffer(radius + width / 2, quad_segs=128).difference(
        c.buffer(radius - width / 2, quad_segs=128)
    )


def rectangle_outline(width: float, height: float, spacing: float) -> np.ndarray:
    """Samples of the boundary of an axis-aligned rectangle centred at the origin [m]."""
    return sample_outline(shapely.box(-width / 2, -height / 2, width / 2, height / 2), spacing)


def rectangle_medial_axis(width: float, height: float, n: int = 200) -> np.ndarray:
    """(P, 2) dense samples of the medial axis of the ``width`` x ``height`` rectangle.

    Closed form: the central segment of length ``|width - height|`` and four branches from
    its ends to the corners (45 degree bisectors).
    """
    a, b = width / 2, height / 2
    h = min(a, b)
    if a >= b:
        core = [(-a + h, 0.0), (a - h, 0.0)]
    else:
        core = [(0.0, -b + h), (0.0, b - h)]
    lines = [core]
    for sx in (-1, 1):
        for sy in (-1, 1):
            end = core[1] if (sx > 0 if a >= b else sy > 0) else core[0]
            lines.append([end, (sx * a, sy * b)])
    t = np.linspace(0, 1, n)[:, None]
    return np.concatenate(
        [np.asarray(p0) + t * (np.asarray(p1) - np.asarray(p0)) for p0, p1 in lines]
    )


def ellipse_outline(a: float, b: float, spacing: float, n_poly: int = 4096) -> np.ndarray:
    """Samples every ``spacing`` of arc length along the ellipse x²/a² + y²/b² = 1 [m]."""
    t = np.linspace(0, 2 * np.pi, n_poly, endpoint=False)
    ring = shapely.Polygon(np.column_stack([a * np.cos(t), b * np.sin(t)]))
    return sample_outline(ring, spacing)


def ellipse_medial_axis(a: float, b: float, n: int = 400) -> np.ndarray:
    """(n, 2) samples of the ellipse's medial axis: the segment between the centres of
    curvature of the two main vertices, ``|x| <= (a² - b²) / a`` (for a >= b) [m]."""
    if a >= b:
        c = (a * a - b * b) / a
        return np.column_stack([np.linspace(-c, c, n), np.zeros(n)])
    c = (b * b - a * a) / b
    return np.column_stack([np.zeros(n), np.linspace(-c, c, n)])


def densify(polyline: np.ndarray, step: float) -> np.ndarray:
    """(P, 2) points every at most ``step`` [m] along an (N, 2) polyline."""
    out = [polyline[:1]]
    for p0, p1 in zip(polyline[:-1], polyline[1:], strict=True):
        k = max(int(np.ceil(np.hypot(*(p1 - p0)) / step)), 1)
        t = np.arange(1, k + 1)[:, None] / k
        out.append(p0 + t * (p1 - p0))
    return np.concatenate(out)


__all__ = [
    "arc_centerline",
    "densify",
    "ellipse_medial_axis",
    "ellipse_outline",
    "rectangle_medial_axis",
    "rectangle_outline",
    "ridge_polygon",
    "ring_polygon",
    "sample_outline",
]
