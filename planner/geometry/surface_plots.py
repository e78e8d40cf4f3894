"""Figures of a surface feature analysis (thesis Figs. 3.3-3.4, 3.6-3.7).

Every function returns a :class:`matplotlib.figure.Figure` (never shown); the caller saves it.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from planner.geometry.surface_analysis import MapAnalysis, SliceAnalysis

_KIND_COLOURS = {
    "bump": "tab:red",
    "pit": "tab:blue",
    "ridge": "tab:orange",
    "ravine": "tab:cyan",
    "step": "tab:green",
    "cusp": "tab:purple",
    "unknown": "tab:gray",
}


def surface_figure(surface, tip_radius: float, n: int = 40) -> Figure:
    """The surface and its parallel surface (eq. 3.10) in 3-D, like Fig. 3.6.

    Args:
        surface: a parametric surface or height field; tip_radius: ``r_f`` [m];
        n: samples per axis of the wireframe.
    """
    from planner.geometry.surface_analysis import finite_box

    box = finite_box(surface)
    uu, vv = np.meshgrid(np.linspace(*box[0], n), np.linspace(*box[1], n), indexing="ij")
    g = surface.evaluate(uu, vv)
    par = g.point + tip_radius * g.gauss_frame[..., :, 2]
    fig = Figure(figsize=(7, 6))
    ax = fig.add_subplot(projection="3d")
    ax.plot_surface(*np.moveaxis(g.point, -1, 0), cmap="viridis", alpha=0.9, linewidth=0)
    ax.plot_wireframe(
        *np.moveaxis(par, -1, 0), color="tab:red", linewidth=0.4, alpha=0.6, rstride=2, cstride=2
    )
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    ax.set_title(f"{surface.name} (surface) and parallel surface (red), r_f = {tip_radius:g} m")
    return fig


def slice_figure(sl: SliceAnalysis, tip_radius: float, name: str = "") -> Figure:
    """``K11`` along the slice with ``±1/r_f`` and the curvature features shaded (Fig. 3.7)."""
    fig = Figure(figsize=(8, 4.5))
    ax = fig.add_subplot()
    ax.plot(sl.u, sl.k11, color="k", label="k1(S) = K11 along u")
    thr = 1.0 / tip_radius
    ax.axhline(thr, color="tab:red", ls="--", label="+1/r_f")
    ax.axhline(-thr, color="tab:blue", ls="--", label="-1/r_f")
    for f in sl.features:
        ax.axvspan(
            sl.to_u(f.start),
            sl.to_u(f.end),
            alpha=0.2,
            color="tab:red" if f.sign > 0 else "tab:blue",
        )
    for m in sl.macros:
        ax.annotate(
            m.kind,
            xy=(sl.to_u(0.5 * (m.start + m.end)), thr),
            xytext=(0, 12),
            textcoords="offset points",
            ha="center",
            color=_KIND_COLOURS.get(m.kind, "k"),
        )
    lim = max(3 * thr, 1.1 * thr)
    ax.set_ylim(max(sl.k11.min(), -lim) * 1.1, min(sl.k11.max(), lim) * 1.1 + thr)
    ax.set_xlabel("u (slice parameter)")
    ax.set_ylabel("curvature [1/m]")
    ax.set_title(
        f"{name} curvature features along u at v = {sl.v:.3g} ({len(sl.features)} features)"
    )
    ax.legend(loc="lower right", fontsize=8)
    ax.grid(alpha=0.3)
    return fig


def feature_map_figure(ma: MapAnalysis, name: str = "") -> Figure:
    """Map of ``k1`` with the curvature-feature regions outlined and macro features named."""
    fm = ma.features
    thr = 1.0 / fm.tip_radius
    fig = Figure(figsize=(7, 6))
    ax = fig.add_subplot()
    ext = [ma.y[0], ma.y[-1], ma.x[0], ma.x[-1]]
    k = np.where(ma.inside, ma.k1, np.nan)
    im = ax.imshow(
        k, origin="lower", extent=ext, cmap="RdBu_r", vmin=-3 * thr, vmax=3 * thr, aspect="auto"
    )
    fig.colorbar(im, ax=ax, label="k1 [1/m] (clipped at ±3/r_f)")
    gy, gx = np.meshgrid(ma.y, ma.x)
    if (fm.positive > 0).any():
        ax.contour(gy, gx, (fm.positive > 0).astype(float), levels=[0.5], colors="darkred")
    if (fm.negative > 0).any():
        ax.contour(gy, gx, (fm.negative > 0).astype(float), levels=[0.5], colors="navy")
    for m in fm.macros:
        ax.annotate(
            m.kind,
            xy=(m.centroid[1], m.centroid[0]),
            ha="center",
            fontsize=11,
            color=_KIND_COLOURS.get(m.kind, "k"),
            fontweight="bold",
        )
    axes = ("x", "y") if ma.graph else ("u (arc length)", "v (arc length)")
    ax.set_xlabel(f"{axes[1]} [m]")
    ax.set_ylabel(f"{axes[0]} [m]")
    ax.set_title(f"{name} curvature features (red +, blue -), r_f = {fm.tip_radius:g} m")
    return fig


def offsets_figure(ma: MapAnalysis, name: str = "") -> Figure | None:
    """A cut at the middle ``y`` through the original, traced and estimated surfaces with the
    unobservable samples marked (Figs. 3.3-3.4); ``None`` when there are no offsets."""
    off = ma.offsets
    if off is None:
        return None
    j = off.y.size // 2
    x, h = off.x, off.height[:, j]
    fig = Figure(figsize=(8, 4.5))
    ax = fig.add_subplot()
    ax.plot(x, h, color="k", label="original surface")
    ax.plot(x, off.traced[:, j], color="tab:red", label="traced surface (fingertip centre)")
    ax.plot(x, off.estimated[:, j], color="tab:green", ls="--", label="estimated surface")
    hidden = off.unobservable[:, j]
    if hidden.any():
        ax.scatter(x[hidden], h[hidden], s=10, color="tab:orange", label="unobservable")
    crease = off.interference[:, j]
    if crease.any():
        ax.scatter(
            x[crease], off.traced[crease, j], marker="x", color="tab:purple", label="interference"
        )
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")
    ax.set_title(f"{name} cut at y = {off.y[j]:.3g} m, r_f = {off.tip_radius:g} m")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return fig


__all__ = ["feature_map_figure", "offsets_figure", "slice_figure", "surface_figure"]
