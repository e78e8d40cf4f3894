"""Figures of the ``trace`` kind (Figs. 3.3, 3.4 and 3.9 of the thesis), in millimetres."""

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


def trace_figure(name, profile, centers, smoothed, estimated, tip_radius, closed, true_mid):
    """Fig. 3.9: object, noisy traced curve, smoothed traced curve, estimated surface."""
    fig, ax = _axes(f"{name}: simulated trace (Fig. 3.9)")
    k = 1e3
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
    ax.plot(profile[:, 0] * k, profile[:, 1] * k, "k-", lw=1.5, label="object")
    step = max(1, len(centers) // 3000)
    ax.plot(
        centers[::step, 0] * k,
        centers[::step, 1] * k,
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
    ax.legend(loc="best", fontsize=8)
    return fig


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
