"""Feature analysis of one surface for one fingertip (thesis §3.2.1-3.2.3, Figs. 3.6-3.7).

Two views of a surface explored by a fingertip of radius ``r_f``:

* a **slice** along ``u`` at fixed ``v`` (Fig. 3.7): the normal curvature along the slice
  (``K11``, the curvature a fingertip moving along ``u`` meets), its curvature features
  (Definition 1) and macro features (Table 3.1), with positions as arc length along the
  slice;
* a **map** over the surface: principal curvatures on a grid, curvature-feature regions and
  macro features (:func:`~planner.geometry.feature_maps.curvature_feature_map`), and for
  surfaces that are graphs ``z = h(x, y)`` (normal up everywhere) the traced/estimated
  surfaces with unobservable regions and interference curves. Graph surfaces are resampled
  on a regular ``(x, y)`` raster so that distances are true distances; other surfaces
  (sphere, cylinder) are mapped on their ``(u, v)`` grid with both axes scaled to arc length
  at the centre of the domain (exact for the cylinder, approximate for the sphere).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.geometry.feature_maps import FeatureMap, curvature_feature_map
from planner.geometry.features import (
    CurvatureFeature1D,
    MacroFeature1D,
    curvature_features_1d,
    macro_features_1d,
)
from planner.geometry.surfaces.offsets import OffsetSurfaces, offset_surfaces


@dataclass(frozen=True)
class SliceAnalysis:
    """Curvature along ``u`` at fixed ``v`` (Fig. 3.7).

    Attributes:
        v: the slice's ``v``.
        u: (N,) samples of ``u``.
        s: (N,) arc length along the slice from its start [m].
        k11: (N,) normal curvature along the slice, ``K11`` of eq. A.2 [1/m].
        k22: (N,) ``K22``, the curvature across the slice [1/m].
        points: (N, 3) surface points [m]; parallel: (N, 3) parallel-surface points (3.10).
        features: curvature features of ``k11`` with ``start``/``end``/``peak`` in ``s``.
        macros: macro features of the slice (Table 3.1, using ``k22`` as ``k2``).
    """

    v: float
    u: np.ndarray
    s: np.ndarray
    k11: np.ndarray
    k22: np.ndarray
    points: np.ndarray
    parallel: np.ndarray
    features: tuple[CurvatureFeature1D, ...]
    macros: tuple[MacroFeature1D, ...]

    def to_u(self, s_value: float) -> float:
        """The ``u`` at arc length ``s_value`` along the slice."""
        return float(np.interp(s_value, self.s, self.u))


@dataclass(frozen=True)
class MapAnalysis:
    """Curvature map, features and offset surfaces over a grid.

    Attributes:
        x: (nx,) and y: (ny,) grid axes [m] (arc-length-scaled ``u, v`` for non-graphs).
        graph: whether the surface was resampled as a height field ``z = h(x, y)``.
        height: (nx, ny) heights [m] for graphs, else ``None``.
        k1: (nx, ny) and k2: (nx, ny) principal curvatures, ``|k1| >= |k2|`` [1/m].
        inside: (nx, ny) bool, raster cells covered by the surface patch.
        caustic: (nx, ny) bool, ``k_i < -1/r_f`` (parallel-surface caustics, §3.2.1).
        features: the curvature/macro feature map.
        offsets: traced/estimated surfaces (graphs only, on the raster subsampled so that
            the ball spans at most ``MAX_BALL_CELLS`` cells), else ``None``.
    """

    x: np.ndarray
    y: np.ndarray
    graph: bool
    height: np.ndarray | None
    k1: np.ndarray
    k2: np.ndarray
    inside: np.ndarray
    caustic: np.ndarray
    features: FeatureMap
    offsets: OffsetSurfaces | None


def finite_box(surface, span_hint: float | None = None) -> np.ndarray:
    dom = np.array(surface.domain, dtype=float)
    (u0, u1) = dom[0]
    if not np.isfinite(u0) or not np.isfinite(u1):
        u0, u1 = -1.0, 1.0
    half = (u1 - u0) / 2 if span_hint is None else span_hint
    v0, v1 = dom[1]
    if not np.isfinite(v0) or not np.isfinite(v1):
        mid = 0.0 if not (np.isfinite(v0) or np.isfinite(v1)) else (v0 if np.isfinite(v0) else v1)
        v0, v1 = mid - half, mid + half
    # stay inside the open domain
    eu, ev = 1e-3 * (u1 - u0), 1e-3 * (v1 - v0)
    return np.array([[u0 + eu, u1 - eu], [v0 + ev, v1 - ev]])


MAX_BALL_CELLS = 12  # ball radius in grid cells for the morphological offsets


def _offsets(x, y, height, r) -> OffsetSurfaces | None:
    """Offsets on the raster, subsampled so the ball spans at most ``MAX_BALL_CELLS``."""
    step = max(x[1] - x[0], y[1] - y[0])
    if r < step:
        return None
    k = max(1, int(np.ceil(r / (MAX_BALL_CELLS * step))))
    return offset_surfaces(x[::k], y[::k], height[::k, ::k], r)


def _rectilinear_resample(pts, vals, x, y) -> np.ndarray | None:
    """Bilinear resampling when ``x`` depends on ``u`` only and ``y`` on ``v`` only (straight
    sweeps): exact lattice, no triangulation. ``None`` when the points are not such a grid."""
    xs, ys = pts[:, 0, 0], pts[0, :, 1]
    if not (
        np.allclose(pts[..., 0], xs[:, None])
        and np.allclose(pts[..., 1], ys[None, :])
        and np.all(np.diff(xs) > 0)
        and np.all(np.diff(ys) > 0)
    ):
        return None
    fi = np.interp(x, xs, np.arange(xs.size))
    fj = np.interp(y, ys, np.arange(ys.size))
    i0 = np.clip(np.floor(fi).astype(int), 0, xs.size - 2)
    j0 = np.clip(np.floor(fj).astype(int), 0, ys.size - 2)
    a = (fi - i0)[:, None, None]
    b = (fj - j0)[None, :, None]
    v00 = vals[i0][:, j0]
    v10 = vals[i0 + 1][:, j0]
    v01 = vals[i0][:, j0 + 1]
    v11 = vals[i0 + 1][:, j0 + 1]
    return (1 - a) * (1 - b) * v00 + a * (1 - b) * v10 + (1 - a) * b * v01 + a * b * v11


def slice_analysis(
    surface, tip_radius: float, v: float | None = None, n: int = 801
) -> SliceAnalysis:
    """Curvature features along ``u`` at fixed ``v`` (Fig. 3.7).

    Args:
        surface: a :class:`~planner.geometry.surfaces.ParametricSurface` (or height field).
        tip_radius: ``r_f`` [m].
        v: the slice (default: middle of the domain's ``v`` range).
        n: number of samples along ``u`` (>= 3).
    """
    n = checks.integer("n", n, minimum=3)
    tip_radius = checks.positive("tip_radius", tip_radius, "m")
    box = finite_box(surface)
    v = float(np.mean(box[1])) if v is None else float(v)
    u = np.linspace(box[0, 0], box[0, 1], n)
    g = surface.evaluate(u, v)
    k = g.curvature_matrix
    pts = g.point
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
    feats = curvature_features_1d(s, k[:, 0, 0], tip_radius)
    macros = macro_features_1d(feats, tip_radius, s=s, k2=k[:, 1, 1])
    par = pts + tip_radius * g.gauss_frame[:, :, 2]
    return SliceAnalysis(v, u, s, k[:, 0, 0], k[:, 1, 1], pts, par, tuple(feats), tuple(macros))


def map_analysis(surface, tip_radius: float, n: int = 201) -> MapAnalysis:
    """Principal-curvature map, curvature/macro features and offsets over a grid.

    Args:
        surface: a :class:`~planner.geometry.surfaces.ParametricSurface` or
            :class:`~planner.geometry.surfaces.HeightField`.
        tip_radius: ``r_f`` [m].
        n: grid size per axis (>= 8).
    """
    from scipy.interpolate import LinearNDInterpolator, NearestNDInterpolator

    n = checks.integer("n", n, minimum=8)
    tip_radius = checks.positive("tip_radius", tip_radius, "m")
    box = finite_box(surface)
    uu, vv = np.meshgrid(np.linspace(*box[0], n), np.linspace(*box[1], n), indexing="ij")
    k1, k2 = surface.principal_curvatures(uu, vv)
    pts = surface.point(uu, vv)
    normal_z = surface.normal(uu, vv)[..., 2]
    graph = bool(np.all(normal_z > 1e-6))
    if graph:
        x = np.linspace(pts[..., 0].min(), pts[..., 0].max(), n)
        y = np.linspace(pts[..., 1].min(), pts[..., 1].max(), n)
        gx, gy = np.meshgrid(x, y, indexing="ij")
        vals = np.stack([k1, k2, pts[..., 2]], axis=-1)
        inverse = getattr(surface, "inverse", None)
        lin = _rectilinear_resample(pts, vals, x, y) if inverse is None else None
        if inverse is not None:  # exact: evaluate at the parameters above each raster cell
            ru, rv = inverse(gx, gy)
            (u0, u1), (v0, v1) = np.asarray(surface.domain, float)
            ok = (ru >= u0) & (ru <= u1) & (rv >= v0) & (rv <= v1)
            ru, rv = np.clip(ru, u0, u1), np.clip(rv, v0, v1)
            rk1, rk2 = surface.principal_curvatures(ru, rv)
            lin = np.stack([rk1, rk2, surface.point(ru, rv)[..., 2]], axis=-1)
            lin[~ok] = np.nan
        elif lin is None:  # scattered: one triangulation for all three values
            src = np.column_stack([pts[..., 0].ravel(), pts[..., 1].ravel()])
            lin = LinearNDInterpolator(src, vals.reshape(-1, 3))(gx, gy)
        inside = np.all(np.isfinite(lin), axis=-1)
        if inside.all():
            height = lin[..., 2]
        else:
            src = np.column_stack([pts[..., 0].ravel(), pts[..., 1].ravel()])
            near = NearestNDInterpolator(src, pts[..., 2].ravel())(gx, gy)
            height = np.where(inside, lin[..., 2], near)
        mk1, mk2 = (np.where(inside, lin[..., i], 0.0) for i in (0, 1))
        offsets = _offsets(x, y, height, tip_radius)
    else:
        c = surface.evaluate(np.mean(box[0]), np.mean(box[1]))
        su, sv = abs(c.metric[0, 0]), abs(c.metric[1, 1])
        x = np.linspace(*box[0], n) * su
        y = np.linspace(*box[1], n) * sv
        inside = np.ones(uu.shape, dtype=bool)
        height, offsets, mk1, mk2 = None, None, k1, k2
    fmap = curvature_feature_map(x, y, mk1, mk2, tip_radius)
    caustic = inside & ((mk1 < -1 / tip_radius) | (mk2 < -1 / tip_radius))
    return MapAnalysis(x, y, graph, height, mk1, mk2, inside, caustic, fmap, offsets)


__all__ = ["MapAnalysis", "SliceAnalysis", "finite_box", "map_analysis", "slice_analysis"]
