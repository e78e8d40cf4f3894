"""Parametric surfaces with Montana's Gauss frame and forms (thesis App. A.1, §3.2.1).

A :class:`ParametricSurface` is defined once by a CasADi expression ``f(u, v) -> R^3`` on a
box domain ``U`` and an outward orientation. Its tangents, normalized Gauss frame (eq. A.1),
curvature form ``K`` (A.2), torsion form ``T`` (A.3), metric ``M`` (A.4) and principal
curvatures (§3.2.1, eqs. 3.4-3.8) are generated symbolically by CasADi (no finite
differences) and evaluated over arrays by numpy code translated from the CasADi graph.

Conventions (thesis App. A, Montana 1988):

* ``x = f_u / |f_u|``, ``z`` the unit outward normal, ``y = z × x`` (right-handed frame).
  For an *orthogonal* coordinate system (``f_u · f_v = 0``) ``y = ± f_v / |f_v|`` and
  everything below reduces to eqs. A.1-A.4 exactly.
* ``M = [x y]^T [f_u f_v]`` maps parameter rates to velocities in the frame:
  ``[x y]^T ḟ = M u̇``. Orthogonal coordinates give ``M = diag(|f_u|, ±|f_v|)`` (A.4); the
  sign is ``-`` only where ``f_u × f_v`` points inward (e.g. the bump of eq. 3.13 at
  ``u < 0``, whose thesis frame eq. 3.14 keeps ``y = (-sin v, cos v, 0)``).
* ``K = [x y]^T [z_u z_v] M^{-1}`` and ``T = y^T [x_u x_v] M^{-1}``: the derivatives of the
  frame along the unit frame directions. With orthogonal coordinates these are eqs. A.2 and
  A.3 (``M^{-1} = diag(1/|f_u|, 1/|f_v|)``). **Montana's K, T, M assume orthogonal
  coordinates**; for a non-orthogonal parametrization (a height field, say) this module still
  returns the frame-based forms above, which are what the contact equations (A.12) need, and
  :meth:`ParametricSurface.orthogonality` reports how far the coordinates are from orthogonal.
* Curvature sign: convex positive with the outward normal (sphere: ``K = I/R``, eq. A.10).
  ``K`` is symmetric; its eigenvalues are the principal curvatures ``k1, k2`` ordered
  ``|k1| >= |k2|`` and its eigenvectors the principal directions (eqs. 3.5-3.8).
  :meth:`ParametricSurface.principal_curvatures` evaluates the same values from the first and
  second fundamental forms (``k = H ± sqrt(H^2 - K_G)``, the root taken from the Weingarten
  map so that umbilics stay exact), a graph half the size of ``K``'s.

Removable coordinate singularities (the bump's apex ``u = 0``, where ``f_v = 0``) are
evaluated as the mean of the one-sided values at ``u ± δ``; a point where these disagree (a
true singularity such as the sphere's pole for ``T``) raises :class:`SingularConfiguration`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from functools import cached_property

import casadi as ca
import numpy as np

from planner import checks
from planner.errors import InvalidParameter, SingularConfiguration
from planner.geometry.surfaces.forms import SurfaceGeometry, principal_from_k
from planner.geometry.surfaces.sx2numpy import numpy_function, scalar_function

SurfaceMap = Callable[[ca.SX, ca.SX], Sequence]
_CHUNK = 1 << 15
# name -> (trailing shape of the value, column-major reshaping of the CasADi non-zeros)
_SHAPES = {
    "point": (3,),
    "f_u": (3,),
    "f_v": (3,),
    "gauss_frame": (3, 3),
    "curvature_matrix": (2, 2),
    "torsion": (1, 2),
    "metric": (2, 2),
    "principal_curvatures": (2,),
}


class ParametricSurface:
    """A surface patch ``f: U -> R^3`` with Montana's frame and forms (App. A.1).

    Args:
        surface_map: ``surface_map(u, v)`` returns the three coordinates of ``f(u, v)`` [m] as
            CasADi SX expressions of the SX scalars ``u`` and ``v``.
        domain: ``((u_min, u_max), (v_min, v_max))``, the open box ``U``.
        orientation: ``+1`` when ``f_u × f_v`` is the outward normal, ``-1`` when it is the
            inward one, or a callable ``(u, v) -> SX`` giving that sign pointwise (e.g. the
            bump of eq. 3.13, whose ``f_u × f_v`` flips at ``u = 0``).
        name: a label used in messages and plots.
        inverse: for a surface that is a graph ``z = h(x, y)``, a numpy function
            ``(x, y) -> (u, v)`` giving the parameters of the point above ``(x, y)``; lets
            maps be evaluated exactly on an ``(x, y)`` raster (optional).

    Evaluation methods take scalars or arrays ``u, v`` (broadcast together) and return arrays
    whose leading shape is the broadcast shape, e.g. ``gauss_frame(u, v)`` is ``(3, 3)`` for
    scalars and ``(N, 3, 3)`` for ``(N,)`` arrays. Points outside ``U`` are evaluated by the
    same formula (see :meth:`contains`); integrators check the domain.
    """

    def __init__(
        self,
        surface_map: SurfaceMap,
        domain: Sequence[Sequence[float]],
        *,
        orientation: int | Callable[[ca.SX, ca.SX], ca.SX] = 1,
        name: str = "surface",
        inverse: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]] | None = None,
    ):
        try:
            dom = np.asarray(domain, dtype=float)
        except (TypeError, ValueError):
            raise InvalidParameter(
                f"domain must be ((u_min, u_max), (v_min, v_max)), got {checks.shown(domain)}"
            ) from None
        if dom.shape != (2, 2) or np.any(np.isnan(dom)) or np.any(dom[:, 0] >= dom[:, 1]):
            raise InvalidParameter(
                "domain must be ((u_min, u_max), (v_min, v_max)) with min < max, "
                f"got {checks.shown(domain)}"
            )
        if not callable(orientation) and orientation not in (1, -1):
            raise InvalidParameter(
                f"orientation must be +1, -1 or a callable, got {checks.shown(orientation)}"
            )
        self.surface_map = surface_map
        self.domain = dom
        self.orientation = orientation
        self.name = name
        self.inverse = inverse
        self._np: dict[str, Callable] = {}

    # ----------------------------------------------------------------- symbolic layer
    def symbolic(self, u: ca.SX, v: ca.SX) -> dict[str, ca.SX]:
        """CasADi expressions of every quantity at symbolic ``(u, v)``.

        Returns:
            dict with ``point`` (3x1), ``f_u``, ``f_v`` (3x1), ``x, y, z`` (3x1),
            ``gauss_frame`` (3x3), ``metric`` (2x2, A.4), ``curvature_matrix`` (2x2, A.2),
            ``torsion`` (1x2, A.3).
        """
        f = ca.vertcat(
            *[ca.SX(c) if not isinstance(c, ca.SX) else c for c in self.surface_map(u, v)]
        )
        if f.shape != (3, 1):
            raise InvalidParameter(f"surface_map must return 3 coordinates, got shape {f.shape}")
        uv = ca.vertcat(u, v)
        jac = ca.jacobian(f, uv)
        fu, fv = jac[:, 0], jac[:, 1]
        sign = self.orientation(u, v) if callable(self.orientation) else self.orientation
        n = sign * ca.cross(fu, fv)
        z = n / ca.norm_2(n)
        x = fu / ca.norm_2(fu)
        y = ca.cross(z, x)
        frame2 = ca.horzcat(x, y)
        metric = frame2.T @ jac
        minv = ca.inv(metric)
        kmat = frame2.T @ ca.jacobian(z, uv) @ minv
        tors = y.T @ ca.jacobian(x, uv) @ minv
        # principal curvatures from the fundamental forms (valid for any parametrization):
        # I = [[E, F], [F, G]], II = [[L, M], [M, N]] with the convex-positive sign
        hess_u = ca.jacobian(fu, uv)
        fvv = ca.jacobian(fv, v)
        nn = ca.norm_2(n)
        e_, f_, g_ = ca.dot(fu, fu), ca.dot(fu, fv), ca.dot(fv, fv)
        l_, m_ = -ca.dot(hess_u[:, 0], n) / nn, -ca.dot(hess_u[:, 1], n) / nn
        n_ = -ca.dot(fvv, n) / nn
        det = e_ * g_ - f_**2
        mean = (e_ * n_ - 2 * f_ * m_ + g_ * l_) / (2 * det)
        # sqrt(H^2 - K_G) from the Weingarten map W = I^-1 II without the cancellation of
        # H^2 - K_G at umbilics: ((W11 - W22)/2)^2 + W12 W21
        half_diff = (g_ * l_ - e_ * n_) / (2 * det)
        cross = (g_ * m_ - f_ * n_) * (e_ * m_ - f_ * l_) / det**2
        disc = ca.sqrt(ca.fmax(half_diff**2 + cross, 0))
        k1 = ca.if_else(mean >= 0, mean + disc, mean - disc)
        return {
            "point": f,
            "f_u": fu,
            "f_v": fv,
            "x": x,
            "y": y,
            "z": z,
            "gauss_frame": ca.horzcat(x, y, z),
            "metric": metric,
            "curvature_matrix": kmat,
            "torsion": tors,
            "principal_curvatures": ca.vertcat(k1, 2 * mean - k1),
        }

    @cached_property
    def functions(self) -> dict[str, ca.Function]:
        """CasADi ``Function``s ``(u, v) -> value`` for ``point``, ``f_u``, ``f_v``,
        ``gauss_frame`` (A.1), ``curvature_matrix`` (A.2), ``torsion`` (A.3), ``metric`` (A.4),
        ``principal_curvatures`` (2x1, ``|k1| >= |k2|``) and ``all`` (point, frame, K, T, M),
        for use in optimization problems."""
        u, v = ca.SX.sym("u"), ca.SX.sym("v")
        s = {k: ca.densify(e) for k, e in self.symbolic(u, v).items()}
        out = {k: ca.Function(k, [u, v], [s[k]], ["u", "v"], [k]) for k in _SHAPES}
        names = ["point", "gauss_frame", "curvature_matrix", "torsion", "metric"]
        out["all"] = ca.Function("all", [u, v], [s[k] for k in names], ["u", "v"], names)
        return out

    # ----------------------------------------------------------------- numeric layer
    def _compiled(self, key: str) -> Callable:
        if key not in self._np:
            self._np[key] = numpy_function(self.functions[key])
        return self._np[key]

    def _eval(self, key: str, u, v) -> list[np.ndarray]:
        """Evaluate CasADi function ``key`` over broadcast arrays; list of (..., *shape)."""
        try:
            uu, vv = np.broadcast_arrays(np.asarray(u, dtype=float), np.asarray(v, dtype=float))
        except (TypeError, ValueError):
            raise InvalidParameter(
                f"u and v must be numbers or arrays that broadcast together,"
                f" got {np.shape(u)} and {np.shape(v)}"
            ) from None
        if not (np.all(np.isfinite(uu)) and np.all(np.isfinite(vv))):
            raise InvalidParameter("u and v must be finite (no NaN or inf)")
        shape = uu.shape
        uf, vf = uu.ravel(), vv.ravel()
        fn = self._compiled(key)
        fun = self.functions[key]
        outs = [np.empty((uf.size, fun.nnz_out(j))) for j in range(fun.n_out())]
        with np.errstate(all="ignore"):
            for i in range(0, max(uf.size, 1), _CHUNK):
                res = fn(uf[i : i + _CHUNK], vf[i : i + _CHUNK])
                for j, r in enumerate(res):
                    outs[j][i : i + _CHUNK] = r.T
            for j, o in enumerate(outs):
                bad = ~np.all(np.isfinite(o), axis=1)
                if bad.any():
                    o[bad] = self._limit(fn, j, uf[bad], vf[bad])
        result = []
        for j, o in enumerate(outs):
            rows, cols = fun.size_out(j)
            if cols == 1:
                result.append(o.reshape(shape + (rows,)))
            else:
                result.append(np.swapaxes(o.reshape(shape + (cols, rows)), -1, -2))
        return result

    def _limit(self, fn: Callable, j: int, u: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Value at removable singularities: the mean of the one-sided values at ``u ± δ``."""
        for du, dv in ((1.0, 0.0), (0.0, 1.0)):
            du_ = du * 1e-6 * np.maximum(1.0, np.abs(u))
            dv_ = dv * 1e-6 * np.maximum(1.0, np.abs(v))
            lo = fn(u - du_, v - dv_)[j].T
            hi = fn(u + du_, v + dv_)[j].T
            scale = np.maximum(1.0, np.maximum(np.abs(lo), np.abs(hi)))
            ok = np.all(np.isfinite(lo) & np.isfinite(hi) & (np.abs(hi - lo) <= 1e-4 * scale))
            if ok:
                return 0.5 * (lo + hi)
        k = int(np.argmax(~np.all(np.isfinite(fn(u, v)[j]), axis=0)))
        raise SingularConfiguration(
            f"{self.name}: the coordinate system is singular at (u, v) = ({u[k]!r}, {v[k]!r}) "
            f"and the value has no limit there; evaluate inside the domain U = "
            f"{self.domain.tolist()} away from poles",
            value=float(u[k]),
        )

    def local_geometry(self, u: float, v: float) -> SurfaceGeometry:
        """Point, frame, ``K``, ``T``, ``M`` at one point, by a direct CasADi call.

        Faster than :meth:`evaluate` for a single point (used in contact integrators).

        Args:
            u, v: scalar coordinates.
        """
        if "scalar" not in self._np:
            self._np["scalar"] = scalar_function(self.functions["all"])
        try:
            p, fr, k, t, m = self._np["scalar"](float(u), float(v))
        except (ZeroDivisionError, ValueError, OverflowError):
            return SurfaceGeometry(*self._eval("all", u, v))
        if not math.isfinite(sum(fr) + sum(k) + sum(t) + sum(m)):
            return SurfaceGeometry(*self._eval("all", u, v))
        return SurfaceGeometry(
            np.array(p),
            np.array(fr).reshape(3, 3).T,
            np.array(k).reshape(2, 2).T,
            np.array(t).reshape(1, 2),
            np.array(m).reshape(2, 2).T,
        )

    def point(self, u, v) -> np.ndarray:
        """Surface points ``f(u, v)``: (..., 3) [m]."""
        return self._eval("point", u, v)[0]

    def tangents(self, u, v) -> tuple[np.ndarray, np.ndarray]:
        """Partial derivatives ``(f_u, f_v)``: each (..., 3) [m per unit of u, v]."""
        return self._eval("f_u", u, v)[0], self._eval("f_v", u, v)[0]

    def gauss_frame(self, u, v) -> np.ndarray:
        """Normalized Gauss frame (eq. A.1): (..., 3, 3), columns ``x, y, z``; ``z`` outward."""
        return self._eval("gauss_frame", u, v)[0]

    def normal(self, u, v) -> np.ndarray:
        """Unit outward normal ``z(u, v)``: (..., 3)."""
        return self.gauss_frame(u, v)[..., :, 2]

    def curvature_matrix(self, u, v) -> np.ndarray:
        """Curvature form ``K`` (eq. A.2): (..., 2, 2) [1/m], convex positive."""
        return self._eval("curvature_matrix", u, v)[0]

    def torsion(self, u, v) -> np.ndarray:
        """Torsion form ``T`` (eq. A.3): (..., 1, 2) [1/m]."""
        return self._eval("torsion", u, v)[0]

    def metric(self, u, v) -> np.ndarray:
        """Metric ``M`` (eq. A.4): (..., 2, 2) [m per unit of u, v]."""
        return self._eval("metric", u, v)[0]

    def evaluate(self, u, v) -> SurfaceGeometry:
        """Point, Gauss frame, ``K``, ``T`` and ``M`` in one pass (see :class:`SurfaceGeometry`)."""
        return SurfaceGeometry(*self._eval("all", u, v))

    def principal_curvatures(self, u, v) -> tuple[np.ndarray, np.ndarray]:
        """Principal curvatures ``(k1, k2)`` with ``|k1| >= |k2|`` (§3.2.1): each (...) [1/m]."""
        k = self._eval("principal_curvatures", u, v)[0]
        return k[..., 0], k[..., 1]

    def principal_directions(self, u, v) -> tuple[np.ndarray, np.ndarray]:
        """Unit principal directions ``(p1, p2)`` of ``k1`` and ``k2`` in world coordinates,
        each (..., 3) (eq. 3.8); ``p1 = x`` at umbilic points."""
        frame = self.gauss_frame(u, v)
        _, _, p1, p2 = principal_from_k(self.curvature_matrix(u, v))
        return (
            np.einsum("...ij,...j->...i", frame[..., :, :2], p1),
            np.einsum("...ij,...j->...i", frame[..., :, :2], p2),
        )

    def orthogonality(self, u, v) -> np.ndarray:
        """``|cos|`` of the angle between ``f_u`` and ``f_v``: (...); 0 for orthogonal
        coordinates (Definition 3 of App. A), where K, T, M are exactly eqs. A.2-A.4; 0 where
        a tangent vanishes (a coordinate singularity such as a pole)."""
        fu, fv = self.tangents(u, v)
        den = np.linalg.norm(fu, axis=-1) * np.linalg.norm(fv, axis=-1)
        dot = np.abs(np.sum(fu * fv, axis=-1))
        return np.where(den > 0, dot / np.where(den > 0, den, 1.0), 0.0)

    def contains(self, u, v) -> np.ndarray:
        """Whether ``(u, v)`` lies in the open domain ``U``: bool (...)."""
        (u0, u1), (v0, v1) = self.domain
        u = np.asarray(u, dtype=float)
        v = np.asarray(v, dtype=float)
        return (u > u0) & (u < u1) & (v > v0) & (v < v1)

    def parallel(self, distance: float) -> ParametricSurface:
        """The parallel surface ``s_p = f + r z`` (eq. 3.10) as a new surface.

        Its Gauss map is that of this surface (the fingertip centre moves along the normal);
        in caustic regions (a principal curvature ``k_i < -1/r``) its parametrization folds.

        Args:
            distance: offset ``r`` along the outward normal, usually ``tip_radius`` [m].
        """
        r = checks.in_range("distance", distance, -np.inf, np.inf, "m", closed=(False, False))
        base = self

        def offset_map(u, v):
            s = base.symbolic(u, v)
            return [s["point"][i] + r * s["z"][i] for i in range(3)]

        def offset_orientation(u, v):
            s = base.symbolic(u, v)
            e = ca.jacobian(s["point"] + r * s["z"], ca.vertcat(u, v))
            return ca.sign(ca.dot(ca.cross(e[:, 0], e[:, 1]), s["z"]))

        return ParametricSurface(
            offset_map,
            self.domain,
            orientation=offset_orientation,
            name=f"parallel({self.name}, {r:g})",
        )

    def caustic_mask(self, u, v, distance: float) -> np.ndarray:
        """Where the parallel surface at ``distance`` has caustics: some ``k_i < -1/r``
        (§3.2.1): bool (...)."""
        k1, k2 = self.principal_curvatures(u, v)
        r = float(distance)
        return (1.0 + r * k1 <= 0.0) | (1.0 + r * k2 <= 0.0)

    def __repr__(self) -> str:
        return f"ParametricSurface({self.name!r}, domain={self.domain.tolist()})"


__all__ = ["ParametricSurface", "SurfaceGeometry", "principal_from_k"]
