"""Figures of grasp maps, workspace overlays and gaits (Fig. 2.4, Fig. 2.12 style).

Figures are built with :class:`matplotlib.figure.Figure` (no pyplot state, no ``show``).
"""

from __future__ import annotations

import numpy as np


def plot_grasp_map(gmap, tables=None, gait=None, *, title: str = "Grasp map"):
    """Grasp map (ε shaded where in force closure) with workspace regions and the gait.

    Args:
        gmap: :class:`planner.grasp.maps.GraspMap` (left–right pair, object frame).
        tables: :class:`planner.grasp.workspace.WorkspaceTables` at the initial pose (its
            ``theta`` may have another resolution); overlays the left–right region
            (reachable by both fingers), and the left–palm / right–palm regions (lines at
            the palm's contact angle).
        gait: :class:`planner.grasp.gait.Gait` whose map-space path is drawn.

    Returns:
        A matplotlib Figure.
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    fig = Figure(figsize=(6.4, 5.6))
    ax = fig.add_subplot()
    deg = np.rad2deg(gmap.theta)
    step = deg[1] - deg[0]
    extent = (deg[0] - step / 2, deg[-1] + step / 2, deg[0] - step / 2, deg[-1] + step / 2)
    eps = np.where(gmap.force_closure, gmap.epsilon, np.nan)
    im = ax.imshow(
        eps.T,
        origin="lower",
        extent=extent,
        cmap="Greys",
        vmin=0,
        vmax=max(float(np.nanmax(eps)) if np.isfinite(eps).any() else 1.0, 1e-9),
        interpolation="nearest",
        aspect="equal",
    )
    fig.colorbar(im, ax=ax, label="ε quality (force closure cells) [-]", shrink=0.8)
    handles = [Patch(facecolor="0.5", label="force closure (ε shaded)")]
    if tables is not None:
        th = np.rad2deg(tables.theta)
        rl, rr = tables.reachable["left"][0], tables.reachable["right"][0]
        both = (rl[:, None] & rr[None, :]).astype(float)
        ax.contourf(th, th, both.T, levels=[0.5, 1.5], colors=["tab:blue"], alpha=0.3)
        handles.append(Patch(facecolor="tab:blue", alpha=0.3, label="left–right workspace"))
        if tables.palm_index[0] >= 0:
            tp = th[tables.palm_index[0]]
            ax.plot(th[rl], np.full(rl.sum(), tp), "s", color="tab:orange", ms=3)
            ax.plot(np.full(rr.sum(), tp), th[rr], "s", color="tab:green", ms=3)
            handles.append(Patch(facecolor="tab:orange", label="left–palm workspace"))
            handles.append(Patch(facecolor="tab:green", label="right–palm workspace"))
    if gait is not None and gait.feasible and len(gait.path):
        th = 360.0 / gait.resolution
        path = gait.path[(gait.path[:, 1] >= 0) & (gait.path[:, 2] >= 0)]
        x, y = path[:, 1] * th, path[:, 2] * th
        # break the polyline where it wraps around 360 deg
        jump = np.r_[False, (np.abs(np.diff(x)) > 180) | (np.abs(np.diff(y)) > 180)]
        x = np.where(jump, np.nan, x)
        ax.plot(x, y, "-", color="tab:red", lw=1.5)
        ax.plot(path[0, 1] * th, path[0, 2] * th, "o", color="tab:red")
        handles.append(Patch(facecolor="tab:red", label="gait (one period)"))
    ax.set_xlim(0, 360)
    ax.set_ylim(0, 360)
    ax.set_xlabel("θ1, left finger contact angle [deg]")
    ax.set_ylabel("θ2, right finger contact angle [deg]")
    ax.set_title(title)
    ax.legend(handles=handles, loc="upper left", fontsize=7, framealpha=0.8)
    return fig


def plot_gait_phases(profile, gait, problem, *, max_phases: int = 3):
    """The object on the palm with the grasp of each phase of the gait's first cycle.

    Args:
        profile: the object's closed profile (object frame) [m].
        gait: a feasible :class:`planner.grasp.gait.Gait`.
        problem: its :class:`planner.grasp.gait.GaitProblem` (object placements).
        max_phases: number of phases drawn.

    Returns:
        A matplotlib Figure, one panel per phase (hand frame, mm).
    """
    from matplotlib.figure import Figure

    from planner.grasp.maps import profile_contacts
    from planner.grasp.workspace import rotation

    phases = gait.phases[:max_phases]
    fig = Figure(figsize=(4.0 * max(len(phases), 1), 4.0))
    outline, _ = profile_contacts(profile, np.linspace(0, 2 * np.pi, 361))
    place = problem.tables.placement
    colors = {"left": "tab:orange", "right": "tab:green", "palm": "k"}
    for a, ph in enumerate(phases):
        ax = fig.add_subplot(1, max(len(phases), 1), a + 1)
        k = ph.pose_end
        R = rotation(place.angles[k])
        t = place.offsets[k]
        ow = (outline @ R.T + t) * 1e3
        ax.fill(ow[:, 0], ow[:, 1], color="0.85", ec="0.3")
        ax.axhline(0.0, color="k", lw=2)
        for who in ("left", "right", "palm"):
            th = ph.end[who]
            if not np.isfinite(th):
                continue
            p, _ = profile_contacts(profile, [th])
            pw = (p @ R.T + t)[0] * 1e3
            holding = who in ph.holding
            state = "holds" if holding else ("touches" if who == "palm" else "relocated")
            ax.plot(*pw, "o" if holding else "x", color=colors[who], ms=8, label=f"{who} ({state})")
        ax.set_aspect("equal")
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.set_title(
            f"phase {ph.phase}: {'+'.join(ph.holding)}\nrotation {np.rad2deg(ph.rotation):.0f}°",
            fontsize=9,
        )
        ax.legend(fontsize=7, loc="upper right")
    fig.suptitle("Grasps of the first gait cycle (object on the palm, y = 0)")
    fig.tight_layout()
    return fig


__all__ = ["plot_gait_phases", "plot_grasp_map"]
