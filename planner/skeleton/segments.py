"""Vectorized helpers on line segments: clipping to a box, merging, point distances."""

from __future__ import annotations

import numpy as np


def clip_segments(
    seg: np.ndarray, bounds: tuple[float, float, float, float]
) -> tuple[np.ndarray, np.ndarray]:
    """Clip segments to an axis-aligned box (Liang-Barsky).

    Args:
        seg: (S, 2, 2) segment end points [m].
        bounds: ``(xmin, ymin, xmax, ymax)`` [m].

    Returns:
        ``(clipped (S, 2, 2), inside (S,) bool)``; rows with ``inside`` False lie outside
        the box (their clipped coordinates are meaningless).
    """
    p0, d = seg[:, 0], seg[:, 1] - seg[:, 0]
    t0, t1 = np.zeros(len(seg)), np.ones(len(seg))
    inside = np.ones(len(seg), dtype=bool)
    xmin, ymin, xmax, ymax = bounds
    for p, q in (
        (-d[:, 0], p0[:, 0] - xmin),
        (d[:, 0], xmax - p0[:, 0]),
        (-d[:, 1], p0[:, 1] - ymin),
        (d[:, 1], ymax - p0[:, 1]),
    ):
        par = p == 0
        inside &= ~(par & (q < 0))
        with np.errstate(divide="ignore", invalid="ignore"):
            r = np.where(par, 0.0, q / np.where(par, 1.0, p))
        t0 = np.where(~par & (p < 0), np.maximum(t0, r), t0)
        t1 = np.where(~par & (p > 0), np.minimum(t1, r), t1)
    inside &= t0 <= t1
    out = np.stack([p0 + t0[:, None] * d, p0 + t1[:, None] * d], axis=1)
    # put clipped end points exactly on the box (rounding would leave gaps at the border)
    lo, hi = np.array([xmin, ymin]), np.array([xmax, ymax])
    for k, t in ((0, t0 > 0), (1, t1 < 1)):
        q = out[t, k]
        gap = np.concatenate([np.abs(q - lo), np.abs(q - hi)], axis=1)
        side = np.argmin(gap, axis=1)
        rows = np.arange(len(q))
        q[rows, side % 2] = np.where(side < 2, lo[side % 2], hi[side % 2])
        out[t, k] = np.clip(q, lo, hi)
    return out, inside


def merge_segments(seg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Turn segments into a graph, merging exactly equal end points.

    Args:
        seg: (S, 2, 2) segment end points [m].

    Returns:
        ``(points (K, 2), edges (S, 2))``.
    """
    if len(seg) == 0:
        return np.zeros((0, 2)), np.zeros((0, 2), dtype=np.int64)
    pts, inv = np.unique(seg.reshape(-1, 2), axis=0, return_inverse=True)
    return pts, inv.reshape(-1, 2).astype(np.int64)


def point_segment_distance(p: np.ndarray, seg: np.ndarray) -> np.ndarray:
    """(S,) distance from points ``p`` (S, 2) to segments ``seg`` (S, 2, 2), row by row [m]."""
    if len(seg) == 0:
        return np.zeros(0)
    a, d = seg[:, 0], seg[:, 1] - seg[:, 0]
    dd = np.einsum("ij,ij->i", d, d)
    t = np.einsum("ij,ij->i", p - a, d) / np.where(dd > 0, dd, 1.0)
    t = np.clip(np.where(dd > 0, t, 0.0), 0.0, 1.0)
    q = a + t[:, None] * d - p
    return np.hypot(q[:, 0], q[:, 1])


__all__ = ["clip_segments", "merge_segments", "point_segment_distance"]
