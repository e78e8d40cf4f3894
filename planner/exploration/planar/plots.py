"""Figures of an executed gait: Fig. 2.12-like snapshots, Fig. 2.14-like force traces with
phase bands and tactile images, Fig. 2.10-like commanded vs actual contacts, a timeline;
and the optional animation (GIF bytes)."""

from __future__ import annotations

import io
import math

import numpy as np

_COLORS = {1: "#dbe9f6", 2: "#fde5cc", 3: "#dff2dc"}


def _outline(profile, pose) -> np.ndarray:
    P = profile.sample(1e-3).points
    c, s = math.cos(pose[2]), math.sin(pose[2])
    x = pose[0] + c * P[:, 0] - s * P[:, 1]
    return np.column_stack([x, pose[1] + s * P[:, 0] + c * P[:, 1]])


def _draw_hand(ax, hand, q, style: str, alpha: float) -> None:
    for f in ("left", "right"):
        pts = hand.finger_points(q, f)
        ax.plot(pts[:, 0], pts[:, 1], style, color="0.2", lw=1.5, alpha=alpha)
        pose = hand.fingertip_pose(q, f)
        if hand.params.finger(f).tip == "round":
            r = hand.params.finger(f).tip_radius
            a = np.linspace(0, 2 * np.pi, 60)
            ax.plot(pose.position[0] + r * np.cos(a), pose.position[1] + r * np.sin(a), style,
                    color="tab:red", lw=1, alpha=alpha)  # fmt: skip
        else:
            w = hand.params.finger(f).pad_half_width
            d = np.array([math.cos(pose.angle), math.sin(pose.angle)])
            seg = np.array([pose.position - w * d, pose.position + w * d])
            ax.plot(seg[:, 0], seg[:, 1], style, color="tab:blue", lw=3, alpha=alpha)


def plot_snapshots(result, profile, hand, max_panels: int = 6):
    """Fig. 2.12: hand, fingertips, object and palm at the start (dashed) and end (solid)
    of each phase."""
    import matplotlib.pyplot as plt

    log = result.log
    phases = list(result.phases)[:max_panels]
    n = max(len(phases), 1)
    fig, axes = plt.subplots(1, n, figsize=(3.2 * n, 3.4), squeeze=False)
    w = hand.params.palm_half_width
    for ax, ph in zip(axes[0], phases, strict=False):
        for t, style, alpha in ((ph.start, "--", 0.5), (ph.end, "-", 1.0)):
            i = int(np.clip(np.searchsorted(log.t, t), 0, len(log.t) - 1))
            _draw_hand(ax, hand, log.q[i], style, alpha)
            o = _outline(profile, log.poses["object"][i])
            ax.plot(o[:, 0], o[:, 1], style, color="tab:green", lw=1.2, alpha=alpha)
        ax.plot([-w, w], [0, 0], "k-", lw=3)
        ax.set_aspect("equal")
        ax.set_xlim(-0.13, 0.13)
        ax.set_ylim(-0.01, 0.2)
        skip = " (transition 4)" if ph.skip else ""
        ax.set_title(f"phase {ph.kind}{skip}\n{math.degrees(ph.rotation):+.1f} deg, {ph.event}",
                     fontsize=8)  # fmt: skip
        ax.tick_params(labelsize=7)
    fig.tight_layout()
    return fig


def _bands(ax, phases) -> None:
    for ph in phases:
        ax.axvspan(ph.start, ph.end, color=_COLORS[ph.kind], lw=0)


def plot_forces(result, ridge_angle: float | None = None, images: int = 4):
    """Fig. 2.14: the left finger's normal and tangential force vs time (strain gauges,
    positive tangential = along the object's clockwise tangent), phase bands, and tactile
    images (those closest to the ridge when ``ridge_angle`` [rad] is given)."""
    import matplotlib.pyplot as plt

    tr = result.trace
    fig = plt.figure(figsize=(8, 5))
    ax = fig.add_axes((0.08, 0.1, 0.88, 0.5))
    _bands(ax, result.phases)
    if len(tr["t"]):
        n = np.column_stack([tr["nLx"], tr["nLy"]])
        f = np.column_stack([tr["fLx"], tr["fLy"]])
        fn = -np.sum(f * n, axis=1)
        tang = np.column_stack([n[:, 1], -n[:, 0]])  # clockwise tangent of the object
        ft = np.sum(f * tang, axis=1)
        ax.plot(tr["t"], fn, label="normal [N]", color="tab:blue", lw=1)
        ax.plot(tr["t"], ft, label="tangential [N]", color="tab:orange", lw=1)
    ax.axhline(0, color="0.5", lw=0.5)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("left finger force [N]")
    ax.legend(fontsize=8, loc="upper right")
    imgs, ti = tr.get("images", np.zeros((0, 8, 8))), tr.get("image_t", np.zeros(0))
    if len(imgs):
        pick = _pick_images(result, ti, ridge_angle, images)
        vmax = max(float(np.max(imgs[pick])), 1e-9)
        for j, k in enumerate(pick):
            a = fig.add_axes((0.08 + j * 0.22, 0.68, 0.18, 0.28))
            a.imshow(imgs[k], cmap="gray_r", vmin=0, vmax=vmax)
            a.set_title(f"t = {ti[k]:.2f} s", fontsize=7)
            a.set_xticks([])
            a.set_yticks([])
    return fig


