"""Figures of an exploration: top view, time series, a 3-D view of the finger (Fig. 4.5)."""

from __future__ import annotations

import numpy as np

__all__ = ["finger_view", "time_series", "top_view"]

_COLORS = ("tab:red", "tab:blue", "tab:green", "tab:purple", "tab:orange", "tab:brown")


def top_view(result, plate, region, truth=None, title: str = ""):
    """Plate heights, true outlines/skeletons, the path, traced boundaries and skeletons."""
    import matplotlib.pyplot as plt

    from planner.exploration.surface.plates import plate_height

    reg = np.asarray(region, float)
    u = np.linspace(reg[0, 0], reg[0, 1], 160)
    v = np.linspace(reg[1, 0], reg[1, 1], 160)
    U, V = np.meshgrid(u, v, indexing="ij")
    H = plate_height(plate)(U, V)
    fig, ax = plt.subplots(figsize=(7, 6.5))
    ax.contourf(U * 1e3, V * 1e3, H * 1e3, levels=20, cmap="Greys", alpha=0.55)
    for t in truth or ():
        for ln in t.outline:
            ax.plot(ln[:, 0] * 1e3, ln[:, 1] * 1e3, "k--", lw=0.8)
        sk = np.atleast_2d(t.skeleton)
        ax.plot(sk[:, 0] * 1e3, sk[:, 1] * 1e3, "k:", lw=1.0, marker="x" if len(sk) == 1 else "")
    P = result.path
    ax.plot(P[:, 0] * 1e3, P[:, 1] * 1e3, color="0.45", lw=0.6, label="fingertip centre")
    for i, f in enumerate(result.features):
        c = _COLORS[i % len(_COLORS)]
        if len(f.boundary):
            ax.plot(f.boundary[:, 0] * 1e3, f.boundary[:, 1] * 1e3, ".", ms=1.5, color=c)
        if f.skeleton is not None and len(f.skeleton.points):
            sp = f.skeleton.points * 1e3
            for a, b in f.skeleton.edges:
                ax.plot(sp[[a, b], 0], sp[[a, b], 1], "-", color=c, lw=2)
            if len(f.skeleton.edges) == 0:
                ax.plot(sp[:, 0], sp[:, 1], "o", color=c)
        ax.annotate(
            f"{f.kind} ({f.confidence:.2f})", f.centre * 1e3, color=c, fontsize=8, weight="bold"
        )
    gs = result.global_skeleton
    if gs is not None:
        gp = gs.points * 1e3
        for a, b in gs.edges:
            ax.plot(gp[[a, b], 0], gp[[a, b], 1], "-", color="tab:cyan", lw=1.2)
    ax.set_xlim(reg[0] * 1e3)
    ax.set_ylim(reg[1] * 1e3)
    ax.set_aspect("equal")
    ax.set_xlabel("u [mm] (plate frame)")
    ax.set_ylabel("v [mm]")
    ax.set_title(title or "exploration: top view")
    ax.legend(loc="upper right", fontsize=7)
    fig.tight_layout()
    return fig


def time_series(result, normal_force: float, title: str = ""):
    """Normal force, speed, OWTS intensity and phases against time, with the events."""
    import matplotlib.pyplot as plt

    log = result.log
    t = result.t
    fig, axs = plt.subplots(3, 1, figsize=(8, 6.5), sharex=True)
    if log is not None and log.normal_force.size:
        axs[0].plot(log.t, log.normal_force.sum(axis=1), lw=0.7, label="contact force (sim)")
    axs[0].axhline(normal_force, color="k", ls="--", lw=0.8, label="f_des")
    axs[0].set_ylabel("normal force [N]")
    axs[0].legend(fontsize=7)
    if len(t) > 2:
        v = np.hypot(*np.gradient(result.path[:, :2], t, axis=0).T)
        axs[1].plot(t, v * 1e3, lw=0.7)
    axs[1].set_ylabel("speed [mm/s]")
    axs[2].step(t, result.phase, where="post", lw=0.8)
    axs[2].set_yticks(range(len(result.phases)))
    axs[2].set_yticklabels(result.phases, fontsize=7)
    axs[2].set_xlabel("time [s]")
    for e in result.events:
        if e.kind in (
            "feature_detected",
            "feature_identified",
            "feature_relabelled",
            "end_reached",
            "stopped",
        ):
            for ax in axs:
                ax.axvline(e.t, color="tab:red", lw=0.5, alpha=0.6)
    fig.suptitle(title or "exploration: time series")
    fig.tight_layout()
    return fig


def _finger_points(gm, theta) -> np.ndarray:
    """Polyline base - P1 - endpoint and P2 - joint of the 3GM at ``theta`` (WCS) [m]."""
    p = gm.params
    st = gm.state(theta)
    t1, t2, t3 = theta
    c3, s3 = np.cos(t3), np.sin(t3)

    def w(r, z):
        rh = r + p["h2"]
        return np.array([rh * c3 + p["h3"] * s3, rh * s3 - p["h3"] * c3, z])

    P1 = (p["l1"] * np.cos(t1), p["l1"] * np.sin(t1))
    P2 = (p["l2"] * np.cos(t2), -p["h1"] + p["l2"] * np.sin(t2))
    J = (P1[0] + p["l4"] * np.cos(st.gamma1), P1[1] + p["l4"] * np.sin(st.gamma1))
    E = (P1[0] + p["l5"] * np.cos(st.gamma1), P1[1] + p["l5"] * np.sin(st.gamma1))
    return np.array([w(0, 0), w(*P1), w(*J), w(*E), [np.nan] * 3, w(0, -p["h1"]), w(*P2), w(*J)])


def finger_view(result, plate, region, gm, title: str = ""):
    """3-D view of the 3GM over the plate (like Fig. 4.5), the path and traced boundaries."""
    import matplotlib.pyplot as plt

    from planner.exploration.surface.placement import to_world
    from planner.exploration.surface.plates import plate_height

    reg = np.asarray(region, float)
    u = np.linspace(reg[0, 0], reg[0, 1], 40)
    v = np.linspace(reg[1, 0], reg[1, 1], 40)
    U, V = np.meshgrid(u, v, indexing="ij")
    W = to_world(result.pose, np.stack([U, V, plate_height(plate)(U, V)], -1))
    fig = plt.figure(figsize=(7.5, 6))
    ax = fig.add_subplot(projection="3d")
    ax.plot_surface(*(W[..., i] * 1e3 for i in range(3)), cmap="Greys", alpha=0.5, lw=0)
    P = to_world(result.pose, result.path)
    ax.plot(*(P[:, i] * 1e3 for i in range(3)), color="tab:blue", lw=0.6)
    for i, f in enumerate(result.features):
        if len(f.boundary):
            B = to_world(result.pose, np.column_stack([f.boundary, np.zeros(len(f.boundary))]))
            ax.plot(*(B[:, j] * 1e3 for j in range(3)), ".", ms=1, color=_COLORS[i % 6])
    log = result.log
    if log is not None and len(log.q):
        for k in np.linspace(0, len(log.q) - 1, 3).astype(int):
            F = _finger_points(gm, log.q[k])
            ax.plot(*(F[:, j] * 1e3 for j in range(3)), "-o", color="tab:orange", ms=2, lw=1.5)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    ax.set_title(title or "the 3GM exploring the plate (cf. Fig. 4.5)")
    fig.tight_layout()
    return fig
