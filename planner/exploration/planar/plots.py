"""Figures of an executed gait (thesis ch. 2): Fig. 2.12-like snapshots, Fig. 2.14-like force
traces with phase bands and tactile images, Fig. 2.10-like commanded vs actual contacts, a
phase/event timeline, and the optional animation (GIF bytes).

Every function takes an :class:`planner.exploration.planar.ExplorationResult`, also a failed
or truncated one (the figures then show what ran up to the end), and returns a matplotlib
Figure (or bytes for the GIF).
"""

from __future__ import annotations

import io
import math

import numpy as np

#: phase band colours (Fig. 2.3 phases 1/2/3)
_COLORS = {1: "#dbe9f6", 2: "#fde5cc", 3: "#dff2dc"}
#: the pad is "at the ridge" within this polar angle of it (ridge half-width ~2.3 deg) [rad]
RIDGE_WINDOW = math.radians(4.0)
#: event kinds marked on the timeline, with their markers
_EVENT_MARKS = {
    "transition_4": "v",
    "deviation": "x",
    "no_plan": "s",
    "sim": "D",
    "end": "*",
    "prior": "|",
}
#: event kinds that repeat what the phase bars show
_PHASE_EVENTS = ("phase_end", "phase")


def _outline(profile, pose) -> np.ndarray:
    """(N, 2) outline of ``profile`` at ``pose`` = (x, y, angle) [m, m, rad] in the world."""
    P = profile.sample(1e-3).points
    c, s = math.cos(pose[2]), math.sin(pose[2])
    x = pose[0] + c * P[:, 0] - s * P[:, 1]
    return np.column_stack([x, pose[1] + s * P[:, 0] + c * P[:, 1]])


def _draw_object(ax, profile, pose, style: str, alpha: float) -> np.ndarray:
    """Object outline and a radius marking its frame's x axis (rotation is visible on round
    objects too); returns the drawn points."""
    o = _outline(profile, pose)
    ax.plot(o[:, 0], o[:, 1], style, color="tab:green", lw=1.2, alpha=alpha)
    r = 0.6 * float(np.min(np.hypot(o[:, 0] - pose[0], o[:, 1] - pose[1])))
    ax.plot([pose[0], pose[0] + r * math.cos(pose[2])], [pose[1], pose[1] + r * math.sin(pose[2])],
            style, color="tab:green", lw=0.8, alpha=alpha)  # fmt: skip
    return o


def _draw_hand(ax, hand, q, style: str, alpha: float) -> np.ndarray:
    """Finger links and fingertips (round tip: circle, flat pad: thick segment); returns
    the drawn points."""
    pts = []
    for f in ("left", "right"):
        links = hand.finger_points(q, f)
        pts.append(links)
        ax.plot(links[:, 0], links[:, 1], style, color="0.2", lw=1.5, alpha=alpha)
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
    return np.vstack(pts)


def _row(log, t: float) -> int:
    """Index of the log row at time ``t`` [s] (clipped)."""
    return int(np.clip(np.searchsorted(log.t, t), 0, max(len(log.t) - 1, 0)))


def _pick(items: list, count: int) -> list:
    """At most ``count`` items spread evenly, always with the first and the last."""
    if len(items) <= count:
        return items
    idx = np.unique(np.linspace(0, len(items) - 1, count).round().astype(int))
    return [items[i] for i in idx]


def _scene(ax, hand, profile, log, i: int, style: str, alpha: float) -> np.ndarray:
    a = _draw_hand(ax, hand, log.q[i], style, alpha)
    return np.vstack([a, _draw_object(ax, profile, log.poses["object"][i], style, alpha)])


def _limits(points: np.ndarray, palm: float) -> tuple[tuple[float, float], tuple[float, float]]:
    """Equal-margin axis limits around the drawn points and the palm [m]."""
    lo = np.minimum(points.min(axis=0), [-palm, 0.0]) - 0.01
    hi = np.maximum(points.max(axis=0), [palm, 0.0]) + 0.01
    return (float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1]))


