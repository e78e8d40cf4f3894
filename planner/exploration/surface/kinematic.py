"""Geometric fingertip over a height field: where a ball of radius r_f rests (no dynamics).

The centre of a sphere of radius ``r`` resting on the graph ``w = h(u, v)`` above the point
``c = (u, v)`` is at height ``max_p h(p) + sqrt(r² - |p - c|²)`` over ``|p - c| <= r`` (the
grey dilation of the heights by the ball, thesis §3.2.1's traced surface, here evaluated only
along a path); the contact point is the maximizer ``p`` and the contact normal ``(c - p)/r``.
Used to plan and to test type identification and raster matching without the simulator, and
for the true outlines of features.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from planner import checks

__all__ = ["BallTrace", "ball_trace", "line_points"]


@dataclass(frozen=True)
class BallTrace:
    """A ball resting on a height field along a path (plate frame).

    Attributes:
        centers: (N, 3) fingertip centres ``(u, v, w)`` [m].
        contacts: (N, 3) contact points on the surface [m].
        normals: (N, 3) outward surface normals at the contacts (unit) [-].
    """

    centers: np.ndarray
    contacts: np.ndarray
    normals: np.ndarray


def line_points(start, end, spacing: float) -> np.ndarray:
    """(N, 2) points from ``start`` to ``end`` (2,) every ``spacing`` [m] (both ends kept)."""
    a = checks.vector("start", start, 2, "m")
    b = checks.vector("end", end, 2, "m")
    h = checks.positive("spacing", spacing, "m")
    n = max(2, int(np.ceil(np.linalg.norm(b - a) / h)) + 1)
    return a + np.linspace(0.0, 1.0, n)[:, None] * (b - a)


def ball_trace(
    height: Callable[[np.ndarray, np.ndarray], np.ndarray],
    path,
    tip_radius: float,
    *,
    grid: float = 2e-4,
    noise: float = 0.0,
    rng: np.random.Generator | None = None,
) -> BallTrace:
    """Fingertip centres, contacts and normals of a ball following ``path`` on ``h``.

    Args:
        height: vectorized ``h(u, v)`` [m] of the plate frame.
        path: (N, 2) horizontal centre positions [m].
        tip_radius: ball radius r_f [m].
        grid: spacing of the height samples under the ball [m].
        noise: standard deviation of Gaussian noise added to the centres [m].
        rng: generator for the noise.
    """
    P = checks.points("path", path, dims=(2,))
    r = checks.positive("tip_radius", tip_radius, "m")
    g = checks.positive("grid", grid, "m")
    k = int(np.ceil(r / g))
    off = np.arange(-k, k + 1) * g
    ou, ov = np.meshgrid(off, off, indexing="ij")
    inside = ou**2 + ov**2 <= r * r
    ou, ov = ou[inside], ov[inside]
    cap = np.sqrt(np.maximum(r * r - ou**2 - ov**2, 0.0))
    centers = np.empty((len(P), 3))
    contacts = np.empty((len(P), 3))
    for i0 in range(0, len(P), 64):
        blk = P[i0 : i0 + 64]
        U = blk[:, :1] + ou[None]
        V = blk[:, 1:2] + ov[None]
        Hs = np.asarray(height(U, V), float)
        tot = Hs + cap[None]
        j = np.argmax(tot, axis=1)
        rows = np.arange(len(blk))
        centers[i0 : i0 + 64] = np.column_stack([blk, tot[rows, j]])
        contacts[i0 : i0 + 64] = np.column_stack([U[rows, j], V[rows, j], Hs[rows, j]])
    normals = (centers - contacts) / r
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    if noise > 0:
        gen = rng if rng is not None else np.random.default_rng(0)
        centers = centers + gen.normal(0.0, noise, centers.shape)
    return BallTrace(centers, contacts, normals)
