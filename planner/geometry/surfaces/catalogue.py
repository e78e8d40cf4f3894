"""Catalogue of parametric surfaces: the thesis' examples and the macro features of Table 3.1.

Every constructor returns a :class:`ParametricSurface` whose outward normal points away from
the material (up, ``+z``, for the feature surfaces lying on the plane ``z = 0``). Feature
surfaces are *profiles swept along a line* (``f(u, v) = (X(u), v, Z(u))``) or, with
``bend_radius``, along a circular arc in the ``xy`` plane; both are orthogonal coordinate
systems, so Montana's forms are exactly eqs. A.2-A.4.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import casadi as ca
import numpy as np

from planner import checks
from planner.geometry.surfaces.parametric import ParametricSurface

Profile = Callable[[ca.SX], tuple[ca.SX, ca.SX]]
INF = math.inf


def plane() -> ParametricSurface:
    """The plane ``z = 0``, ``f(u, v) = (u, v, 0)``, normal ``+z``; ``K = 0``, ``M = I``."""
    return ParametricSurface(lambda u, v: [u, v, 0 * u], ((-INF, INF), (-INF, INF)), name="plane")


def sphere(radius: float) -> ParametricSurface:
    """Sphere of radius ``R`` with exactly the parametrization of eq. A.7.

    ``f(u, v) = (R cos u cos v, -R cos u sin v, R sin u)`` on
    ``U = (-π/2, π/2) x (-π, π)`` (eq. A.5), outward normal (A.8). Closed forms (A.10):
    ``K = I/R``, ``T = [0, -tan(u)/R]``, ``M = diag(R, R cos u)``.

    Note: the OCR of eq. A.9 swaps ``y`` and ``z``; from A.1 and A.7,
    ``y = (-sin v, -cos v, 0)`` and ``z = (cos u cos v, -cos u sin v, sin u)``.

    Args:
        radius: ``R`` [m].
    """
    r = checks.positive("radius", radius, "m")
    return ParametricSurface(
        lambda u, v: [r * ca.cos(u) * ca.cos(v), -r * ca.cos(u) * ca.sin(v), r * ca.sin(u)],
        ((-math.pi / 2, math.pi / 2), (-math.pi, math.pi)),
        name=f"sphere(R={r:g})",
    )


def cylinder(radius: float, length: float = INF) -> ParametricSurface:
    """Circular cylinder about the ``z`` axis: ``f(u, v) = (R cos u, R sin u, v)``.

    ``U = (-π, π) x (-length/2, length/2)``; ``k1 = 1/R`` (around), ``k2 = 0`` (along).

    Args:
        radius: ``R`` [m].
        length: axial extent of the patch [m] (default unbounded).
    """
    r = checks.positive("radius", radius, "m")
    half = checks.positive("length", length, "m", allow_inf=True) / 2
    return ParametricSurface(
        lambda u, v: [r * ca.cos(u), r * ca.sin(u), v],
        ((-math.pi, math.pi), (-half, half)),
        name=f"cylinder(R={r:g})",
    )


def bump(a: float) -> ParametricSurface:
    """The parabolic bump of revolution of eqs. 3.12-3.13.

    ``f(u, v) = (u cos v, u sin v, 1/(1 + a u^2))`` on ``U = (-1, 1) x (0, π)``; the normal
    points up (eq. 3.14), so ``f_u × f_v`` is outward for ``u > 0`` and inward for ``u < 0``.
    ``K = diag(2ad(1-3au^2)/(c(d^4+4a^2u^2)), 2a/(cd^2))`` (eq. 3.17) with ``c, d`` of eqs.
    3.15-3.16. The apex ``u = 0`` is a removable singularity (``f_v = 0``). The OCR of eq.
    3.14 prints the z-component of ``x`` as ``+2au/(cd^2)``; ``x = f_u/|f_u|`` gives
    ``-2au/(cd^2)`` (and only that is orthogonal to ``z``).

    Args:
        a: sharpness of the bump, ``a > -1`` so that ``1 + a u^2 > 0`` on ``U`` [1/m^2].
    """
    return _bump(a, 1.0, "bump")


def pit(a: float) -> ParametricSurface:
    """The negated bump: ``f(u, v) = (u cos v, u sin v, -1/(1 + a u^2))``, normal up.

    Its curvature form is minus that of :func:`bump` (a pit in Table 3.1).

    Args:
        a: sharpness, ``a > -1`` [1/m^2].
    """
    return _bump(a, -1.0, "pit")


def _bump(a: float, sign: float, name: str) -> ParametricSurface:
    # a > -1 keeps 1 + a u^2 > 0 on the domain -1 < u < 1
    a = checks.in_range("a", a, -1.0, math.inf, "1/m^2", closed=(False, False))
    return ParametricSurface(
        lambda u, v: [u * ca.cos(v), u * ca.sin(v), sign / (1 + a * u**2)],
        ((-1.0, 1.0), (0.0, math.pi)),
        orientation=lambda u, v: ca.sign(u),
        name=f"{name}(a={a:g})",
        inverse=_polar_inverse,
    )


def _polar_inverse(x, y):
    """``(x, y) -> (u, v)`` for ``(u cos v, u sin v)`` with ``0 <= v < π``, ``u`` signed."""
    r = np.hypot(x, y)
    ang = np.arctan2(y, x)
    upper = ang >= 0
    return np.where(upper, r, -r), np.where(upper, ang, ang + np.pi)


def swept_profile(
    profile: Profile,
    u_range: tuple[float, float],
    *,
    bend_radius: float | None = None,
    length: float = INF,
    name: str = "swept",
    graph: bool = False,
) -> ParametricSurface:
    """A profile curve ``(X(u), Z(u))`` swept along the ``y`` axis or a circular arc.

    Straight: ``f(u, v) = (X(u), v, Z(u))``. Bent: the profile's ``X`` is measured outward
    from a circle of radius ``bend_radius`` in the ``xy`` plane and ``v`` is arc length along
    it: ``f = ((ρ + X) cos(v/ρ), (ρ + X) sin(v/ρ), Z)``. The profile must run with increasing
    ``X`` so that ``(-Z', X')`` (the normal) points up; both are orthogonal coordinates.

    Args:
        profile: ``profile(u) -> (X, Z)`` as CasADi expressions [m].
        u_range: ``(u_min, u_max)`` of the profile parameter.
        bend_radius: radius ``ρ`` of the sweep circle [m], or ``None`` for a straight sweep;
            must exceed ``-X`` everywhere.
        length: extent of the sweep in ``v`` [m] (default unbounded; at most ``2πρ`` bent).
        name: label.
        graph: the profile is a graph, ``X(u) = u``: enables the ``(x, y) -> (u, v)`` inverse.
    """
    inverse = None
    if bend_radius is None:

        def smap(u, v):
            x, z = profile(u)
            return [x, v, z]

        half = checks.positive("length", length, "m", allow_inf=True) / 2
        if graph:
            inverse = _identity_inverse
    else:
        rho = checks.positive("bend_radius", bend_radius, "m")
        half = min(checks.positive("length", length, "m", allow_inf=True), 2 * math.pi * rho) / 2

        def smap(u, v):
            x, z = profile(u)
            return [(rho + x) * ca.cos(v / rho), (rho + x) * ca.sin(v / rho), z]

        if graph:

            def inverse(x, y):
                return np.hypot(x, y) - rho, rho * np.arctan2(y, x)

    return ParametricSurface(smap, (tuple(u_range), (-half, half)), name=name, inverse=inverse)


def _identity_inverse(x, y):
    return np.asarray(x, float), np.asarray(y, float)


def ridge(
    height: float = 1.0,
    width: float = 1.0,
    *,
    bend_radius: float | None = None,
    half_span: float | None = None,
) -> ParametricSurface:
    """A ridge: Gaussian cross-section ``Z = h exp(-u^2 / (2 w^2))`` swept along a line/arc.

    Curvature across the crest ``h/w^2`` (convex), concave flanks of at most ``≈0.45 h/w^2``;
    along the crest ``k2 = 0`` (straight) or small (bent): ``-+-`` with ``ε`` inside.

    Args:
        height: ``h`` [m]; width: ``w`` [m].
        bend_radius: sweep along a circle of this radius [m] instead of a line.
        half_span: ``u`` runs over ``(-half_span, half_span)`` [m] (default ``5 w``).
    """
    return _gauss_profile(height, width, 1.0, bend_radius, half_span, "ridge")


def ravine(
    height: float = 1.0,
    width: float = 1.0,
    *,
    bend_radius: float | None = None,
    half_span: float | None = None,
) -> ParametricSurface:
    """A ravine: the ridge profile negated, ``Z = -h exp(-u^2 / (2 w^2))`` (``+-+``)."""
    return _gauss_profile(height, width, -1.0, bend_radius, half_span, "ravine")


def _gauss_profile(height, width, sign, bend_radius, half_span, name) -> ParametricSurface:
    h = checks.positive("height", height, "m")
    w = checks.positive("width", width, "m")
    span = 5 * w if half_span is None else checks.positive("half_span", half_span, "m")
    return swept_profile(
        lambda u: (u, sign * h * ca.exp(-(u**2) / (2 * w**2))),
        (-span, span),
        bend_radius=bend_radius,
        name=f"{name}(h={h:g}, w={w:g})",
        graph=True,
    )


def step(
    height: float = 1.0, width: float = 0.5, *, half_span: float | None = None
) -> ParametricSurface:
    """A smoothed step ``Z = h (1 + tanh(u / w)) / 2`` swept along ``y`` (``-+``, going up).

    Args:
        height: ``h`` [m] (negative heights are not allowed; walk the step the other way).
        width: transition width ``w`` [m]; the foot and edge curvatures are ``≈ ±0.77 h/w^2``.
        half_span: ``u`` runs over ``(-half_span, half_span)`` [m] (default ``6 w``).
    """
    h = checks.positive("height", height, "m")
    w = checks.positive("width", width, "m")
    span = 6 * w if half_span is None else checks.positive("half_span", half_span, "m")
    return swept_profile(
        lambda u: (u, h * (1 + ca.tanh(u / w)) / 2),
        (-span, span),
        name=f"step(h={h:g}, w={w:g})",
        graph=True,
    )


def cusp(
    slope: float = 1.0, rounding: float = 0.05, *, half_span: float = 1.0
) -> ParametricSurface:
    """A convex cusp (rounded roof edge): ``Z = -s (sqrt(u^2 + ρ^2) - ρ)`` along ``y``.

    A true cusp has infinite curvature; as the thesis does (§3.2.1) it is given a finite one:
    ``k = s/ρ`` at the crest, decaying over a few ``ρ``. One positive feature (``+``).

    Args:
        slope: ``s``, the flank slope far from the crest (dimensionless).
        rounding: ``ρ`` [m], the rounding length of the crest.
        half_span: ``u`` runs over ``(-half_span, half_span)`` [m].
    """
    s = checks.positive("slope", slope)
    rho = checks.positive("rounding", rounding, "m")
    span = checks.positive("half_span", half_span, "m")
    return swept_profile(
        lambda u: (u, -s * (ca.sqrt(u**2 + rho**2) - rho)),
        (-span, span),
        name=f"cusp(s={s:g}, rho={rho:g})",
        graph=True,
    )


def wire_on_plane(
    wire_radius: float, fillet_radius: float, *, half_span: float | None = None
) -> ParametricSurface:
    """A wire (cylinder of radius ``R``) lying along ``y`` on the plane ``z = 0``.

    The two concave corners where the wire meets the plane are filleted with radius ``ρ`` (a
    real wire has glue or a meniscus there; ``ρ → 0`` is the sharp union). The profile is
    parametrized by arc length ``u`` (0 at the crest): plane, concave fillet (``k = -1/ρ``),
    wire arc (``k = 1/R``), fillet, plane; curvature is piecewise constant (the surface is
    C1, not C2). Seen across the wire this is ``-+-``, a bump (or ridge with ``k2 = 0``).

    Args:
        wire_radius: ``R`` [m].
        fillet_radius: ``ρ`` [m].
        half_span: ``u`` runs over ``(-half_span, half_span)`` of arc length [m]
            (default: the wire and fillets plus ``3R`` of plane each side).
    """
    r = checks.positive("wire_radius", wire_radius, "m")
    rho = checks.positive("fillet_radius", fillet_radius, "m")
    xc = 2 * math.sqrt(r * rho)  # fillet centres at (±xc, ρ), tangent to plane and wire
    gamma0 = math.atan2(xc, rho - r)  # half-angle of the wire arc from its top
    theta_t = math.atan2(r - rho, xc)  # fillet angle at the wire tangency
    lw = r * gamma0  # half of the wire arc length
    lf = rho * (theta_t + math.pi / 2)  # fillet arc length
    span = lw + lf + 3 * r if half_span is None else checks.positive("half_span", half_span, "m")

    def profile(u):
        x_w, z_w = r * ca.sin(u / r), r + r * ca.cos(u / r)
        sigma = ca.fabs(u) - lw
        th = math.pi - theta_t + sigma / rho  # right fillet, counter-clockwise (concave)
        x_f, z_f = xc + rho * ca.cos(th), rho + rho * ca.sin(th)
        x_p, z_p = xc + (sigma - lf), 0 * u
        sgn = ca.sign(u)
        x_o = ca.if_else(sigma <= lf, x_f, x_p)
        z_o = ca.if_else(sigma <= lf, z_f, z_p)
        inside = ca.fabs(u) <= lw
        return ca.if_else(inside, x_w, sgn * x_o), ca.if_else(inside, z_w, z_o)

    return swept_profile(profile, (-span, span), name=f"wire_on_plane(R={r:g}, rho={rho:g})")


CATALOGUE = {
    "plane": plane,
    "sphere": sphere,
    "cylinder": cylinder,
    "bump": bump,
    "pit": pit,
    "ridge": ridge,
    "ravine": ravine,
    "step": step,
    "cusp": cusp,
    "wire_on_plane": wire_on_plane,
}

__all__ = [
    "CATALOGUE",
    "bump",
    "cusp",
    "cylinder",
    "pit",
    "plane",
    "ravine",
    "ridge",
    "sphere",
    "step",
    "swept_profile",
    "wire_on_plane",
]
