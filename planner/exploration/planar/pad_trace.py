"""Two facts about the exploring pad's trace that every reader of it shares (a leaf module:
the coverage and feature measures, the macro-feature detector and the corner probe all
import it, none of them each other for it)."""

from __future__ import annotations

import numpy as np

#: radius of the virtual fingertip the pad's trace is offset by for the detection [m]
VIRTUAL_RADIUS = 0.003


def phase_runs(kind) -> list[np.ndarray]:
    """The row indices of each run of equal ``kind`` (the trace's phase column), in order."""
    kind = np.asarray(kind)
    return np.split(np.arange(kind.size), np.flatnonzero(np.diff(kind) != 0) + 1)


__all__ = ["VIRTUAL_RADIUS", "phase_runs"]