def _pick_images(result, ti, ridge_angle, count):
    tr = result.trace
    if ridge_angle is None or not len(tr["t"]):
        return list(np.linspace(0, len(ti) - 1, min(count, len(ti))).astype(int))
    a = np.arctan2(tr["pLy"] - tr["cy"], tr["pLx"] - tr["cx"]) - tr["theta"]
    d = np.abs(np.angle(np.exp(1j * (a - ridge_angle))))
    rows = np.searchsorted(tr["t"], ti).clip(0, len(tr["t"]) - 1)
    order = np.argsort(d[rows])
    near = sorted(order[: max(count - 1, 1)])
    far = [int(np.argmax(d[rows]))]
    return sorted(set(far + [int(k) for k in near]))[:count]


def plot_contacts(result):
    """Fig. 2.10: commanded vs actual contact locations on the two fingertips (rolling PD)."""
    import matplotlib.pyplot as plt

    tr = result.trace
    fig, axes = plt.subplots(2, 1, figsize=(7, 4.5), sharex=True)
    for ax, (act, cmd, label) in zip(
        axes,
        (("u", "u_des", "left pad u [mm]"), ("sR", "sR_des", "right tip s [mm]")),
        strict=True,
    ):
        _bands(ax, result.phases)
        ax.plot(tr["t"], 1e3 * tr[cmd], "--", color="k", lw=1, label="commanded")
        ax.plot(tr["t"], 1e3 * tr[act], color="tab:red", lw=1, label="actual (sensed)")
        ax.set_ylabel(label)
        ax.legend(fontsize=8)
    axes[-1].set_xlabel("time [s]")
    fig.tight_layout()
    return fig


def plot_timeline(result):
    """Phase/event timeline: one bar per phase, labelled with the event that ended it."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 2.4))
    for ph in result.phases:
        y = {1: 2, 2: 1, 3: 0}[ph.kind]
        ax.barh(y, ph.end - ph.start, left=ph.start, color=_COLORS[ph.kind],
                edgecolor="k" if ph.skip else "0.6", hatch="//" if ph.skip else None)  # fmt: skip
        ax.text(ph.end, y, ph.event, fontsize=6, va="center", ha="right", rotation=0)
    ax.set_yticks([2, 1, 0], ["phase 1", "phase 2", "phase 3"])
    ax.set_xlabel("time [s]")
    ax.set_title(f"{result.status}: {result.reason}", fontsize=8)
    fig.tight_layout()
    return fig


def animation_gif(result, profile, hand, frames: int = 60, fps: int = 15) -> bytes:
    """GIF bytes of the run (matplotlib + pillow): hand, object and palm over time."""
    import matplotlib.pyplot as plt
    from PIL import Image

    log = result.log
    idx = np.linspace(0, len(log.t) - 1, min(frames, len(log.t))).astype(int)
    images = []
    w = hand.params.palm_half_width
    for i in idx:
        fig, ax = plt.subplots(figsize=(3.2, 3.0), dpi=80)
        _draw_hand(ax, hand, log.q[i], "-", 1.0)
        o = _outline(profile, log.poses["object"][i])
        ax.plot(o[:, 0], o[:, 1], "-", color="tab:green")
        ax.plot([-w, w], [0, 0], "k-", lw=3)
        ax.set_aspect("equal")
        ax.set_xlim(-0.13, 0.13)
        ax.set_ylim(-0.01, 0.2)
        ax.set_title(f"t = {log.t[i]:.2f} s", fontsize=8)
        ax.axis("off")
        buf = io.BytesIO()
        fig.savefig(buf, format="png")
        plt.close(fig)
        buf.seek(0)
        images.append(Image.open(buf).convert("P"))
    out = io.BytesIO()
    images[0].save(out, format="GIF", save_all=True, append_images=images[1:],
                   duration=int(1000 / fps), loop=0)  # fmt: skip
    return out.getvalue()


__all__ = ["animation_gif", "plot_contacts", "plot_forces", "plot_snapshots", "plot_timeline"]
