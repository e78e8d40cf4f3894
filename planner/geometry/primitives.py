"""Exact planar curve pieces: line segments, circular arcs and smooth parametric pieces.

A piece is traversed from its start to its end. With the hapex convention the **outward
normal is the left normal of the direction of travel**, n = (-t_y, t_x), and the signed
curvature is measured along that normal with convex (bulging outward) positive (thesis eq.
3.17 convention). For the standard signed curvature κ = x'y'' - y'x'' (positive when the path
turns left) this is ``k = -κ``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np


def left_normal(t: np.ndarray) -> np.ndarray:
    """Left normals (-t_y, t_x) of tangents ``t`` (..., 2)."""
    return np.stack([-t[..., 1], t[..., 0]], axis=-1)


@dataclass(frozen=True)
class Line:
    """Straight segment from ``p0`` to ``p1`` [m]."""

    p0: tuple[float, float]
    p1: tuple[float, float]

    @property
    def length(self) -> float:
        return float(np.hypot(self.p1[0] - self.p0[0], self.p1[1] - self.p0[1]))

    def evaluate(self, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Points, unit tangents and outward curvature at arclengths ``sigma`` from the start."""
        p0, p1 = np.asarray(self.p0, float), np.asarray(self.p1, float)
        t = (p1 - p0) / max(self.length, 1e-300)
        pts = p0 + sigma[:, None] * t
        return pts, np.broadcast_to(t, pts.shape).copy(), np.zeros(len(sigma))

    def transformed(self, R: np.ndarray, d: np.ndarray) -> Line:
        return Line(tuple(R @ self.p0 + d), tuple(R @ self.p1 + d))


@dataclass(frozen=True)
class Arc:
    """Circular arc about ``center`` of ``radius`` [m], from polar angle ``phi0`` swept by
    ``sweep`` [rad] (positive counter-clockwise).

    A clockwise arc (sweep < 0) has the material inside the circle: convex, k = +1/radius;
    a counter-clockwise one is concave, k = -1/radius.
    """

    center: tuple[float, float]
    radius: float
    phi0: float
    sweep: float

    @property
    def length(self) -> float:
        return abs(self.sweep) * self.radius

    def evaluate(self, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        sgn = 1.0 if self.sweep > 0 else -1.0
        phi = self.phi0 + sgn * sigma / self.radius
        c = np.asarray(self.center, float)
        pts = c + self.radius * np.stack([np.cos(phi), np.sin(phi)], axis=-1)
        tan = sgn * np.stack([-np.sin(phi), np.cos(phi)], axis=-1)
        return pts, tan, np.full(len(sigma), -sgn / self.radius)

    def transformed(self, R: np.ndarray, d: np.ndarray) -> Arc:
        rot = float(np.arctan2(R[1, 0], R[0, 0]))
        return Arc(tuple(R @ self.center + d), self.radius, self.phi0 + rot, self.sweep)


@dataclass(frozen=True)
class Parametric:
    """A smooth piece c(u), u in [u0, u1], given with its first and second derivatives.

    Attributes:
        f, df, ddf: callables mapping (n,) parameters to (n, 2) point / derivative arrays.
        u0, u1: parameter range (u1 > u0 or u1 < u0; traversal from u0 to u1).
        table: number of samples of the arclength table used to invert s(u).
    """

    f: Callable[[np.ndarray], np.ndarray]
    df: Callable[[np.ndarray], np.ndarray]
    ddf: Callable[[np.ndarray], np.ndarray]
    u0: float
    u1: float
    table: int = 4097

    def _lengths(self) -> tuple[np.ndarray, np.ndarray]:
        u = np.linspace(self.u0, self.u1, self.table)
        speed = np.linalg.norm(self.df(u), axis=1)
        # Simpson-like accuracy from the trapezoid on a fine table
        ds = 0.5 * (speed[1:] + speed[:-1]) * np.abs(np.diff(u))
        return u, np.concatenate([[0.0], np.cumsum(ds)])

    @property
    def length(self) -> float:
        return float(self._lengths()[1][-1])

    def evaluate(self, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        u_tab, s_tab = self._lengths()
        u = np.interp(sigma, s_tab, u_tab)
        d1 = self.df(u) * np.sign(self.u1 - self.u0)
        d2 = self.ddf(u)
        speed = np.linalg.norm(d1, axis=1)
        tan = d1 / speed[:, None]
        kappa = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / speed**3
        return self.f(u), tan, -kappa

    def transformed(self, R: np.ndarray, d: np.ndarray) -> Parametric:
        f, df, ddf = self.f, self.df, self.ddf
        return Parametric(
            lambda u: f(u) @ R.T + d,
            lambda u: df(u) @ R.T,
            lambda u: ddf(u) @ R.T,
            self.u0,
            self.u1,
            self.table,
        )


Piece = Line | Arc | Parametric


def turn_angle(t_in: np.ndarray, t_out: np.ndarray) -> float:
    """Signed angle [rad] from tangent ``t_in`` to ``t_out``, in (-pi, pi]; positive = left."""
    return float(
        np.arctan2(t_in[0] * t_out[1] - t_in[1] * t_out[0], t_in[0] * t_out[0] + t_in[1] * t_out[1])
    )


def joint_turn(prev: Piece, nxt: Piece) -> float:
    """Signed turning angle at the joint of two pieces [rad] (positive = left = concave).

    An exact reversal (±pi) is resolved by looking slightly inside the pieces, so that e.g. a
    wire touching a plane gives a concave (+pi) cusp.
    """
    _, t_in, _ = prev.evaluate(np.array([prev.length]))
    _, t_out, _ = nxt.evaluate(np.array([0.0]))
    a = turn_angle(t_in[0], t_out[0])
    if abs(abs(a) - np.pi) < 1e-9:
        eps = 1e-6 * min(prev.length, nxt.length)
        _, ti, _ = prev.evaluate(np.array([prev.length - eps]))
        _, to, _ = nxt.evaluate(np.array([eps]))
        b = turn_angle(ti[0], to[0])
        a = np.pi if b >= 0 else -np.pi
    return a


__all__ = ["Arc", "Line", "Parametric", "Piece", "joint_turn", "left_normal", "turn_angle"]
