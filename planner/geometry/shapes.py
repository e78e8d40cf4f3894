"""The catalogue of 2-D profiles (thesis §3.2.2-3.4: steps, wires, ridges, ravines, bumps,
pits, cusps; closed objects for grasping, §2.2.1).

Open profiles are centred on ``x0`` and span ``length`` [m] along x (default 0.06 m, several
fingertip radii), run in +x with the material below (y < surface). Closed profiles are
centred on the origin and run clockwise. All sizes in metres, angles in radians.
"""

from __future__ import annotations

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from planner.geometry.primitives import Arc, Line, Parametric, turn_angle
from planner.geometry.profiles import Profile

DEFAULT_LENGTH = 0.06


def _length(name: str, value: float) -> float:
    return checks.positive(name, value, "m")


def _finite(name: str, value: float, unit: str) -> float:
    return checks.in_range(name, value, -np.inf, np.inf, unit, closed=(False, False))


def _coordinate(name: str, value: float) -> float:
    return _finite(name, value, "m")


def _chain(points: np.ndarray, radii: np.ndarray | None = None, closed: bool = False) -> list:
    """Pieces of a polyline through ``points`` (n, 2), with optional corner fillets.

    ``radii[i]`` rounds the corner at vertex i with a tangent circular arc of that radius
    (0 keeps it sharp). Fillets must fit in the adjacent segments.
    """
    P = np.asarray(points, float)
    n = len(P)
    if radii is None:
        radii = np.zeros(n)
    # per vertex: (entry point, arc or None, exit point)
    entry = [P[i].copy() for i in range(n)]
    exitp = [P[i].copy() for i in range(n)]
    arcs: list = [None] * n
    cut = np.zeros(n)  # length each fillet takes from the two adjacent segments
    geo = {}
    idx = range(n) if closed else range(1, n - 1)
    for i in idx:
        rho = radii[i]
        if rho <= 0:
            continue
        a, b, c = P[i - 1], P[i], P[(i + 1) % n]
        t1 = (b - a) / np.linalg.norm(b - a)
        t2 = (c - b) / np.linalg.norm(c - b)
        turn = turn_angle(t1, t2)
        if abs(turn) < 1e-12:
            continue
        cut[i] = rho * np.tan(abs(turn) / 2)
        geo[i] = (b, t1, t2, turn, rho)
    segs = range(n) if closed else range(n - 1)
    for i in segs:
        j = (i + 1) % n
        length = np.linalg.norm(P[j] - P[i])
        if cut[i] + cut[j] > length * (1 + 1e-9):
            raise InvalidParameter(
                f"corner radii at vertices {i} and {j} do not fit on the side between "
                f"{P[i].tolist()} and {P[j].tolist()} ({length:.4g} m long; they need "
                f"{cut[i] + cut[j]:.4g} m)"
            )
    for i, (b, t1, t2, turn, rho) in geo.items():
        d = cut[i]
        e0, e1 = b - d * t1, b + d * t2
        side = np.array([-t1[1], t1[0]]) * np.sign(turn)  # toward the centre
        centre = e0 + rho * side
        phi0 = np.arctan2(*(e0 - centre)[::-1])
        arcs[i] = Arc(tuple(centre), rho, float(phi0), float(turn))
        entry[i], exitp[i] = e0, e1
    pieces = []
    last = n if closed else n - 1
    for i in range(last):
        j = (i + 1) % n
        if arcs[i] is not None:
            pieces.append(arcs[i])
        if np.linalg.norm(entry[j] - exitp[i]) > 1e-15:
            pieces.append(Line(tuple(exitp[i]), tuple(entry[j])))
    if closed and arcs[0] is not None:
        pieces = [arcs[0], *pieces]
        pieces = pieces[1:] + pieces[:1]
    return pieces