def plot_snapshots(result, profile, hand, max_panels: int = 12):
    """Fig. 2.12: hand links, fingertips, object and palm at the start (dashed, faint) and
    the end (solid) of each phase; with more than ``max_panels`` phases, an even selection
    (first and last included). The green radius marks the object frame's x axis."""
    import matplotlib.pyplot as plt

    log = result.log
    phases = _pick(list(result.phases), max_panels)
    n = max(len(phases), 1)
    cols = min(n, 6)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(2.9 * cols, 2.9 * rows + 0.3), squeeze=False)
    w = hand.params.palm_half_width
    drawn = [np.zeros((0, 2))]
    for ax, ph in zip(axes.flat, phases, strict=False):
        for t, style, alpha in ((ph.start, "--", 0.45), (ph.end, "-", 1.0)):
            drawn.append(_scene(ax, hand, profile, log, _row(log, t), style, alpha))
        ax.plot([-w, w], [0, 0], "k-", lw=3)
        skip = " (transition 4)" if ph.skip else ""
        ax.set_title(f"phase {ph.phase}{skip}, {ph.start:.2f}-{ph.end:.2f} s\n"
                     f"{math.degrees(ph.rotation):+.1f} deg, {ph.event}", fontsize=7)  # fmt: skip
    if not phases:
        axes[0, 0].text(0.5, 0.5, "no phase executed", ha="center", transform=axes[0, 0].transAxes)
    xlim, ylim = _limits(np.vstack(drawn) if len(drawn) > 1 else np.zeros((1, 2)), w)
    for k, ax in enumerate(axes.flat):
        if k >= len(phases) and phases:
            ax.axis("off")
            continue
        ax.set_aspect("equal")
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        ax.tick_params(labelsize=6)
    aspect = (ylim[1] - ylim[0]) / (xlim[1] - xlim[0])
    fig.set_size_inches(2.9 * cols, rows * (2.9 * aspect + 0.55) + 0.3)
    fig.suptitle(f"gait snapshots ({len(result.phases)} phases; dashed: phase start, solid: "
                 f"end) - {result.status}", fontsize=8)  # fmt: skip
    fig.tight_layout()
    return fig


def _bands(ax, phases) -> None:
    for ph in phases:
        ax.axvspan(ph.start, ph.end, color=_COLORS[ph.phase], lw=0)


def _band_legend(ax, phases) -> None:
    from matplotlib.patches import Patch

    kinds = sorted({ph.phase for ph in phases})
    handles = [Patch(color=_COLORS[k], label=f"phase {k}") for k in kinds]
    ax.legend(handles=handles + ax.get_legend_handles_labels()[0], fontsize=7,
              loc="upper right", ncol=2)  # fmt: skip


def left_forces(trace: dict) -> tuple[np.ndarray, np.ndarray]:
    """The left finger's sensed normal and tangential contact force [N] over ``trace["t"]``:
    normal positive when pressing, tangential positive along the object's clockwise
    tangent (the strain-gauge forces ``fLx, fLy`` projected on the sensed normal)."""
    n = np.column_stack([trace["nLx"], trace["nLy"]])
    f = np.column_stack([trace["fLx"], trace["fLy"]])
    tang = np.column_stack([n[:, 1], -n[:, 0]])
    return -np.sum(f * n, axis=1), np.sum(f * tang, axis=1)


def ridge_distance(trace: dict, ridge_angle: float, theta=None) -> np.ndarray:
    """Polar-angle distance [rad] of the left pad's sensed contact from the ridge in the
    object frame, per trace row; ``theta``: (N,) sensed object rotation [rad] per row
    (default the controller's ``trace["theta"]``; better
    :func:`planner.exploration.planar.metrics.object_rotation`)."""
    th = trace["theta"] if theta is None else np.asarray(theta, float)
    a = np.arctan2(trace["pLy"] - trace["cy"], trace["pLx"] - trace["cx"]) - th
    return np.abs(np.angle(np.exp(1j * (a - ridge_angle))))


