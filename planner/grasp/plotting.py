"""Figures of grasp maps, workspace overlays and gaits (Fig. 2.4, Fig. 2.12 style).

Figures are built with :class:`matplotlib.figure.Figure` (no pyplot state, no ``show``).
"""

from __future__ import annotations

import numpy as np


def plot_grasp_map(gmap, tables=None, gait=None, *, title: str = "Grasp map", pose: int = 0):
    """Grasp map (ε shaded where in force closure) with the workspace regions of one pose.

    The workspace regions move in map space as the object turns, so the gait is drawn in
    the same frame only: the gait's grasps held at that pose. The whole gait, phase by
    phase with the workspace of each phase's pose, is :func:`plot_gait_map`.

    Args:
        gmap: :class:`planner.grasp.maps.GraspMap` (left–right pair, object frame).
        tables: :class:`planner.grasp.workspace.WorkspaceTables` whose first pose is drawn
            (its ``theta`` may have another resolution); overlays the left–right region
            (reachable by both fingers), and the left–palm / right–palm regions (lines at
            the palm's contact angle).
        gait: :class:`planner.grasp.gait.Gait`; its grasps at pose ``pose`` are marked.
        title: the figure title.
        pose: the gait-grid pose index of ``tables`` (0: the object as placed).

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
        # only the gait's grasps at the pose whose workspace is drawn: one frame for both
        step = 360.0 / gait.resolution
        at = gait.path[(gait.path[:, 0] == pose) & (gait.path[:, 1] >= 0) & (gait.path[:, 2] >= 0)]
        ax.plot(at[:, 1] * step, at[:, 2] * step, "o", color="tab:red", ms=5)
        handles.append(Patch(facecolor="tab:red", label=f"gait grasps at pose {pose}"))
    ax.set_xlim(0, 360)
    ax.set_ylim(0, 360)
    ax.set_xlabel("θ1, left finger contact angle [deg]")
    ax.set_ylabel("θ2, right finger contact angle [deg]")
    ax.set_title(f"{title}\nworkspace at pose {pose} (object as placed)" if pose == 0 else title)
    ax.legend(handles=handles, loc="upper left", fontsize=7, framealpha=0.8)
    return fig


def phase_segment(ph, sign: int, theta_step: float) -> np.ndarray:
    """(m, 2) map-space points [deg] of one phase: a diagonal walk (1) or an axis move.

    Args:
        ph: a :class:`planner.grasp.gait.GaitPhase`.
        sign: the search's ``GaitProblem.sign`` (phase 1 steps both angles by ``sign``).
        theta_step: the contact-angle grid step [deg].
    """
    a = np.rad2deg([ph.start["left"], ph.start["right"]])
    b = np.rad2deg([ph.end["left"], ph.end["right"]])
    if ph.phase != 1:
        return np.array([a, b])
    steps = int(round(abs(ph.rotation) / np.deg2rad(theta_step)))
    return np.mod(a + sign * theta_step * np.arange(steps + 1)[:, None], 360.0)


def _workspace_regions(ax, problem, k: int, deg: np.ndarray, filled: bool) -> None:
    """Left–right region (filled or outlined) and palm lines at pose ``k``."""
    rl, rr = problem.reach["left"][k], problem.reach["right"][k]
    both = (rl[:, None] & rr[None, :]).astype(float).T
    if filled:
        ax.contourf(deg, deg, both, levels=[0.5, 1.5], colors=["tab:blue"], alpha=0.3)
        pi = int(problem.tables.palm_index[k])
        if pi >= 0:
            ax.plot(deg[rl], np.full(rl.sum(), deg[pi]), "s", color="tab:orange", ms=2)
            ax.plot(np.full(rr.sum(), deg[pi]), deg[rr], "s", color="tab:green", ms=2)
    else:
        ax.contour(deg, deg, both, levels=[0.5], colors=["tab:blue"], linestyles="--")


def plot_gait_map(problem, gait, *, max_phases: int = 4):
    """The gait phase by phase in map space, each over the workspace of its own pose.

    One panel per phase of the first cycle: the left–right grasp map at the gait's
    resolution (grey: force closure), the workspace regions at the phase's start pose
    (filled; dashed: at its end pose, where the object has turned) and the phase's path
    (phase 1 a diagonal walk, phases 2-3 one finger relocating along an axis).

    Args:
        problem: the gait's :class:`planner.grasp.gait.GaitProblem`.
        gait: a feasible :class:`planner.grasp.gait.Gait`.
        max_phases: number of phases drawn.

    Returns:
        A matplotlib Figure.
    """
    from matplotlib.figure import Figure

    phases = gait.phases[:max_phases]
    n = problem.theta.size
    deg = np.rad2deg(problem.theta)
    step = 360.0 / n
    fig = Figure(figsize=(3.6 * max(len(phases), 1), 3.9), layout="constrained")
    for a, ph in enumerate(phases):
        ax = fig.add_subplot(1, max(len(phases), 1), a + 1)
        ext = (-step / 2, 360 - step / 2, -step / 2, 360 - step / 2)
        ax.imshow(
            problem.fc_lr.T,
            origin="lower",
            extent=ext,
            cmap="Greys",
            vmin=0,
            vmax=2,
            interpolation="nearest",
            aspect="equal",
        )
        _workspace_regions(ax, problem, ph.pose_start, deg, filled=True)
        if ph.pose_end != ph.pose_start:
            _workspace_regions(ax, problem, ph.pose_end, deg, filled=False)
        seg = phase_segment(ph, problem.sign, step)
        jump = np.r_[False, np.any(np.abs(np.diff(seg, axis=0)) > 180, axis=1)]
        ax.plot(np.where(jump, np.nan, seg[:, 0]), seg[:, 1], "-", color="tab:red", lw=2)
        ax.plot(*seg[0], "o", color="tab:red", ms=5)
        ax.plot(*seg[-1], ">", color="tab:red", ms=6)
        ax.set_xlim(0, 360)
        ax.set_ylim(0, 360)
        ax.set_xlabel("θ1 left [deg]")
        ax.set_ylabel("θ2 right [deg]")
        ax.set_title(
            f"phase {ph.phase} ({'+'.join(ph.holding)}), poses {ph.pose_start}→{ph.pose_end}",
            fontsize=8,
        )
    fig.suptitle(
        "Gait in map space, each phase over its own pose's workspace "
        "(blue: left–right, orange/green: finger–palm)",
        fontsize=9,
    )
    return fig


def finger_configuration(hand, finger: str, contact, outward) -> np.ndarray | None:
    """Joint angles (3,) [rad] of ``finger`` touching the object at ``contact``, or None.

    A round tip's centre sits at ``contact + r_f outward``; a flat pad faces the object
    (its axis along ``-outward``) with the contact on the pad (centre first, then offsets).

    Args:
        hand: a :class:`robots.planar_hand.PlanarHand`.
        finger: ``"left"`` or ``"right"``.
        contact: (2,) contact point in the hand frame [m].
        outward: (2,) outward unit normal of the object at the contact.
    """
    from robots.errors import UnreachableTarget

    f = hand.params.finger(finger)
    c, u = np.asarray(contact, float), np.asarray(outward, float)
    if f.tip == "round":
        targets = [(c + f.tip_radius * u, None)]
    else:
        phi = float(np.arctan2(u[0], -u[1]))  # link axis (-sin phi, cos phi) = -u
        t = np.array([u[1], -u[0]])
        targets = [(c + o * f.pad_half_width * t, phi) for o in (0.0, 0.5, -0.5, 0.9, -0.9)]
    for position, angle in targets:
        try:
            return hand.inverse_kinematics(finger, position, angle=angle)
        except UnreachableTarget:
            continue
    return None


def _draw_fingers(ax, hand, who_at: dict, colors: dict) -> None:
    """The links of each finger at its contact (``{finger: (point, outward)}``) [mm]."""
    from matplotlib.patches import Circle

    q = np.zeros(6)
    for finger, (point, outward) in who_at.items():
        qf = finger_configuration(hand, finger, point, outward)
        if qf is None:
            continue
        q[hand.finger_slice(finger)] = qf
        pts = hand.finger_points(q, finger) * 1e3
        ax.plot(pts[:, 0], pts[:, 1], "-o", color=colors[finger], lw=2.5, ms=3, alpha=0.8)
        f, pose = hand.params.finger(finger), hand.fingertip_pose(q, finger)
        if f.tip == "round":
            ax.add_patch(
                Circle(
                    pose.position * 1e3, f.tip_radius * 1e3, fc="none", ec=colors[finger], lw=1.5
                )
            )
        else:
            t = np.array([pose.axis[1], -pose.axis[0]]) * f.pad_half_width
            seg = np.array([pose.position - t, pose.position + t]) * 1e3
            ax.plot(seg[:, 0], seg[:, 1], color=colors[finger], lw=5, solid_capstyle="butt")


def plot_gait_phases(profile, gait, problem, *, hand=None, max_phases: int = 3):
    """The hand and the object on the palm at the end of each phase of the first cycle.

    Args:
        profile: the object's closed profile (object frame) [m].
        gait: a feasible :class:`planner.grasp.gait.Gait`.
        problem: its :class:`planner.grasp.gait.GaitProblem` (object placements).
        hand: the :class:`robots.planar_hand.PlanarHand` whose fingers (links and tips) are
            drawn at their contacts (solved by inverse kinematics); ``None``: contacts only.
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
        at = {}
        for who in ("left", "right", "palm"):
            th = ph.end[who]
            if not np.isfinite(th):
                continue
            p, n_in = profile_contacts(profile, [th])
            pw = (p @ R.T + t)[0] * 1e3
            if who != "palm":
                at[who] = ((p @ R.T + t)[0], -(n_in @ R.T)[0])
            holding = who in ph.holding
            state = "holds" if holding else ("touches" if who == "palm" else "relocated")
            ax.plot(*pw, "o" if holding else "x", color=colors[who], ms=8, label=f"{who} ({state})")
        if hand is not None:
            _draw_fingers(ax, hand, at, colors)
        ax.set_aspect("equal")
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.set_title(
            f"phase {ph.phase}: {'+'.join(ph.holding)}\nrotation {np.rad2deg(ph.rotation):.0f}°",
            fontsize=9,
        )
        ax.legend(fontsize=7, loc="upper right")
    fig.suptitle("Hand and grasps at the end of each phase of the first gait cycle (palm: y = 0)")
    fig.tight_layout()
    return fig


__all__ = [
    "finger_configuration",
    "phase_segment",
    "plot_gait_map",
    "plot_gait_phases",
    "plot_grasp_map",
]
