"""Figures of the ``trace`` kind (Figs. 3.3, 3.4, 3.9 and 3.12 of the thesis), in millimetres."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Circle


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
    ax.plot(profile[:, 0] * k, profile[:, 1] * k, "k-", lw=1.5, label="object")
    ax.plot(
        centers[:, 0] * k,
        centers[:, 1] * k,
        ".",
        ms=2,
        color="tab:orange",
        alpha=0.6,
        label="traced (noisy)",
    )
    ax.plot(
        smoothed[:, 0] * k,
        smoothed[:, 1] * k,
        "-",
        color="tab:red",
        lw=1,
        label="traced (smoothed)",
    )
    ax.plot(
        estimated[:, 0] * k,
        estimated[:, 1] * k,
        "--",
        color="tab:blue",
        lw=1.2,
        label="estimated surface",
    )
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