def plot_forces(result, ridge_angle: float | None = None, images: int = 4, theta=None):
    """Fig. 2.14: the left finger's normal and tangential force vs time (strain gauges,
    :func:`left_forces`) over the phase bands, the rows where the pad touches the ridge
    (``ridge_angle`` [rad] given) marked in red, and ``images`` tactile images of the left
    pad (those at the ridge plus one far from it; evenly spread without a ridge), their
    times marked a, b, c, ... on the force axis. ``theta``: see :func:`ridge_distance`."""
    import matplotlib.pyplot as plt

    tr = result.trace
    fig = plt.figure(figsize=(8, 5.2))
    ax = fig.add_axes((0.08, 0.09, 0.88, 0.5))
    _bands(ax, result.phases)
    t = tr.get("t", np.zeros(0))
    if len(t):
        fn, ft = left_forces(tr)
        ax.plot(t, fn, label="normal [N]", color="tab:blue", lw=1)
        ax.plot(t, ft, label="tangential [N]", color="tab:orange", lw=1)
        if ridge_angle is not None:
            d = ridge_distance(tr, ridge_angle, theta)
            at = (d < RIDGE_WINDOW) & (tr["pad_touch"] > 0)
            if at.any():
                ax.plot(t[at], fn[at], ".", ms=2, color="tab:red", label="pad at the ridge")
    else:
        ax.text(0.5, 0.5, "no control step executed", ha="center", transform=ax.transAxes)
    ax.axhline(0, color="0.5", lw=0.5)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("left finger force [N]")
    imgs, ti = tr.get("images", np.zeros((0, 8, 8))), tr.get("image_t", np.zeros(0))
    if len(imgs):
        pick = pick_images(tr, ridge_angle, images, theta)
        vmax = max(float(np.max(imgs[pick])), 1e-9)
        for j, k in enumerate(pick):
            label = chr(ord("a") + j)
            a = fig.add_axes((0.08 + j * 0.22, 0.68, 0.18, 0.27))
            a.imshow(imgs[k], cmap="gray_r", vmin=0, vmax=vmax)
            a.set_title(f"({label}) t = {ti[k]:.2f} s", fontsize=7)
            a.set_xticks([])
            a.set_yticks([])
            ax.axvline(ti[k], color="k", lw=0.6, ls=":")
            ax.annotate(label, (ti[k], 1.0), xycoords=("data", "axes fraction"), fontsize=7,
                        ha="center", va="bottom")  # fmt: skip
    _band_legend(ax, result.phases)
    return fig


def pick_images(trace: dict, ridge_angle: float | None, count: int, theta=None) -> list[int]:
    """Indices of ``count`` tactile images of ``trace["images"]``: with a ridge, those whose
    pad contact is closest to it plus the farthest one (the round pattern to compare
    with); without, evenly spread in time."""
    ti = trace.get("image_t", np.zeros(0))
    if len(ti) == 0 or count <= 0:
        return []
    if ridge_angle is None or not len(trace["t"]):
        return list(np.unique(np.linspace(0, len(ti) - 1, min(count, len(ti))).astype(int)))
    rows = np.searchsorted(trace["t"], ti).clip(0, len(trace["t"]) - 1)
    d = ridge_distance(trace, ridge_angle, theta)[rows]
    d = np.where(trace["pad_touch"][rows] > 0, d, np.inf)  # images of a touching pad only
    if not np.isfinite(d).any():
        return list(np.unique(np.linspace(0, len(ti) - 1, min(count, len(ti))).astype(int)))
    gap = max(0.02, (ti[-1] - ti[0]) / 50.0)  # spread the picks over the ridge crossing [s]
    near: list[int] = []
    for k in np.argsort(d):
        if len(near) >= max(count - 1, 1) or not np.isfinite(d[k]):
            break
        if all(abs(ti[k] - ti[j]) >= gap for j in near):
            near.append(int(k))
    far = int(np.argmax(np.where(np.isfinite(d), d, -1.0)))
    return sorted(set(near + [far]))[:count]


def tactile_elongation(image: np.ndarray) -> float:
    """How line-like a tactile image is: sqrt of the ratio of the principal second moments
    of its pressure distribution, each plus 1/12 taxel^2 (a single taxel's own spread), so
    a round patch gives ~1 and a line of taxels several; NaN for an empty image. One image
    of :func:`.sensed_features.image_shape` (the detector's measure).

    Args:
        image: (rows, cols) taxel pressures [Pa] (negative values count as 0).
    """
    from planner.exploration.planar.sensed_features import image_shape

    return float(image_shape(np.asarray(image, float)[None])[0][0])


