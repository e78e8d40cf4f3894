"""Figures of feature detection (thesis Figs. 3.12, B.5-B.6): the trace with the features
marked, the curvature signals with their thresholds, the multiscale features, and the
filter comparison of App. B.4."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from planner.detection.types import CurvatureSignal
from planner.geometry.features import CurvatureFeature

_COLORS = {1: "tab:orange", 2: "tab:green", 3: "tab:red", 4: "tab:purple"}


def trace_figure(
    centers: np.ndarray,
    surfaces: Mapping[int, np.ndarray],
    features: Mapping[int, Sequence[CurvatureFeature]],
    tip_radius: float,
    *,
    profile: np.ndarray | None = None,
    truth: Sequence | None = None,
    title: str = "Feature detection",
):
    """Fingertip-centre path, estimated surfaces and detected features (cf. Fig. 3.12).

    Args:
        centers: (N, 2+) measured fingertip centres [m] (only x, y are drawn).
        surfaces: algorithm -> (M, 2+) estimated surface used by that algorithm [m].
        features: algorithm -> detected features.
        tip_radius: r_f [m] (a fingertip circle is drawn for scale).
        profile: (K, 2) true object profile [m], if known.
        truth: true features (``.sign``, ``.position``), if known.
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle

    fig = Figure(figsize=(12, 5.5))
    axes = [fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)]
    mm = 1e3
    step = max(1, len(centers) // 3000)  # enough points to see the noise, fast to draw
    centers = centers[::step]
    pts = [np.asarray(f.position)[:2] for fs in features.values() for f in fs]
    pts += [np.asarray(f.position)[:2] for f in truth or []]
    for ax in axes:
        ax.plot(
            centers[:, 0] * mm,
            centers[:, 1] * mm,
            ".",
            ms=1,
            color="0.6",
            label="fingertip centre (measured)",
        )
        if profile is not None:
            ax.plot(
                profile[:, 0] * mm,
                profile[:, 1] * mm,
                "-",
                color="k",
                lw=1.2,
                label="object profile (truth)",
            )
        for alg, surf in surfaces.items():
            ax.plot(
                surf[:, 0] * mm,
                surf[:, 1] * mm,
                "-",
                lw=0.8,
                color=_COLORS[alg],
                alpha=0.7,
                label=f"estimated surface, alg. {alg}",
            )
        for alg, feats in features.items():
            for f in feats:
                p = np.asarray(f.position) * mm
                ax.plot(
                    p[0],
                    p[1],
                    "^" if f.sign > 0 else "v",
                    ms=9,
                    mfc="none",
                    mec=_COLORS[alg],
                    mew=1.5,
                )
        for f in truth or []:
            p = np.asarray(f.position) * mm
            ax.plot(p[0], p[1], "o", ms=4, color="k")
    if truth:
        axes[0].plot([], [], "o", ms=4, color="k", label="true feature (observable)")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.grid(True, lw=0.3)
    mid = centers[len(centers) // 2, :2] * mm
    axes[0].add_patch(Circle(mid, tip_radius * mm, fill=False, ls="--", color="0.3", lw=0.8))
    axes[0].plot([], [], "^", mfc="none", mec="k", label="convex feature (+)")
    axes[0].plot([], [], "v", mfc="none", mec="k", label="concave feature (-)")
    axes[0].set_title(title, fontsize=10)
    axes[0].legend(fontsize=7, loc="best")
    if pts:
        c = np.mean(pts, axis=0) * mm
        half = max(0.6 * tip_radius * mm, float(np.ptp(np.array(pts) * mm, axis=0).max()))
        axes[1].set_xlim(c[0] - half, c[0] + half)
        axes[1].set_ylim(c[1] - half, c[1] + half)
        axes[1].set_aspect("equal", adjustable="box")
    axes[1].set_title("zoom on the features", fontsize=10)
    fig.subplots_adjust(left=0.06, right=0.98, bottom=0.1, top=0.93, wspace=0.18)
    return fig


def signal_figure(
    signals: Mapping[int, CurvatureSignal],
    features: Mapping[int, Sequence[CurvatureFeature]],
    title: str = "Curvature signals and thresholds",
):
    """One panel per algorithm: its curvature signal against arclength with thresholds and
    feature regions shaded (cf. Figs. B.5-B.6)."""
    from matplotlib.figure import Figure

    n = max(1, len(signals))
    fig = Figure(figsize=(8, 2.2 * n + 0.6))
    axes = [fig.add_subplot(n, 1, i + 1) for i in range(n)]
    for ax, (alg, sig) in zip(axes, signals.items(), strict=False):
        step = max(1, sig.s.size // 4000)
        s = sig.s[::step] * 1e3
        k = np.clip(sig.curvature[::step], -20 * sig.upper, 20 * sig.upper)
        ax.plot(s, k, "-", lw=0.8, color=_COLORS[alg])
        ax.axhline(sig.upper, color="k", ls="--", lw=0.7)
        ax.axhline(sig.lower, color="k", ls=":", lw=0.7)
        for f in features.get(alg, []):
            ax.axvspan(
                f.start * 1e3,
                max(f.end * 1e3, f.start * 1e3 + 0.05),
                color="tab:red" if f.sign > 0 else "tab:blue",
                alpha=0.25,
            )
        lim = max(3 * sig.upper, float(np.percentile(np.abs(k), 99.5)) * 1.1)
        ax.set_ylim(-lim, lim)
        ax.set_ylabel("k [1/m]")
        ax.set_title(
            f"algorithm {alg}: thresholds {sig.upper:.3g} / {sig.lower:.3g} 1/m", fontsize=9
        )
        ax.grid(True, lw=0.3)
    axes[-1].set_xlabel("arclength along the fingertip-centre path [mm]")
    fig.suptitle(title)
    fig.subplots_adjust(
        left=0.1,
        right=0.97,
        bottom=0.6 / fig.get_figheight(),
        top=1 - 0.8 / fig.get_figheight(),
        hspace=0.45,
    )
    return fig


def multiscale_figure(
    features: Mapping[float, Sequence[CurvatureFeature]],
    macros: Mapping[float, Sequence[str]],
    title: str = "Multiscale features",
):
    """The features seen by each fingertip radius along the path (§3.2.2): one row per
    radius, convex regions red, concave blue, peaks marked, macro kinds written beside.

    Args:
        features: radius [m] -> its features (arclengths along the real centre path [m]).
        macros: radius [m] -> the kinds of its macro features.
    """
    from matplotlib.figure import Figure

    radii = sorted(features)
    fig = Figure(figsize=(9, 1.0 + 0.7 * len(radii)))
    ax = fig.add_subplot(1, 1, 1)
    for row, r in enumerate(radii):
        for f in features[r]:
            color = "tab:red" if f.sign > 0 else "tab:blue"
            a, b = f.start * 1e3, max(f.end * 1e3, f.start * 1e3 + 0.1)
            ax.fill_between([a, b], row - 0.3, row + 0.3, color=color, alpha=0.35, lw=0)
            ax.plot(f.peak * 1e3, row, "^" if f.sign > 0 else "v", color=color, ms=7)
        kinds = ", ".join(macros.get(r, [])) or "no feature"
        ax.annotate(kinds, (1.01, row), xycoords=("axes fraction", "data"), va="center", fontsize=8)
    ax.set_yticks(range(len(radii)), [f"r = {r * 1e3:g} mm" for r in radii])
    ax.set_ylim(-0.6, len(radii) - 0.4)
    ax.set_xlabel("arclength along the fingertip-centre path [mm]")
    ax.plot([], [], "^", color="tab:red", label="convex (+)")
    ax.plot([], [], "v", color="tab:blue", label="concave (-)")
    ax.legend(fontsize=7, loc="upper left")
    ax.grid(True, axis="x", lw=0.3)
    ax.set_title(title, fontsize=10)
    fig.subplots_adjust(left=0.12, right=0.8, bottom=0.6 / fig.get_figheight() + 0.05, top=0.85)
    return fig


def filter_errors_figure(
    filters: Sequence[str], scores: Sequence, windows: Sequence[int], sigmas: Sequence[float]
):
    """False positives + false negatives per trace of the App. B.2 scheme by filter window
    (left) and, for the Gaussian filter, by window and sigma (right; cf. App. B.4).

    Args:
        filters: the filters rated.
        scores: :class:`planner.detection.filter_study.FilterScore` of every setting.
        windows: the windows of the grid [samples].
        sigmas: the Gaussian sigmas of the grid [samples].
    """
    from matplotlib.figure import Figure

    windows, sigmas = list(windows), list(sigmas)

    fig = Figure(figsize=(11, 4.5))
    ax1 = fig.add_subplot(1, 2, 1)
    for m in filters:
        if m in ("gaussian", "none", "dual_point"):
            continue
        ms = [s for s in scores if s.setting.method == m]
        ax1.plot([s.setting.window for s in ms], [s.errors for s in ms], "o-", label=m)
    g = [s for s in scores if s.setting.method == "gaussian"]
    if g:
        best_sig = min(g, key=lambda s: s.errors).setting.sigma
        gs = [s for s in g if s.setting.sigma == best_sig]
        ax1.plot(
            [s.setting.window for s in gs],
            [s.errors for s in gs],
            "s-",
            label=f"gaussian, sigma={best_sig:g}",
        )
    for m in ("none",):
        ms = [s for s in scores if s.setting.method == m]
        if ms:
            ax1.axhline(ms[0].errors, color="0.5", ls=":", label="no filter")
    ax1.set_xlabel("window [samples]")
    ax1.set_ylabel("false positives + false negatives per trace")
    ax1.set_title("App. B.2 scheme errors by filter window")
    ax1.legend(fontsize=8)
    ax1.grid(True, lw=0.3)
    ax2 = fig.add_subplot(1, 2, 2)
    if g:
        mat = np.full((len(sigmas), len(windows)), np.nan)
        for s in g:
            mat[sigmas.index(s.setting.sigma), windows.index(s.setting.window)] = s.errors
        im = ax2.imshow(mat, origin="lower", aspect="auto", cmap="viridis_r")
        ax2.set_xticks(range(len(windows)), [str(w) for w in windows])
        ax2.set_yticks(range(len(sigmas)), [f"{s:g}" for s in sigmas])
        for i in range(len(sigmas)):
            for j in range(len(windows)):
                ax2.text(
                    j,
                    i,
                    f"{mat[i, j]:.1f}",
                    ha="center",
                    va="center",
                    fontsize=7,
                    color="w" if mat[i, j] > np.nanmax(mat) / 2 else "k",
                )
        fig.colorbar(im, ax=ax2, label="FP + FN per trace")
        ax2.set_xlabel("Gaussian window [samples]")
        ax2.set_ylabel("Gaussian sigma [samples]")
        ax2.set_title("Gaussian filter (thesis best: window 25-40, sigma 5-10)", fontsize=9)
    fig.subplots_adjust(left=0.07, right=0.97, bottom=0.12, top=0.92, wspace=0.25)
    return fig


__all__ = ["filter_errors_figure", "multiscale_figure", "signal_figure", "trace_figure"]
