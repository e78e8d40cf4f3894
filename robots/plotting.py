"""Figures of the robots: the hand with a ball and its workspace map, the 3GM and its trapezoid.

Every function returns a ``matplotlib.figure.Figure`` (never shows it); axes in mm.
"""

from __future__ import annotations

import numpy as np

from robots.planar_hand import PlanarHand, WorkspaceMap
from robots.three_gm import ThreeGM
from robots.three_gm.workspace import ConditionedWorkspace

MM = 1000.0
_COLORS = {"left": "tab:blue", "right": "tab:red"}


def _figure(size=(6.4, 5.2)):
    from matplotlib.figure import Figure

    return Figure(figsize=size, layout="constrained")


def plot_hand(
    hand: PlanarHand,
    q: np.ndarray,
    center: np.ndarray,
    radius: float,
    maps: dict[str, WorkspaceMap] | None = None,
    title: str = "",
):
    """The hand at ``q`` (6,) [rad] with the ball (centre (2,) [m], radius [m]) and, when
    given, each finger's reachable contacts on the ball (coloured arcs)."""
    from matplotlib.patches import Circle

    fig = _figure((9.0, 5.0))
    ax = fig.add_subplot()
    pw = hand.params.palm_half_width
    ax.plot([-pw * MM, pw * MM], [0, 0], color="k", lw=5, solid_capstyle="butt", label="palm")
    ax.add_patch(Circle(center * MM, radius * MM, fc="0.92", ec="0.4", lw=1))
    for finger in ("left", "right"):
        f = hand.params.finger(finger)
        pts = hand.finger_points(q, finger) * MM
        c = _COLORS[finger]
        ax.plot(pts[:, 0], pts[:, 1], "-o", color=c, lw=3, ms=5, label=f"{finger} finger")
        pose = hand.fingertip_pose(q, finger)
        if f.tip == "round":
            ax.add_patch(Circle(pose.position * MM, f.tip_radius * MM, fc="none", ec=c, lw=2))
        else:
            t = np.array([pose.axis[1], -pose.axis[0]]) * f.pad_half_width
            seg = np.array([pose.position - t, pose.position + t]) * MM
            ax.plot(seg[:, 0], seg[:, 1], color=c, lw=6, solid_capstyle="butt")
        if maps and finger in maps:
            m = maps[finger]
            pts_c = m.contacts[m.reachable] * MM
            ax.plot(
                pts_c[:, 0],
                pts_c[:, 1],
                ".",
                color=c,
                ms=7,
                label=f"{finger}: reachable contacts ({100 * m.fraction:.0f} %)",
            )
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title(title or "Planar hand, palm and ball")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7)
    ax.grid(alpha=0.3)
    return fig


def plot_reachable_sets(positions: dict[str, np.ndarray], center: np.ndarray, radius: float):
    """Scatter of sampled fingertip points (N, 2) [m] per finger, with the ball outline."""
    from matplotlib.patches import Circle

    fig = _figure()
    ax = fig.add_subplot()
    for finger, p in positions.items():
        ax.plot(
            p[:, 0] * MM,
            p[:, 1] * MM,
            ".",
            ms=2,
            alpha=0.5,
            color=_COLORS[finger],
            label=f"{finger} fingertip",
        )
    ax.add_patch(Circle(center * MM, radius * MM, fc="none", ec="k", lw=1))
    ax.axhline(0.0, color="k", lw=1)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title("Reachable fingertip points (uniform joint-space samples)")
    ax.legend(loc="upper right", fontsize=7, markerscale=4)
    return fig


def plot_three_gm(gm: ThreeGM, theta: np.ndarray, ws: ConditionedWorkspace | None = None):
    """Side view of the five-bar at ``theta`` (3,) [rad] and top view of the trapezoid,
    coloured by the condition number of the sampled workspace points."""
    from robots.three_gm.params import WORKSPACE_HALF_ANGLE, WORKSPACE_RADII, WORKSPACE_Z

    p = gm.params
    st = gm.state(theta)
    u = lambda a: np.array([np.cos(a), np.sin(a)])  # noqa: E731
    P1, P2 = p["l1"] * u(theta[0]), np.array([0.0, -p["h1"]]) + p["l2"] * u(theta[1])
    B, E = P1 + p["l4"] * u(st.gamma1), P1 + p["l5"] * u(st.gamma1)
    fig = _figure((11.0, 4.8))
    side, top = fig.subplots(1, 2)
    off = np.array([p["h2"], 0.0])
    for chain in ([np.zeros(2), P1, E], [np.array([0.0, -p["h1"]]), P2, B]):
        c = (np.array(chain) + off) * MM
        side.plot(c[:, 0], c[:, 1], "-o", lw=3, ms=5)
    side.plot(*(E + off) * MM, "r*", ms=12, label="endpoint (OWTS centre)")
    r0, r1 = WORKSPACE_RADII
    z0, z1 = WORKSPACE_Z
    side.add_patch(_rect(r0 * MM, z0 * MM, (r1 - r0) * MM, (z1 - z0) * MM))
    side.set_aspect("equal")
    side.set_xlabel("radial distance r + h2 [mm]")
    side.set_ylabel("z [mm]")
    side.set_title(f"3GM five-bar, θ = {np.rad2deg(theta).round(1).tolist()}°")
    side.legend(fontsize=7, loc="upper right")
    a = np.linspace(-WORKSPACE_HALF_ANGLE, WORKSPACE_HALF_ANGLE, 50)
    outline = np.concatenate(
        [
            np.column_stack([r0 * np.cos(a), r0 * np.sin(a)]),
            np.column_stack([r1 * np.cos(a[::-1]), r1 * np.sin(a[::-1])]),
        ]
    )
    outline = np.vstack([outline, outline[:1]]) * MM
    top.plot(outline[:, 0], outline[:, 1], "k-", lw=1.5, label="App. C.2 trapezoid")
    if ws is not None:
        ok = ws.reachable
        sc = top.scatter(
            ws.points[ok, 0] * MM, ws.points[ok, 1] * MM, c=ws.condition[ok], s=12, cmap="viridis"
        )
        fig.colorbar(sc, ax=top, label="condition number of the five-bar Jacobian [-]")
        if (~ok).any():
            top.plot(ws.points[~ok, 0] * MM, ws.points[~ok, 1] * MM, "rx", label="unreachable")
    x = gm.forward_kinematics(theta) * MM
    top.plot(x[0], x[1], "r*", ms=12)
    top.plot([0], [0], "ks", label="base axis")
    top.set_aspect("equal")
    top.set_xlabel("x [mm]")
    top.set_ylabel("y [mm]")
    top.set_title("Top view of the well-conditioned workspace")
    top.legend(fontsize=7, loc="lower right")
    return fig


def _rect(x, y, w, h):
    from matplotlib.patches import Rectangle

    return Rectangle((x, y), w, h, fc="none", ec="k", ls="--", label="workspace (side)")


__all__ = ["plot_hand", "plot_reachable_sets", "plot_three_gm"]
