"""Polar angles on the circle [rad]: grouping and (weighted) medians, for features seen at
angles of the object (the pad's tactile sightings, macro features over several passes,
the true features' clusters)."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np


def circular_groups(
    items: Sequence, gap: float, angle: Callable[[object], float] | None = None
) -> list[list]:
    """``items`` sorted by their angle in (-pi, pi] [rad] (``angle(item)``, default the item
    itself), split where consecutive angles differ by ``gap`` [rad] or more; the first and
    last groups are one when they lie within ``gap`` across +-pi (the joined group starts
    with the last group's items)."""
    key = angle or (lambda x: x)
    groups: list[list] = []
    for it in items:
        if groups and key(it) - key(groups[-1][-1]) < gap:
            groups[-1].append(it)
        else:
            groups.append([it])
    if len(groups) > 1 and key(groups[0][0]) + 2 * math.pi - key(groups[-1][-1]) < gap:
        groups[0] = groups.pop() + groups[0]
    return groups


def circular_median(a, w=None) -> float:
    """Median [rad] of angles ``a`` spanning less than pi, unwrapped about their (weighted)
    circular mean; with weights ``w`` the smallest angle whose cumulative weight reaches
    half, or halfway to the next one when it reaches exactly half (equal weights:
    ``np.median``)."""
    a = np.asarray(a, float)
    w = np.ones(a.size) if w is None else np.asarray(w, float)
    m = math.atan2(float(np.sum(w * np.sin(a))), float(np.sum(w * np.cos(a))))
    d = np.remainder(a - m + math.pi, 2 * math.pi) - math.pi
    order = np.argsort(d)
    cum = np.cumsum(w[order])
    half = 0.5 * cum[-1]
    k = int(np.searchsorted(cum, half))
    mid = float(d[order][k])
    if k + 1 < d.size and math.isclose(cum[k], half, rel_tol=1e-12):
        mid = 0.5 * (mid + float(d[order][k + 1]))  # halfway between, as np.median
    return math.remainder(m + mid, 2 * math.pi)


__all__ = ["circular_groups", "circular_median"]
