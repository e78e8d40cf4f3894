"""Closest point of a sphere centre on a contact surface: the exact contact geometry.

For a sphere of centre ``c`` and radius ``r`` touching a surface ``S`` on its outer side, the
contact point is the foot ``p`` of ``c`` on ``S`` (``c - p`` is normal to ``S``), the normal
``n`` the unit outward surface normal there, and the gap ``g = (c - p)·n - r`` (``< 0``:
penetration). ``c`` lies on the offset surface ``S + r n`` exactly when ``g = 0``.

* :class:`Plane`: closed form.
* :class:`Plate`, :class:`~planner.geometry.surfaces.HeightField` (graphs ``z = h(x, y)``):
  Newton on ``D(x, y) = ½|(x, y, h) - c|²`` with exact derivatives (closed-form profiles;
  the spline's derivatives), warm-started from the previous foot point and converged to
  a last step ``|Δ| <= 1e-13 m`` (quadratic convergence: the error after it is ~1e-26 m;
  2-3 iterations per step when sliding). A cold start, a warm one that does not converge
  (a sharp crest crossed), or one that ends on a local foot farther than the surface
  straight below the centre (a sphere sliding off a wire onto the plate) starts from the
  nearest sample of a grid under the sphere (:func:`graph_seed`).
* :class:`~planner.geometry.surfaces.ParametricSurface` (any catalogue surface): Newton on
  ``(u, v)`` with CasADi's exact gradient and Hessian of ``D``.

The Hessian is positive definite as long as the sphere is inside the focal distance of
concave regions (``r < 1/|k|`` of every concave principal curvature,
:meth:`planner.sim.spatial.plate.Plate.concave_radius`): the foot point is then unique and the
contact a single point. A sphere wider than a groove touches it at several points (both rims
of a ravine, a pit's rim, the foot and the edge of a step); the Newton above tracks one of
them. On a :class:`Plate`, :meth:`PlacedSurface.other_feet` finds the others
(:func:`planner.sim.spatial.kernel.plate_other_feet`: a sampled search under the sphere, then
Newton), the step solves all of them together and projects onto their common offset surface:
the 8 mm 3GM tip crossing feature_plate's 2 mm ravine rides the grey dilation of the profile
to 1e-17 m, where with one contact it sank 0.87 mm into the far rim
(``tests/test_sim_spatial_two_feet.py``). Two feet closer than the search's grid step are
seen as one (a sphere just beyond a flank's focal distance). Height fields and parametric
surfaces keep one contact per sphere and surface (a documented limit).
All queries work in the surface frame; :class:`PlacedSurface` maps to and from the WCS.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner.errors import InvalidParameter
from planner.sim.spatial.plate import Plane, Plate

__all__ = ["Foot", "PlacedSurface", "placed"]

_TOL = 1e-13  # [m] last Newton step (the error after it is ~1e-26 m)
_MAX_IT = 50
FOOT_SLACK = 1e-9  # [m] a warm foot this much farther than the surface below still counts


@dataclass(frozen=True)
class Foot:
    """Foot point of a sphere centre on a surface, in the WCS.

    Attributes:
        point: (3,) foot point ``p`` on the surface [m].
        normal: (3,) unit outward surface normal at ``p`` [-].
        distance: signed distance ``(c - p)·n`` of the centre [m].
        hint: parameters of ``p`` to warm-start the next query.
    """

    point: np.ndarray
    normal: np.ndarray
    distance: float
    hint: object


def _newton_graph(hd, c: np.ndarray, x: float, y: float):
    """Foot of ``c`` on the graph ``z = h(x, y)``; ``hd(x, y)`` gives h and derivatives.

    Newton on ``D = ½|(x, y, h) - c|²``; it stops after a step below ``1e-13 m`` (the next
    one would be ~1e-26 m: quadratic convergence) and updates ``h`` to first order over
    that last step instead of evaluating the surface once more. Returns ``(p, n, (x, y),
    converged)``."""
    cx, cy, cz = float(c[0]), float(c[1]), float(c[2])
    for _ in range(_MAX_IT):
        h, hx, hy, hxx, hxy, hyy = hd(x, y)
        e = h - cz
        gx = x - cx + e * hx
        gy = y - cy + e * hy
        a = 1.0 + hx * hx + e * hxx
        b = hx * hy + e * hxy
        d = 1.0 + hy * hy + e * hyy
        det = a * d - b * b
        if a <= 0.0 or det <= 1e-12 * (a * d + 1e-300):
            # not convex here (beyond a focal point): damped gradient step
            lam = abs(min(a, d)) + 1.0
            a, d = a + lam, d + lam
            det = a * d - b * b
        dx = (d * gx - b * gy) / det
        dy = (a * gy - b * gx) / det
        x -= dx
        y -= dy
        if abs(dx) + abs(dy) <= _TOL:
            h -= hx * dx + hy * dy
            converged = True
            break
    else:
        h, hx, hy, *_ = hd(x, y)
        converged = False
    nrm = math.sqrt(1.0 + hx * hx + hy * hy)
    n = np.array([-hx / nrm, -hy / nrm, 1.0 / nrm])
    p = np.array([x, y, h])
    return p, n, (x, y), converged


def graph_seed(height, c: np.ndarray, radius: float, k: int = 33) -> tuple[float, float]:
    """``(x, y)`` of the sample of ``z = height(x, y)`` nearest ``c`` on a ``k x k`` grid over
    the square of half-side ``radius`` [m] around ``(c_x, c_y)`` (the foot lies within
    ``radius = |c_z - h(c_x, c_y)|``): the start of a cold Newton, in the basin of the nearest
    foot (a start at ``(c_x, c_y)`` can land beyond a sharp crest and not converge)."""
    g = np.linspace(-radius, radius, k)
    X, Y = np.meshgrid(c[0] + g, c[1] + g)
    Z = np.asarray(height(X, Y), float)
    d2 = (X - c[0]) ** 2 + (Y - c[1]) ** 2 + (Z - c[2]) ** 2
    i = int(np.nanargmin(d2))
    return float(X.flat[i]), float(Y.flat[i])


def _graph_foot(hd, height, c: np.ndarray, hint):
    """Warm Newton from ``hint``; from :func:`graph_seed` on a cold start, when the warm one
    does not converge, or when it converges to a local foot farther from ``c`` than the
    surface straight below ``c`` (by more than :data:`FOOT_SLACK`), which cannot be the
    nearest: a fingertip sliding off a wire onto the plate kept its foot on the wire's
    flank and sank 7 mm into the plate (found 2026-11-25)."""
    if hint is not None:
        p, n, h, ok = _newton_graph(hd, c, *hint)
        if ok:
            below = float(c[2]) - hd(float(c[0]), float(c[1]))[0]
            if below >= 0.0 and float(np.sum((c - p) ** 2)) <= (below + FOOT_SLACK) ** 2:
                return p, n, h
    radius = max(abs(float(c[2]) - hd(float(c[0]), float(c[1]))[0]), 1e-6)
    x, y = graph_seed(height, c, radius)
    p, n, h, _ = _newton_graph(hd, c, x, y)
    return p, n, h


class _PlaneQuery:
    def __init__(self, plane: Plane) -> None:
        self.p0 = np.array(plane.point)
        self.n = np.array(plane.normal)

    def foot(self, c: np.ndarray, hint):
        dist = float((c - self.p0) @ self.n)
        return c - dist * self.n, self.n, None


class _PlateQuery:
    def __init__(self, plate: Plate) -> None:
        self.hd = plate.height_derivatives
        self.height = plate.height
        self.plate = plate
        self.packed = None  # (F, P, base) of the compiled kernels, packed on first use

    def foot(self, c: np.ndarray, hint):
        return _graph_foot(self.hd, self.height, c, hint)

    def _pack(self):
        if self.packed is None:
            from planner.sim.spatial.kernel import pack_plate

            self.packed = (*pack_plate(self.plate), float(self.plate.base))
        return self.packed

    def others(self, c: np.ndarray, radius: float, reach: float, primary) -> list:
        """Rows ``(x, y, h, n_x, n_y, n_z, distance)`` of the other feet within ``reach``
        (:func:`planner.sim.spatial.kernel.plate_other_feet`)."""
        from planner.sim.spatial.kernel import MAX_OTHER_FEET, plate_other_feet

        F, P, base = self._pack()
        out = np.empty((MAX_OTHER_FEET, 7))
        cx, cy, cz = (float(v) for v in c)
        n = plate_other_feet(F, P, base, cx, cy, cz, radius, reach, *primary, out)
        return list(out[:n])

    def local(self, c: np.ndarray, hint):
        """The foot Newton reaches from ``hint`` alone (no global restart): a second contact
        stays on its own rim while the sphere is projected."""
        from planner.sim.spatial.kernel import plate_foot

        F, P, base = self._pack()
        x, y, h, nx, ny, nz, _, _ = plate_foot(F, P, base, *(float(v) for v in c), *hint)
        return np.array([x, y, h]), np.array([nx, ny, nz]), (x, y)


class _HeightFieldQuery:
    def __init__(self, field) -> None:
        self.field = field
        ev = field.spline.ev

        def hd(x, y):
            return tuple(
                float(ev(x, y, dx=i, dy=j))
                for i, j in ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2))
            )

        self.hd = hd

    def foot(self, c: np.ndarray, hint):
        p, n, h = _graph_foot(self.hd, self.field.height, c, hint)
        if not bool(self.field.contains(h[0], h[1])):
            return p, n, None  # outside the sampled rectangle: flagged by the caller
        return p, n, h


class _ParametricQuery:
    def __init__(self, surface) -> None:
        import casadi as ca

        u, v = ca.SX.sym("u"), ca.SX.sym("v")
        c = ca.SX.sym("c", 3)
        sym = surface.symbolic(u, v)
        f, z = sym["point"], sym["z"]
        D = 0.5 * ca.sumsqr(f - c)
        uv = ca.vertcat(u, v)
        g, H = ca.gradient(D, uv), ca.hessian(D, uv)[0]
        self.fn = ca.Function("foot", [u, v, c], [g, H, f, z])
        self.surface = surface
        self.inverse = surface.inverse
        dom = surface.domain
        self.lo, self.hi = dom[:, 0], dom[:, 1]

    def _start(self, c: np.ndarray) -> tuple[float, float]:
        if self.inverse is not None:
            u, v = self.inverse(np.array([c[0]]), np.array([c[1]]))
            return float(np.ravel(u)[0]), float(np.ravel(v)[0])
        lo = np.where(np.isfinite(self.lo), self.lo, -1.0)
        hi = np.where(np.isfinite(self.hi), self.hi, 1.0)
        uu, vv = np.meshgrid(np.linspace(lo[0], hi[0], 41), np.linspace(lo[1], hi[1], 41))
        pts = self.surface.point(uu.ravel(), vv.ravel())
        k = int(np.argmin(np.sum((pts - c) ** 2, axis=1)))
        return float(uu.ravel()[k]), float(vv.ravel()[k])

    def foot(self, c: np.ndarray, hint):
        u, v = hint if hint is not None else self._start(c)
        for _ in range(_MAX_IT):
            g, H, _, _ = self.fn(u, v, c)
            g, H = np.asarray(g, float).ravel(), np.asarray(H, float)
            if np.linalg.eigvalsh(H)[0] <= 1e-12 * np.trace(H):
                H = H + (abs(np.linalg.eigvalsh(H)[0]) + 1e-9 * np.trace(H) + 1e-12) * np.eye(2)
            du, dv = np.linalg.solve(H, g)
            u, v = u - du, v - dv
            if abs(du) + abs(dv) <= _TOL:
                break
        _, _, f, z = self.fn(u, v, c)
        return np.asarray(f, float).ravel(), np.asarray(z, float).ravel(), (u, v)


class PlacedSurface:
    """A contact surface placed in the WCS by ``T_WS`` (surface frame -> WCS).

    Args:
        surface: a :class:`Plane`, :class:`Plate`, ``HeightField`` or ``ParametricSurface``.
        pose: 4x4 homogeneous transform ``T_WS`` [m], or None (identity).
    """

    def __init__(self, surface, pose=None) -> None:
        from planner.geometry.surfaces import HeightField, ParametricSurface

        if isinstance(surface, Plane):
            self.query = _PlaneQuery(surface)
        elif isinstance(surface, Plate):
            self.query = _PlateQuery(surface)
        elif isinstance(surface, HeightField):
            self.query = _HeightFieldQuery(surface)
        elif isinstance(surface, ParametricSurface):
            self.query = _ParametricQuery(surface)
        else:
            raise InvalidParameter(
                f"surface: expected a Plane, Plate, HeightField or ParametricSurface, "
                f"got {type(surface).__name__}"
            )
        self.surface = surface
        T = np.eye(4) if pose is None else np.asarray(pose, float)
        if T.shape != (4, 4) or not np.all(np.isfinite(T)):
            raise InvalidParameter(f"pose: expected a 4x4 homogeneous transform, got {T!r}")
        R = T[:3, :3]
        if np.max(np.abs(R.T @ R - np.eye(3))) > 1e-9 or np.linalg.det(R) < 0:
            raise InvalidParameter("pose: its 3x3 block must be a rotation matrix")
        self.R, self.t = R.copy(), T[:3, 3].copy()
        self.identity = bool(np.allclose(T, np.eye(4), atol=0.0))

    def foot(self, center: np.ndarray, hint=None) -> Foot | None:
        """Foot of ``center`` (3,) [m, WCS]; None when it falls outside a bounded surface."""
        c = center if self.identity else self.R.T @ (center - self.t)
        p, n, h = self.query.foot(c, hint)
        if h is None and not isinstance(self.query, _PlaneQuery):
            return None
        return self._to_wcs(c, p, n, h)

    def _to_wcs(self, c: np.ndarray, p: np.ndarray, n: np.ndarray, hint) -> Foot:
        """The :class:`Foot` of the surface-frame centre ``c``, point ``p`` and normal ``n``."""
        dist = float((c - p) @ n)
        if not self.identity:
            p, n = self.R @ p + self.t, self.R @ n
        return Foot(p, n, dist, hint)

    def other_feet(self, center: np.ndarray, radius: float, reach: float, primary: Foot):
        """The sphere's other contact points: feet of ``center`` (3,) [m, WCS] besides
        ``primary`` whose gap to the sphere of ``radius`` [m] is at most ``reach`` [m] (a
        sphere wider than a groove touches both rims). Plates only
        (:func:`planner.sim.spatial.kernel.plate_other_feet`); other surfaces: none (one
        contact per sphere, the documented limit of the module)."""
        if not isinstance(self.query, _PlateQuery):
            return []
        c = center if self.identity else self.R.T @ (center - self.t)
        rows = self.query.others(c, radius, reach, primary.hint)
        return [self._to_wcs(c, r[:3], r[3:6], (float(r[0]), float(r[1]))) for r in rows]

    def local_foot(self, center: np.ndarray, hint) -> Foot:
        """Foot of ``center`` by Newton from ``hint`` only (a foot of :meth:`other_feet`)."""
        c = center if self.identity else self.R.T @ (center - self.t)
        p, n, h = self.query.local(c, hint)
        return self._to_wcs(c, p, n, h)


def placed(surface, pose=None) -> PlacedSurface:
    """:class:`PlacedSurface` of ``surface`` at ``pose`` (see there)."""
    return PlacedSurface(surface, pose)