def fig214_measures(result, ridge_angle: float | None, window: float = 0.2, theta=None) -> dict:
    """The claims of Fig. 2.14 measured on the sensed data of the left finger.

    * ``tangential_sign_changes_2to3``: at how many phase 2 -> 3 switches the mean
      tangential force (:func:`left_forces`) of the last ``window`` [s] of phase 2 and of
      ``window`` after the first 0.1 s of phase 3 have opposite signs, over the switches;
    * with ``ridge_angle`` [rad]: the median tangential force magnitude [N] and the median
      :func:`tactile_elongation` of the pad touching the object while exploring (phase 3)
      at the ridge (within :data:`RIDGE_WINDOW`) and away from it (``theta``: see
      :func:`ridge_distance`).
    """
    tr, phases = result.trace, list(result.phases)
    out: dict = {}
    t = tr.get("t", np.zeros(0))
    if not len(t):
        return out
    fn, ft = left_forces(tr)
    changes, switches = 0, 0
    for a, b in zip(phases, phases[1:], strict=False):
        if (a.kind, b.kind) != (2, 3):
            continue
        before = ft[(t >= a.end - window) & (t <= a.end)]
        after = ft[(t >= b.start + 0.1) & (t <= b.start + 0.1 + window)]
        if before.size and after.size:
            switches += 1
            changes += int(np.sign(before.mean()) * np.sign(after.mean()) < 0)
    out["tangential_sign_changes_2to3"] = f"{changes}/{switches}"
    if ridge_angle is None:
        return out
    touch = (tr["kind"] == 3) & (tr["pad_touch"] > 0)
    at = ridge_distance(tr, ridge_angle, theta) < RIDGE_WINDOW
    for name, sel in (("at_ridge", touch & at), ("off_ridge", touch & ~at)):
        out[f"tangential_{name}_N"] = float(np.median(np.abs(ft[sel]))) if sel.any() else None
    ti, imgs = tr.get("image_t", np.zeros(0)), tr.get("images", np.zeros((0, 8, 8)))
    if len(ti):
        rows = np.searchsorted(t, ti).clip(0, len(t) - 1)
        for name, sel in (("at_ridge", (touch & at)[rows]), ("off_ridge", (touch & ~at)[rows])):
            el = [tactile_elongation(im) for im in imgs[sel]]
            el = [e for e in el if np.isfinite(e)]
            out[f"tactile_elongation_{name}"] = float(np.median(el)) if el else None
    return out


def plot_contacts(result):
    """Fig. 2.10: commanded (dashed) vs actual (sensed: tactile centroid on the left pad,
    contact arclength on the right tip) contact locations, over the phase bands."""
    import matplotlib.pyplot as plt

    tr = result.trace
    fig, axes = plt.subplots(2, 1, figsize=(7, 4.5), sharex=True)
    pairs = (("u", "u_des", "left pad u [mm]"), ("sR", "sR_des", "right tip s [mm]"))
    for ax, (act, cmd, label) in zip(axes, pairs, strict=True):
        _bands(ax, result.phases)
        if len(tr.get("t", ())):
            ax.plot(tr["t"], 1e3 * tr[cmd], "--", color="k", lw=1, label="commanded")
            ax.plot(tr["t"], 1e3 * tr[act], color="tab:red", lw=1, label="actual (sensed)")
            err = 1e3 * np.sqrt(np.nanmean((tr[act] - tr[cmd]) ** 2))
            ax.set_title(f"RMS error {err:.2f} mm", fontsize=7, loc="left")
        ax.set_ylabel(label)
        _band_legend(ax, result.phases)
    axes[-1].set_xlabel("time [s]")
    fig.tight_layout()
    return fig


