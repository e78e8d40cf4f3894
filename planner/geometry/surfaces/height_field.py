"""Height-field surfaces ``z = h(x, y)`` from sampled data (thesis §3.2.1 on sensor data).

:class:`HeightField` interpolates a regular grid of heights with a smoothing bicubic spline
(``scipy.interpolate.RectBivariateSpline``) and offers the same evaluation methods as
:class:`~planner.geometry.surfaces.ParametricSurface`, with ``(u, v) = (x, y)``: the Monge
patch ``f(x, y) = (x, y, h(x, y))``, outward normal up. Its coordinates are *not orthogonal*
where ``h_x h_y != 0``; ``K``, ``T``, ``M`` are the frame-based forms described in
:mod:`planner.geometry.surfaces.parametric` (equal to eqs. A.2-A.4 where orthogonal).

:func:`grid_principal_curvatures` computes principal curvatures on the grid itself by
second-order finite differences: the fast path for million-point maps.
"""

from __future__ import annotations

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from planner.geometry.surfaces.forms import SurfaceGeometry, principal_from_k


def _check_grid(x, y, z) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    z = np.asarray(z, dtype=float)
    if x.ndim != 1 or y.ndim != 1 or x.size < 4 or y.size < 4:
        raise InvalidParameter(
            f"x and y must be 1-D with at least 4 samples each, got shapes {x.shape} and {y.shape}"
        )
    if z.shape != (x.size, y.size):
        raise InvalidParameter(
            f"z must have shape (len(x), len(y)) = {(x.size, y.size)} "
            f"(z[i, j] = h(x[i], y[j])), got {z.shape}"
        )
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y)) and np.all(np.isfinite(z))):
        raise InvalidParameter("x, y and z must be finite (no NaN or inf)")
    if np.any(np.diff(x) <= 0) or np.any(np.diff(y) <= 0):
        raise InvalidParameter("x and y must be strictly increasing")
    return x, y, z


def monge_forms(hx, hy, hxx, hxy, hyy) -> SurfaceGeometry:
    """Gauss frame, ``K``, ``T``, ``M`` of a Monge patch from the height derivatives.

    Args:
        hx, hy: (...) first derivatives of ``h`` [m/m]; hxx, hxy, hyy: (...) second [1/m].

    Returns:
        A :class:`SurfaceGeometry` whose ``point`` has ``z = 0`` placeholders (the caller
        fills it); frames (..., 3, 3), ``K`` (..., 2, 2), ``T`` (..., 1, 2), ``M`` (..., 2, 2).
    """
    hx, hy, hxx, hxy, hyy = np.broadcast_arrays(
        *(np.asarray(a, float) for a in (hx, hy, hxx, hxy, hyy))
    )
    zero, one = np.zeros_like(hx), np.ones_like(hx)
    fu = np.stack([one, zero, hx], -1)
    fv = np.stack([zero, one, hy], -1)
    nfu = np.sqrt(1 + hx**2)
    w = np.sqrt(1 + hx**2 + hy**2)
    x = fu / nfu[..., None]
    z = np.stack([-hx, -hy, one], -1) / w[..., None]
    y = np.cross(z, x)
    e = np.stack([x, y], -1)  # (..., 3, 2)
    jac = np.stack([fu, fv], -1)
    m = np.swapaxes(e, -1, -2) @ jac
    minv = np.linalg.inv(m)

    def dnormal(nd):  # derivative of z = n/|n| given the derivative nd of n = (-hx, -hy, 1)
        return (nd - z * np.sum(z * nd, -1, keepdims=True)) / w[..., None]

    zu = dnormal(np.stack([-hxx, -hxy, zero], -1))
    zv = dnormal(np.stack([-hxy, -hyy, zero], -1))
    fuu = np.stack([zero, zero, hxx], -1)
    fuv = np.stack([zero, zero, hxy], -1)
    xu = (fuu - x * np.sum(x * fuu, -1, keepdims=True)) / nfu[..., None]
    xv = (fuv - x * np.sum(x * fuv, -1, keepdims=True)) / nfu[..., None]
    k = np.swapaxes(e, -1, -2) @ np.stack([zu, zv], -1) @ minv
    t = y[..., None, :] @ np.stack([xu, xv], -1) @ minv
    return SurfaceGeometry(np.zeros(hx.shape + (3,)), np.stack([x, y, z], -1), k, t, m)


