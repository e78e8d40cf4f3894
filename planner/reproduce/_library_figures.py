"""Save figures built by the library's own plotting functions as a claim's figure.

The claim modules draw small figures themselves (:mod:`planner.reproduce._plots`); where a
scenario or a library plotting function already draws the thesis figure (the gait kind's
Fig. 2.10/2.12/2.14 plots, the trace figure, the exploration top view, the DVMA figure),
the claims save that figure instead. These helpers save a figure (pyplot-managed or not)
and close it, pick a figure out of a scenario's :class:`planner.results.RunResult`, and put
several figures side by side in one PNG.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from pathlib import Path

from planner.reproduce._plots import figure, save

__all__ = ["save_figure", "save_panels", "save_run_figure"]


def _close(fig) -> None:
    import matplotlib.pyplot as plt

    plt.close(fig)  # a no-op for a Figure pyplot does not manage


def _save_tight(fig, path: Path | None) -> str | None:
    """As :func:`planner.reproduce._plots.save`, cropped to what is drawn (the library's
    figures size themselves for their own run directories; titles may overhang)."""
    if path is None:
        return None
    fig.savefig(path, dpi=100, bbox_inches="tight")
    return f"figures/{path.name}"


def save_figure(fig, path: Path | None) -> str | None:
    """Save ``fig`` to ``path`` (PNG, cropped to what is drawn) and close it; return its file
    name (``None`` without a path)."""
    try:
        return _save_tight(fig, path)
    finally:
        _close(fig)


def save_run_figure(result, name: str, path: Path | None) -> str | None:
    """Save the figure ``name`` of a scenario's result and close all its figures.

    Returns the figure's file name, or ``None`` without a path or when the run drew no
    figure of that name.
    """
    figs = dict(getattr(result, "figures", {}) or {})
    try:
        if path is None or name not in figs:
            return None
        return _save_tight(figs[name], path)
    finally:
        for fig in figs.values():
            _close(fig)


def _pixels(fig):
    import matplotlib.image as mpimg

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100, bbox_inches="tight")
    _close(fig)
    buf.seek(0)
    return mpimg.imread(buf, format="png")


def save_panels(figs: Sequence, titles: Sequence[str], path: Path | None) -> str | None:
    """Render ``figs`` (closing them) and save them side by side, each under its title."""
    if path is None:
        for fig in figs:
            _close(fig)
        return None
    images = [_pixels(f) for f in figs]
    height = max(im.shape[0] for im in images) / 100
    widths = [im.shape[1] / 100 for im in images]
    out, axes = figure(len(images), width=max(widths), height=height + 0.4)
    for ax, im, title in zip(axes if len(images) > 1 else [axes], images, titles, strict=True):
        ax.imshow(im)
        ax.set_title(title, fontsize=10)
        ax.axis("off")
    return save(out, path)
