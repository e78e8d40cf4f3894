"""Figures of skeletons (like thesis Figs. 4.11, 4.13, 4.14-4.15); axes in millimetres.

Figures are built with ``matplotlib.figure.Figure`` (no pyplot state, no ``show``).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import shapely

from planner.skeleton.feature import Skeleton, dvma
from planner.skeleton.global_map import GlobalSkeleton

MM = 1e3


def _segments(ax, seg: np.ndarray, **kw) -> None:
    from matplotlib.collections import LineCollection

    if len(seg):
        ax.add_collection(LineCollection(seg * MM, **kw))


def _polygon(ax, geom, **kw) -> None:
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path as MplPath

    for poly in shapely.get_parts(geom):
        if poly.is_empty or poly.geom_type != "Polygon":
            continue
        rings = [np.asarray(poly.exterior.coords)] + [np.asarray(r.coords) for r in poly.interiors]
        verts = np.concatenate(rings) * MM
        codes = np.concatenate(
            [
                [MplPath.MOVETO] + [MplPath.LINETO] * (len(r) - 2) + [MplPath.CLOSEPOLY]
                for r in rings
            ]
        )
        ax.add_patch(PathPatch(MplPath(verts, codes), **kw))


def _frame(ax, pts: np.ndarray, title: str) -> None:
    lo, hi = pts.min(axis=0) * MM, pts.max(axis=0) * MM
    pad = 0.08 * max(hi - lo)
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("u [mm]")
    ax.set_ylabel("v [mm]")
    ax.set_title(title)


def dvma_figure(boundary: np.ndarray, skeleton: Skeleton, title: str = ""):
    """Two panels like Fig. 4.11/4.13: the DVMA of the samples, and the pruned skeleton.

    Args:
        boundary: (M, 2) boundary samples [m].
        skeleton: its pruned skeleton.
        title: figure title.

    Returns:
        matplotlib Figure.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 4.8))
    axes = fig.subplots(1, 2)
    verts, edges = dvma(boundary)
    b = np.asarray(boundary)
    for ax in axes:
        ax.plot(b[:, 0] * MM, b[:, 1] * MM, ".", ms=2.5, color="0.35", label="boundary samples")
    _segments(axes[0], verts[edges], colors="tab:blue", linewidths=0.5, label="Voronoi edges")
    _frame(axes[0], b, f"DVMA: {len(edges)} finite Voronoi edges")
    _segments(
        axes[1], skeleton.segments(), colors="tab:red", linewidths=1.4, label="pruned skeleton"
    )
    bp, ep = skeleton.points[skeleton.branch_points], skeleton.points[skeleton.end_points]
    axes[1].plot(bp[:, 0] * MM, bp[:, 1] * MM, "s", color="k", ms=5, label="branch points")
    axes[1].plot(ep[:, 0] * MM, ep[:, 1] * MM, "o", mfc="none", color="k", ms=5, label="end points")
    _frame(axes[1], b, f"pruned: {len(skeleton.edges)} edges, length {skeleton.length * MM:.1f} mm")
    axes[1].legend(loc="best", fontsize=7)
    if title:
        fig.suptitle(title)
    return fig


def feature_map_figure(
    gs: GlobalSkeleton,
    skeletons: Sequence[Skeleton] = (),
    path: np.ndarray | None = None,
    names: Sequence[str] | None = None,
    title: str = "Feature map",
):
    """Regions, feature boundaries and skeletons, and the global skeleton (Figs. 4.14-4.15).

    Args:
        gs: the global skeleton.
        skeletons: feature skeletons to draw.
        path: optional (P, 2) navigation path [m].
        names: feature names for the legend.
        title: axes title.

    Returns:
        matplotlib Figure.
    """
    from matplotlib import colormaps
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.5, 6.5))
    ax = fig.subplots()
    cmap = colormaps["tab10"]
    names = list(names) if names is not None else [f"feature {i}" for i in range(gs.n_features)]
    for i, reg in enumerate(gs.regions):
        _polygon(ax, reg, facecolor=cmap(i % 10), alpha=0.18, edgecolor="none")
        b = gs.boundaries[i]
        ax.plot(
            b[:, 0] * MM,
            b[:, 1] * MM,
            ".",
            ms=1.5,
            color=cmap(i % 10),
            label=f"{names[i]} ({reg.area * 1e6:.0f} mm²)",
        )
    for sk in skeletons:
        _segments(ax, sk.segments(), colors="k", linewidths=1.2)
    _segments(ax, gs.segments(), colors="tab:red", linewidths=1.6)
    ax.plot([], [], color="k", label="feature skeletons")
    ax.plot(
        [], [], color="tab:red", label=f"global skeleton (clearance {gs.clearance * MM:.2f} mm)"
    )
    if path is not None:
        ax.plot(
            path[:, 0] * MM, path[:, 1] * MM, "--", color="tab:green", lw=2, label="safest path"
        )
        ax.plot(path[[0, -1], 0] * MM, path[[0, -1], 1] * MM, "o", color="tab:green", ms=6)
    dom = np.asarray(gs.domain.exterior.coords)
    _frame(ax, dom, title)
    ax.legend(loc="upper left", fontsize=7, bbox_to_anchor=(1.01, 1.0))
    return fig


__all__ = ["dvma_figure", "feature_map_figure"]