def monge_principal_curvatures(hx, hy, hxx, hxy, hyy) -> tuple[np.ndarray, np.ndarray]:
    """Principal curvatures of ``z = h(x, y)``, upward normal, convex positive (§3.2.1).

    From the fundamental forms ``E = 1 + hx^2, F = hx hy, G = 1 + hy^2`` and
    ``(L, M, N) = -(hxx, hxy, hyy)/W``, ``W = sqrt(1 + hx^2 + hy^2)``: mean curvature
    ``H = (EN - 2FM + GL) / (2(EG - F^2))``, Gaussian ``K = (LN - M^2)/(EG - F^2)``,
    ``k = H ± sqrt(H^2 - K)``.

    Returns:
        ``(k1, k2)`` (...) [1/m] with ``|k1| >= |k2|``.
    """
    w2 = 1 + hx**2 + hy**2
    w = np.sqrt(w2)
    big_l, big_m, big_n = -hxx / w, -hxy / w, -hyy / w
    e, f, g = 1 + hx**2, hx * hy, 1 + hy**2
    mean = (e * big_n - 2 * f * big_m + g * big_l) / (2 * w2)
    gauss = (big_l * big_n - big_m**2) / w2
    disc = np.sqrt(np.maximum(mean**2 - gauss, 0.0))
    k1 = mean + np.copysign(disc, mean)
    return k1, 2 * mean - k1


def grid_principal_curvatures(x, y, z) -> tuple[np.ndarray, np.ndarray]:
    """Principal curvatures on a height grid by central finite differences.

    Args:
        x: (nx,) increasing [m]; y: (ny,) increasing [m].
        z: (nx, ny) heights, ``z[i, j] = h(x[i], y[j])`` [m].

    Returns:
        ``(k1, k2)``: (nx, ny) each [1/m], ``|k1| >= |k2|`` (second-order accurate inside,
        first-order on the border rows).
    """
    x, y, z = _check_grid(x, y, z)
    hx, hy = np.gradient(z, x, y)
    hxx, hxy = np.gradient(hx, x, y)
    hyy = np.gradient(hy, y, axis=1)
    return monge_principal_curvatures(hx, hy, hxx, hxy, hyy)