def plot_timeline(result):
    """Phase/event timeline: one bar per phase (hatched when entered by transition 4)
    labelled with the event that ended it, and the gait's events (transition 4,
    deviations from the plan, failed plans, simulator messages, the end) as markers."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 2.8))
    span = max((result.phases[-1].end - result.phases[0].start) if result.phases else 1.0, 1e-9)
    for ph in result.phases:
        y = {1: 3, 2: 2, 3: 1}[ph.phase]
        ax.barh(y, ph.end - ph.start, left=ph.start, color=_COLORS[ph.phase],
                edgecolor="k" if ph.skip else "0.6", hatch="//" if ph.skip else None)  # fmt: skip
        if (ph.end - ph.start) / span > 0.08 or ph is result.phases[-1]:  # room for a label
            ax.text(ph.end, y, ph.event, fontsize=6, va="center", ha="right")
    seen = set()
    for ev in result.events:
        kind = str(ev.get("kind", ""))
        if kind in _PHASE_EVENTS:  # already drawn: the label at the end of its phase bar
            continue
        mark = _EVENT_MARKS.get(kind, "o")
        ax.plot(float(ev.get("t", 0.0)), 0, mark, color="tab:red" if kind != "end" else "k",
                label=kind if kind not in seen else None)  # fmt: skip
        seen.add(kind)
    ax.set_yticks([3, 2, 1, 0], ["phase 1", "phase 2", "phase 3", "events"])
    ax.set_ylim(-0.6, 3.6)
    ax.set_xlabel("time [s]")
    n4 = sum(1 for p in result.phases if p.skip)
    turn = math.degrees(result.rotation)
    head = f"{len(result.phases)} phases, {n4} by transition 4, {turn:+.1f} deg"
    ax.set_title(f"{result.status}: {result.reason} ({head})", fontsize=8)
    if seen:
        ax.legend(fontsize=6, loc="lower right", ncol=len(seen))
    fig.tight_layout()
    return fig


def _phase_at(phases, t: float) -> str:
    for ph in phases:
        if ph.start <= t <= ph.end:
            return f"phase {ph.phase}" + (" (4)" if ph.skip else "")
    return ""


def animation_gif(result, profile, hand, frames: int = 80, fps: int = 12) -> bytes:
    """GIF bytes of the run (matplotlib + pillow): hand, object and palm at ``frames``
    instants evenly spread over the log, ``fps`` frames per second."""
    import matplotlib.pyplot as plt
    from PIL import Image

    log = result.log
    if len(log.t) == 0:
        raise ValueError("animation_gif: the run has no logged step")
    idx = np.unique(np.linspace(0, len(log.t) - 1, min(frames, len(log.t))).astype(int))
    w = hand.params.palm_half_width
    fig, ax = plt.subplots(figsize=(3.4, 3.0), dpi=80)
    pts = np.vstack(
        [_scene(ax, hand, profile, log, i, "-", 1.0) for i in idx[:: max(len(idx) // 8, 1)]]
    )
    xlim, ylim = _limits(pts, w)
    fig.set_size_inches(3.4, 3.4 * (ylim[1] - ylim[0]) / (xlim[1] - xlim[0]) + 0.3)
    fig.subplots_adjust(left=0.01, right=0.99, bottom=0.01, top=0.9)
    images = []
    for i in idx:
        ax.clear()
        _scene(ax, hand, profile, log, int(i), "-", 1.0)
        ax.plot([-w, w], [0, 0], "k-", lw=3)
        ax.set_aspect("equal")
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        ax.set_title(f"t = {log.t[i]:.2f} s  {_phase_at(result.phases, log.t[i])}", fontsize=8)
        ax.axis("off")
        buf = io.BytesIO()
        fig.savefig(buf, format="png")
        buf.seek(0)
        images.append(Image.open(buf).convert("P", palette=Image.Palette.ADAPTIVE))
    plt.close(fig)
    out = io.BytesIO()
    images[0].save(out, format="GIF", save_all=True, append_images=images[1:],
                   duration=int(1000 / fps), loop=0)  # fmt: skip
    return out.getvalue()


__all__ = [
    "RIDGE_WINDOW",
    "animation_gif",
    "fig214_measures",
    "left_forces",
    "pick_images",
    "plot_contacts",
    "plot_forces",
    "plot_snapshots",
    "plot_timeline",
    "ridge_distance",
    "tactile_elongation",
]