def _signed_area(P: np.ndarray) -> float:
    x, y = P[:, 0], P[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def plane(angle: float = 0.0, length: float = DEFAULT_LENGTH, x0: float = 0.0) -> Profile:
    """A straight surface through (x0, 0), inclined by ``angle`` [rad] about that point."""
    L, x0 = _length("length", length), _coordinate("x0", x0)
    angle = _finite("angle", angle, "rad")
    base = Profile((Line((-L / 2, 0.0), (L / 2, 0.0)),), name="plane")
    return base.transformed(angle, (x0, 0.0))


def step(height: float, x0: float = 0.0, length: float = DEFAULT_LENGTH) -> Profile:
    """A sharp step of ``height`` [m] at ``x0`` (positive: up in +x; negative: down)."""
    h = _coordinate("height", height)
    if h == 0:
        raise InvalidParameter("height: expected a non-zero finite number [m], got 0")
    L, x0 = _length("length", length), _coordinate("x0", x0)
    pts = [(x0 - L / 2, 0.0), (x0, 0.0), (x0, h), (x0 + L / 2, h)]
    return Profile(tuple(_chain(np.array(pts))), name=f"step({h:g})")


def ridge(
    width: float,
    height: float,
    corner_radius: float = 0.0,
    x0: float = 0.0,
    length: float = DEFAULT_LENGTH,
) -> Profile:
    """A rectangular ridge of ``width`` x ``height`` [m] centred at ``x0``; its two top
    (convex) corners are rounded with ``corner_radius`` [m] (0: sharp); the base corners are
    sharp and concave."""
    return _rectangular(width, _length("height", height), corner_radius, x0, length, "ridge")


def ravine(
    width: float,
    depth: float,
    corner_radius: float = 0.0,
    x0: float = 0.0,
    length: float = DEFAULT_LENGTH,
) -> Profile:
    """A rectangular groove of ``width`` x ``depth`` [m] centred at ``x0``; its two rim
    (convex) corners are rounded with ``corner_radius`` [m]; the bottom corners are sharp."""
    return _rectangular(width, -_length("depth", depth), corner_radius, x0, length, "ravine")


def _rectangular(width, rise, corner_radius, x0, length, name) -> Profile:
    """A rectangular ridge (``rise > 0``) or groove (``rise < 0``) in a plane; the convex
    corners (top of a ridge, rim of a groove) are rounded with ``corner_radius``."""
    w = _length("width", width)
    L, x0 = _length("length", length), _coordinate("x0", x0)
    c = checks.nonnegative("corner_radius", corner_radius, "m")
    xs = (x0 - L / 2, x0 - w / 2, x0 - w / 2, x0 + w / 2, x0 + w / 2, x0 + L / 2)
    pts = np.column_stack([xs, (0.0, 0.0, rise, rise, 0.0, 0.0)])
    radii = np.array([0, 0, c, c, 0, 0] if rise > 0 else [0, c, 0, 0, c, 0], float)
    return Profile(tuple(_chain(pts, radii)), name=name)


def _gaussian_piece(height: float, sigma: float, x0: float, L: float) -> Parametric:
    h, s = height, sigma

    def f(u):
        return np.stack([u, h * np.exp(-((u - x0) ** 2) / (2 * s * s))], axis=-1)

    def df(u):
        g = np.exp(-((u - x0) ** 2) / (2 * s * s))
        return np.stack([np.ones_like(u), -h * (u - x0) / s**2 * g], axis=-1)

    def ddf(u):
        g = np.exp(-((u - x0) ** 2) / (2 * s * s))
        return np.stack([np.zeros_like(u), h * ((u - x0) ** 2 / s**4 - 1 / s**2) * g], axis=-1)

    return Parametric(f, df, ddf, x0 - L / 2, x0 + L / 2, table=20001)


def bump(
    height: float, width: float, shape: str = "arc", x0: float = 0.0, length: float = DEFAULT_LENGTH
) -> Profile:
    """A bump on a plane, centred at ``x0``.

    Args:
        height: peak height [m] (> 0; use :func:`pit` for depressions).
        width: base width for ``"arc"`` and ``"parabolic"``; standard deviation of the
            Gaussian for ``"gaussian"`` [m].
        shape: ``"arc"`` (circular cap meeting the plane at sharp concave corners),
            ``"parabolic"`` (y = h (1 - (2(x-x0)/w)^2), sharp base corners) or
            ``"gaussian"`` (y = h exp(-(x-x0)^2 / (2 w^2)), smooth everywhere).
    """
    return _bump(height, width, shape, x0, length, sign=1.0)


def pit(
    depth: float, width: float, shape: str = "arc", x0: float = 0.0, length: float = DEFAULT_LENGTH
) -> Profile:
    """A depression of ``depth`` [m]: the mirror image of :func:`bump` (same shapes)."""
    return _bump(depth, width, shape, x0, length, sign=-1.0)


def _bump(h, w, shape, x0, length, sign) -> Profile:
    h, w, L = _length("height", h), _length("width", w), _length("length", length)
    x0 = _coordinate("x0", x0)
    checks.choice("shape", shape, ("arc", "parabolic", "gaussian"))
    name = "bump" if sign > 0 else "pit"
    if shape == "gaussian":
        return Profile((_gaussian_piece(sign * h, w, x0, L),), name=name)
    if w >= L:
        raise InvalidParameter(f"width: expected a number < length = {L:g} [m], got {w!r}")
    left, right = (x0 - L / 2, 0.0), (x0 + L / 2, 0.0)
    a, b = (x0 - w / 2, 0.0), (x0 + w / 2, 0.0)
    if shape == "arc":
        R = (w * w / 4 + h * h) / (2 * h)
        cy = sign * (h - R)
        phi_a = np.arctan2(-cy, -w / 2)
        phi_b = np.arctan2(-cy, w / 2)
        sweep = (
            (phi_b - phi_a) % (2 * np.pi) - 2 * np.pi if sign > 0 else (phi_b - phi_a) % (2 * np.pi)
        )
        mid = Arc((x0, cy), R, float(phi_a), float(sweep))
    else:  # "parabolic" (checked above)
        c = sign * h

        def f(u):
            return np.stack([u, c * (1 - (2 * (u - x0) / w) ** 2)], axis=-1)

        def df(u):
            return np.stack([np.ones_like(u), -8 * c * (u - x0) / w**2], axis=-1)

        def ddf(u):
            return np.stack([np.zeros_like(u), np.full_like(u, -8 * c / w**2)], axis=-1)

        mid = Parametric(f, df, ddf, a[0], b[0])
    return Profile((Line(left, a), mid, Line(b, right)), name=name)


def wire_on_plane(
    diameter: float, angle: float = 0.0, x0: float = 0.0, length: float = DEFAULT_LENGTH
) -> Profile:
    """A round wire of ``diameter`` [m] lying on a plane inclined by ``angle`` [rad], touching
    it at distance ``x0`` [m] along the plane from the origin (thesis §3.4.2, Fig. 3.12).

    The profile is the outline of plane ∪ wire: the plane up to the contact point, once around
    the wire (convex), and the plane again; the two wedges between wire and plane are concave
    cusps (turning angle π).
    """
    d, L = _length("diameter", diameter), _length("length", length)
    x0 = _coordinate("x0", x0)
    angle = _finite("angle", angle, "rad")
    a = d / 2
    pieces = (
        Line((x0 - L / 2, 0.0), (x0, 0.0)),
        Arc((x0, a), a, -np.pi / 2, -2 * np.pi),
        Line((x0, 0.0), (x0 + L / 2, 0.0)),
    )
    return Profile(pieces, name="wire").transformed(angle, (0.0, 0.0))


def cusp(angle: float, x0: float = 0.0, length: float = DEFAULT_LENGTH) -> Profile:
    """A convex roof-shaped corner at (x0, 0) with interior angle ``angle`` [rad] in (0, π)."""
    angle = checks.in_range("angle", angle, 0.0, np.pi, "rad", closed=(False, False))
    L, x0 = _length("length", length), _coordinate("x0", x0)
    slope = 1.0 / np.tan(angle / 2)
    pts = np.array([(x0 - L / 2, -slope * L / 2), (x0, 0.0), (x0 + L / 2, -slope * L / 2)])
    return Profile(tuple(_chain(pts)), name="cusp")


def circle(radius: float) -> Profile:
    """A circle of ``radius`` [m] about the origin (closed, clockwise from (radius, 0))."""
    R = _length("radius", radius)

    def polar(theta):
        u = np.stack([np.cos(theta), np.sin(theta)], axis=-1)
        return R * u, u

    return Profile(
        (Arc((0.0, 0.0), R, 0.0, -2 * np.pi),), closed=True, name="circle", exact_polar=polar
    )


def ellipse(a: float, b: float) -> Profile:
    """An ellipse with semi-axes ``a`` (along x) and ``b`` (along y) [m] (closed)."""
    a, b = _length("a", a), _length("b", b)

    def f(u):
        return np.stack([a * np.cos(u), b * np.sin(u)], axis=-1)

    def df(u):
        return np.stack([-a * np.sin(u), b * np.cos(u)], axis=-1)

    def ddf(u):
        return np.stack([-a * np.cos(u), -b * np.sin(u)], axis=-1)

    def polar(theta):
        r = a * b / np.hypot(b * np.cos(theta), a * np.sin(theta))
        p = np.stack([r * np.cos(theta), r * np.sin(theta)], axis=-1)
        n = np.stack([p[:, 0] / a**2, p[:, 1] / b**2], axis=-1)
        return p, n / np.linalg.norm(n, axis=1, keepdims=True)

    return Profile(
        (Parametric(f, df, ddf, 0.0, -2 * np.pi, table=20001),),
        closed=True,
        name="ellipse",
        exact_polar=polar,
    )


def rounded_rectangle(width: float, height: float, corner_radius: float = 0.0) -> Profile:
    """A ``width`` x ``height`` [m] rectangle about the origin with corners rounded by
    ``corner_radius`` [m] (closed; corner_radius = min(w, h)/2 gives a stadium)."""
    w, h = _length("width", width), _length("height", height)
    corner_radius = checks.in_range("corner_radius", corner_radius, 0.0, min(w, h) / 2, "m")
    pts = np.array(
        [(w / 2, 0.0), (w / 2, -h / 2), (-w / 2, -h / 2), (-w / 2, h / 2), (w / 2, h / 2)]
    )
    radii = np.array([0, corner_radius, corner_radius, corner_radius, corner_radius])
    return Profile(tuple(_chain(pts, radii, closed=True)), closed=True, name="rounded_rectangle")


def _vertices(points, minimum: int) -> np.ndarray:
    P = checks.points("points", points, dims=(2,), min_count=minimum)
    same = np.flatnonzero(np.linalg.norm(np.diff(P, axis=0), axis=1) == 0)
    if len(same):
        raise InvalidParameter(
            f"points: expected no consecutive duplicates [m], got rows {same[0]} and "
            f"{same[0] + 1} equal ({P[same[0]].tolist()})"
        )
    return P


def polyline(points) -> Profile:
    """An open polyline through ``points`` (N, 2) [m], N >= 2, material on the right of
    travel (for a left-to-right surface: below)."""
    P = _vertices(points, 2)
    return Profile(tuple(_chain(P)), name="polyline")


def polygon(points) -> Profile:
    """A closed polygon through ``points`` (N, 2) [m], N >= 3 (reordered clockwise).

    Raises:
        InvalidParameter: fewer than 3 points, consecutive duplicates, or an outline that
            crosses or touches itself (not the boundary of one region).
    """
    P = _vertices(points, 3)
    if np.allclose(P[0], P[-1]):
        P = P[:-1]
    _simple(P)
    if _signed_area(P) > 0:
        P = P[::-1]
    return Profile(tuple(_chain(P, closed=True)), closed=True, name="polygon")


def _simple(P: np.ndarray) -> None:
    """Refuse a closed polygon ``P`` (N, 2) that is not the boundary of one region: fewer
    than 3 vertices, or edges that cross or touch (other than neighbours at their shared
    vertex; the first such pair is named), or one that retraces itself along a line."""
    from shapely.geometry import LinearRing, LineString

    n = len(P)
    if n < 3:
        raise InvalidParameter(
            f"points: expected at least 3 vertices, got {n} (the last point repeats the first)"
        )
    if LinearRing(P).is_simple:
        return
    for i in range(n):
        for j in range(i + 2, n - (i == 0)):  # not neighbours (they share a vertex)
            ab, cd = P[[i, (i + 1) % n]], P[[j, (j + 1) % n]]
            if LineString(ab).intersects(LineString(cd)):
                raise InvalidParameter(
                    f"points: the polygon crosses itself: edge {i} ({ab[0].tolist()} -> "
                    f"{ab[1].tolist()}) meets edge {j} ({cd[0].tolist()} -> {cd[1].tolist()})"
                )
    raise InvalidParameter("points: the polygon retraces itself along a line (no area)")


def spline(points, closed: bool = False) -> Profile:
    """A C² cubic spline through ``points`` (N, 2) [m] (chord-length parametrized; periodic
    when ``closed``, then reordered clockwise)."""
    from scipy.interpolate import CubicSpline

    P = _vertices(points, 3 if closed else 2)
    if closed:
        if not np.allclose(P[0], P[-1]):
            P = np.vstack([P, P[:1]])
        if _signed_area(P[:-1]) > 0:
            P = P[::-1]
    u = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])
    cs = CubicSpline(u, P, bc_type="periodic" if closed else "natural", axis=0)
    d1, d2 = cs.derivative(1), cs.derivative(2)
    piece = Parametric(
        lambda x: cs(x),
        lambda x: d1(x),
        lambda x: d2(x),
        0.0,
        float(u[-1]),
        table=max(4097, 64 * len(P) + 1),
    )
    return Profile((piece,), closed=closed, name="spline")


__all__ = [
    "bump",
    "circle",
    "cusp",
    "ellipse",
    "pit",
    "plane",
    "polygon",
    "polyline",
    "ravine",
    "ridge",
    "rounded_rectangle",
    "spline",
    "step",
    "wire_on_plane",
]