class HeightField:
    """A surface ``z = h(x, y)`` interpolated from a regular grid (smoothing bicubic spline).

    Args:
        x: (nx,) strictly increasing sample abscissae [m].
        y: (ny,) strictly increasing sample ordinates [m].
        z: (nx, ny) heights, ``z[i, j] = h(x[i], y[j])`` [m].
        smoothing: spline smoothing factor ``s`` of ``RectBivariateSpline`` (0 interpolates;
            for noisy sensor data about ``n_points * sigma^2``) [m^2].
        name: label.
    """

    def __init__(self, x, y, z, *, smoothing: float = 0.0, name: str = "height_field"):
        from scipy.interpolate import RectBivariateSpline

        self.x, self.y, self.z = _check_grid(x, y, z)
        smoothing = checks.nonnegative("smoothing", smoothing, "m^2")
        self.spline = RectBivariateSpline(self.x, self.y, self.z, kx=3, ky=3, s=smoothing)
        self.domain = np.array([[self.x[0], self.x[-1]], [self.y[0], self.y[-1]]])
        self.name = name

    @staticmethod
    def inverse(x, y) -> tuple[np.ndarray, np.ndarray]:
        """``(x, y) -> (u, v)``: the identity (a height field is parametrized by x, y)."""
        return np.asarray(x, float), np.asarray(y, float)

    def _derivs(self, u, v):
        try:
            uu, vv = np.broadcast_arrays(np.asarray(u, float), np.asarray(v, float))
        except ValueError:
            raise InvalidParameter(
                f"u and v must broadcast together, got {np.shape(u)} and {np.shape(v)}"
            ) from None
        if not (np.all(np.isfinite(uu)) and np.all(np.isfinite(vv))):
            raise InvalidParameter("u and v must be finite (no NaN or inf)")
        ev = self.spline.ev
        return (
            uu,
            vv,
            [ev(uu, vv, dx=a, dy=b) for a, b in ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2))],
        )

    def height(self, u, v) -> np.ndarray:
        """Interpolated heights ``h(x, y)``: (...) [m]."""
        return self.spline.ev(*np.broadcast_arrays(np.asarray(u, float), np.asarray(v, float)))

    def evaluate(self, u, v) -> SurfaceGeometry:
        """Point, Gauss frame, ``K``, ``T``, ``M`` at ``(x, y) = (u, v)`` (see the module doc)."""
        uu, vv, (h, hx, hy, hxx, hxy, hyy) = self._derivs(u, v)
        g = monge_forms(hx, hy, hxx, hxy, hyy)
        return SurfaceGeometry(
            np.stack([uu, vv, h], -1), g.gauss_frame, g.curvature_matrix, g.torsion, g.metric
        )

    local_geometry = evaluate

    def point(self, u, v) -> np.ndarray:
        """Surface points ``(x, y, h)``: (..., 3) [m]."""
        uu, vv = np.broadcast_arrays(np.asarray(u, float), np.asarray(v, float))
        return np.stack([uu, vv, self.height(uu, vv)], -1)

    def gauss_frame(self, u, v) -> np.ndarray:
        """Gauss frame, columns ``x, y, z``: (..., 3, 3)."""
        return self.evaluate(u, v).gauss_frame

    def normal(self, u, v) -> np.ndarray:
        """Unit upward normal: (..., 3)."""
        return self.evaluate(u, v).gauss_frame[..., :, 2]

    def curvature_matrix(self, u, v) -> np.ndarray:
        """Curvature form ``K``: (..., 2, 2) [1/m]."""
        return self.evaluate(u, v).curvature_matrix

    def torsion(self, u, v) -> np.ndarray:
        """Torsion form ``T``: (..., 1, 2) [1/m]."""
        return self.evaluate(u, v).torsion

    def metric(self, u, v) -> np.ndarray:
        """Metric ``M``: (..., 2, 2)."""
        return self.evaluate(u, v).metric

    def principal_curvatures(self, u, v) -> tuple[np.ndarray, np.ndarray]:
        """Principal curvatures ``(k1, k2)``, ``|k1| >= |k2|``: each (...) [1/m]."""
        _, _, (_, hx, hy, hxx, hxy, hyy) = self._derivs(u, v)
        return monge_principal_curvatures(hx, hy, hxx, hxy, hyy)

    def principal_directions(self, u, v) -> tuple[np.ndarray, np.ndarray]:
        """Unit principal directions ``(p1, p2)`` in world coordinates: each (..., 3)."""
        g = self.evaluate(u, v)
        _, _, p1, p2 = principal_from_k(g.curvature_matrix)
        e = g.gauss_frame[..., :, :2]
        return np.einsum("...ij,...j->...i", e, p1), np.einsum("...ij,...j->...i", e, p2)

    def contains(self, u, v) -> np.ndarray:
        """Whether ``(x, y)`` lies strictly inside the sampled rectangle: bool (...)."""
        (u0, u1), (v0, v1) = self.domain
        u, v = np.asarray(u, float), np.asarray(v, float)
        return (u > u0) & (u < u1) & (v > v0) & (v < v1)

    def __repr__(self) -> str:
        return f"HeightField({self.name!r}, {self.z.shape[0]}x{self.z.shape[1]})"


__all__ = ["HeightField", "grid_principal_curvatures", "monge_forms", "monge_principal_curvatures"]
