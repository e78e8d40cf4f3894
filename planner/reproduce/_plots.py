"""Small figure helpers shared by the claim modules (matplotlib, Agg)."""

from __future__ import annotations

from pathlib import Path

__all__ = ["figure", "save"]


def figure(ncols: int = 1, width: float = 5.0, height: float = 3.6):
    """A new matplotlib figure with ``ncols`` axes side by side."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width * ncols, height), constrained_layout=True)
    axes = [fig.add_subplot(1, ncols, i + 1) for i in range(ncols)]
    return fig, (axes[0] if ncols == 1 else axes)


def save(fig, path: Path | None) -> str | None:
    """Save ``fig`` to ``path`` (PNG) and return its file name, or ``None`` without a path."""
    if path is None:
        return None
    fig.savefig(path, dpi=100)
    return f"figures/{path.name}"
