"""Figures of the geometry package: profiles under a fingertip (thesis Figs. 3.3-3.4, 3.9,
3.12, in millimetres) and surface feature analyses (Figs. 3.3-3.4, 3.6-3.7).

The package's one plotting module (as ``planner.detection.plots`` is detection's). Every
``*_figure`` function returns a :class:`matplotlib.figure.Figure` (never shown); the caller
(a scenario kind) saves it.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Circle

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


# ------------------------------------------------------------------ profiles (2-D)
def _axes(title: str):
    fig = Figure(figsize=(9, 5.5))
    ax = fig.add_subplot()
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    return fig, ax


def trace_figure(
    title,
    profile,
    centers,
    smoothed,
    estimated,
    tip_radius,
    closed,
    true_mid,
    detected=(),
    truth=(),
):
    """Object, noisy and smoothed traced curves, estimated surface, features (Figs. 3.9, 3.12).

    Args:
        title: the figure title (the kind passes the scenario's name and description, which
            names the thesis figure it reproduces).
        profile, centers, smoothed, estimated: (N, 2) polylines [m].
        tip_radius: r_f [m]; closed: the profile is closed; true_mid: (2,) a fingertip centre
            drawn to scale [m].
        detected: ``(sign, (2,) position [m])`` of the features detected in the data.
        truth: the same for the profile's true curvature features (Definition 1).

    When the features lie in a region much smaller than the plot (a 0.65 mm wire under a
    10 mm fingertip), a second panel zooms on them (its frame is marked on the first).
    """
    k = 1e3
    box = _zoom_box(profile, [p for _, p in truth] or [p for _, p in detected], tip_radius)
    if box is None:
        fig, ax = _axes(title)
    else:  # the main view on the left, the zoom on the features beside it
        fig = Figure(figsize=(13, 5.5))
        ax, ins = fig.subplots(1, 2, gridspec_kw={"width_ratios": (3, 2)})
        fig.suptitle(title)
        for a in (ax, ins):
            a.set_aspect("equal")
            a.set_xlabel("x [mm]")
            a.set_ylabel("y [mm]")
            a.grid(alpha=0.3)
    if closed:
        ax.fill(profile[:, 0] * k, profile[:, 1] * k, color="0.85", zorder=0)
    else:
        ax.fill_between(
            profile[:, 0] * k,
            profile[:, 1] * k,
            profile[:, 1].min() * k - 2,
            color="0.85",
            zorder=0,
        )
    step = max(1, len(centers) // 3000)
    _trace_layers(ax, profile, centers[::step], smoothed, estimated, detected, truth)
    ax.add_patch(
        Circle(
            true_mid * k,
            tip_radius * k,
            fill=False,
            color="tab:green",
            lw=1,
            label=f"fingertip (r = {tip_radius * 1e3:g} mm)",
        )
    )
    ax.legend(loc="best", fontsize=7)
    if box is not None:
        if not closed:
            ins.fill_between(profile[:, 0] * k, profile[:, 1] * k, box[2] * k, color="0.85")
        _trace_layers(ins, profile, centers, smoothed, estimated, detected, truth)
        ins.set_xlim(box[0] * k, box[1] * k)
        ins.set_ylim(box[2] * k, box[3] * k)
        ins.set_title("zoom on the features", fontsize=9)
        ax.indicate_inset_zoom(ins, edgecolor="0.3")
    return fig


def _trace_layers(ax, profile, centers, smoothed, estimated, detected, truth):
    """The curves and feature markers shared by the main axes and the zoom inset [mm]."""
    k = 1e3
    curves = (
        (profile, dict(ls="-", color="k", lw=1.5, label="object")),
        (
            centers,
            dict(
                ls="none", marker=".", ms=2, color="tab:orange", alpha=0.6, label="traced (noisy)"
            ),
        ),
        (smoothed, dict(ls="-", color="tab:red", lw=1, label="traced (smoothed)")),
        (estimated, dict(ls="--", color="tab:blue", lw=1.2, label="estimated surface")),
    )
    for pts, style in curves:
        ax.plot(pts[:, 0] * k, pts[:, 1] * k, **style)
    styles = {
        ("truth", 1): dict(marker="o", mfc="none", mec="k", ms=9, label="true feature +"),
        ("truth", -1): dict(marker="s", mfc="none", mec="k", ms=9, label="true feature -"),
        ("detected", 1): dict(marker="^", color="tab:red", ms=7, label="detected +"),
        ("detected", -1): dict(marker="v", color="tab:purple", ms=7, label="detected -"),
    }
    for which, feats in (("truth", truth), ("detected", detected)):
        for sign in (1, -1):
            pts = np.array([p for s, p in feats if s == sign]).reshape(-1, 2)
            if len(pts):
                ax.plot(pts[:, 0] * k, pts[:, 1] * k, ls="none", **styles[(which, sign)])


def _zoom_box(profile, positions, tip_radius):
    """``(x0, x1, y0, y1)`` [m] around the features, or ``None`` if no zoom is needed.

    Half-size: 3 times the features' spread, at least 0.15 r_f; no inset unless the box is
    under a quarter of the plotted extent (otherwise the features are visible as they are).
    """
    if not len(positions):
        return None
    P = np.asarray(positions, float).reshape(-1, 2)
    centre = 0.5 * (P.min(axis=0) + P.max(axis=0))
    half = max(3.0 * float(np.ptp(P, axis=0).max()), 0.15 * tip_radius)
    extent = float(np.ptp(profile, axis=0).max())
    if 2.0 * half > 0.25 * extent:
        return None
    return centre[0] - half, centre[0] + half, centre[1] - half, centre[1] + half


def curves_figure(name, profile, parallel, traced, estimated):
    """Figs. 3.3-3.4: parallel, traced and estimated curves, caustic and interference
    points, unobservable regions."""
    fig, ax = _axes(f"{name}: parallel, traced and estimated curves (Figs. 3.3, 3.4)")
    k = 1e3
    ax.plot(profile[:, 0] * k, profile[:, 1] * k, "k-", lw=1.5, label="object")
    P = parallel.points
    ax.plot(P[:, 0] * k, P[:, 1] * k, ":", color="0.5", lw=1, label="parallel curve")
    T = traced.points
    ax.plot(T[:, 0] * k, T[:, 1] * k, "-", color="tab:red", lw=1.2, label="traced curve")
    E = estimated.points
    ax.plot(E[:, 0] * k, E[:, 1] * k, "--", color="tab:blue", lw=1.2, label="estimated")
    U = np.where(estimated.unobservable[:, None], E, np.nan)
    ax.plot(U[:, 0] * k, U[:, 1] * k, "-", color="magenta", lw=3, alpha=0.6, label="unobservable")
    if len(parallel.caustic_points):
        C = parallel.caustic_points
        ax.plot(C[:, 0] * k, C[:, 1] * k, "x", color="0.3", ms=7, label="caustic points")
    if len(traced.interference_points):
        X = traced.interference_points
        ax.plot(
            X[:, 0] * k,
            X[:, 1] * k,
            "o",
            mfc="none",
            mec="tab:red",
            ms=9,
            label="interference points",
        )
    ax.legend(loc="best", fontsize=8)
    return fig


__all__ = [
    "curves_figure",
    "feature_map_figure",
    "offsets_figure",
    "slice_figure",
    "surface_figure",
    "trace_figure",
]
