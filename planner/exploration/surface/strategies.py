"""Feature search strategies (thesis §4.2, §4.5.1): raster, random walk, Lumelsky Bug-2.

Each strategy yields the straight segments ``(a, b)`` (plate frame, (2,) each [m]) the finger
slides along while the online detector listens. When a feature interrupts a segment the
explorer identifies and traces it and then resumes the same segment past the feature's known
area - for Bug-2 that is the leave point on the m-line beyond the traced obstacle.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["bug2", "raster", "random_walk", "segments"]


def raster(region: np.ndarray, spacing: float, margin: float):
    """Boustrophedon lines along ``u``, at most ``spacing`` [m] apart, ``margin`` [m] inside.

    The band ``v0 + margin .. v1 - margin`` (length ``L``) is covered so that every point
    of it lies within ``spacing / 2`` of a line: one line in the middle when ``L <=
    spacing``, else the fewest lines spread evenly from edge to edge at most ``spacing``
    apart, ``ceil(L / spacing) + 1`` (``floor(L / spacing) + 1`` put them up to twice
    ``spacing`` apart).
    """
    (u0, u1), (v0, v1) = region
    u0, u1, v0, v1 = u0 + margin, u1 - margin, v0 + margin, v1 - margin
    # (1e-9: a band that is a whole number of spacings, up to rounding, gets no extra line)
    lines = (v1 - v0) / spacing - 1e-9
    n = 1 if lines <= 1.0 else int(math.ceil(lines)) + 1
    vs = np.linspace(v0, v1, n) if n > 1 else [0.5 * (v0 + v1)]
    for i, v in enumerate(vs):
        a, b = np.array([u0, v]), np.array([u1, v])
        yield (a, b) if i % 2 == 0 else (b, a)


def _box_reach(p: np.ndarray, d: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> float:
    """Distance [m] from ``p`` (2,) along the unit direction ``d`` (2,) to the box's edge."""
    t = math.inf
    for i in range(2):
        if d[i] > 1e-12:
            t = min(t, (hi[i] - p[i]) / d[i])
        elif d[i] < -1e-12:
            t = min(t, (lo[i] - p[i]) / d[i])
    return max(t, 0.0)


#: the random walk yields no leg shorter than this [m] (a sweep needs more than 0.2 mm to move)
MIN_LEG = 1e-3


def random_walk(region: np.ndarray, start, rng: np.random.Generator, step: float, margin: float):
    """Straight legs of random heading and length U(1, 2) ``step`` [m], kept in the region.

    The usable box is ``region`` shrunk by ``margin`` [m] (collapsed to its mid-line along an
    axis narrower than ``2 margin``). A leg is clipped where it meets the box's edge; a heading
    whose clipped leg is shorter than ``min(step, box size) / 4`` is drawn again, and after 20
    such draws the leg heads to the box corner farthest away (so every leg is at least
    ``min(step, box size) / 4`` and at least :data:`MIN_LEG` long, and each takes simulated
    time). A box smaller than :data:`MIN_LEG` along both axes has no room to walk: no leg.
    """
    lo, hi = region[:, 0] + margin, region[:, 1] - margin
    mid = region.mean(axis=1)
    lo, hi = np.where(lo > hi, mid, lo), np.where(lo > hi, mid, hi)
    room = float(np.max(hi - lo))
    if room < MIN_LEG:
        return
    shortest = max(MIN_LEG, 0.25 * min(step, room))
    corners = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [lo[0], hi[1]], [hi[0], hi[1]]])
    p = np.clip(np.asarray(start, float), lo, hi)
    while True:
        for _ in range(20):
            phi = rng.uniform(0.0, 2 * math.pi)
            d = np.array([math.cos(phi), math.sin(phi)])
            leg = min(rng.uniform(1.0, 2.0) * step, _box_reach(p, d, lo, hi))
            if leg >= shortest:
                break
        else:
            far = corners[int(np.argmax(np.linalg.norm(corners - p, axis=1)))]
            gap = float(np.linalg.norm(far - p))  # >= room / 2 >= shortest
            d, leg = (far - p) / gap, min(gap, max(shortest, rng.uniform(1.0, 2.0) * step))
        q = np.clip(p + leg * d, lo, hi)
        yield p, q
        p = q


def bug2(start, goal):
    """The m-line of Bug-2 from ``start`` to ``goal`` (one segment)."""
    yield np.asarray(start, float), np.asarray(goal, float)


def segments(settings, region: np.ndarray, rng: np.random.Generator):
    """The segment generator of ``settings.strategy`` and its first point (2,) [m]."""
    r = settings.tip_radius
    margin = 0.5 * r
    if settings.strategy == "raster":
        gen = raster(region, settings.line_spacing, margin)
        first = next(raster(region, settings.line_spacing, margin))[0]
        return gen, first
    if settings.strategy == "random_walk":
        start = region.mean(axis=1)
        return random_walk(region, start, rng, 4.0 * r, margin), start
    start = np.array([region[0, 0] + margin, region[1].mean()])
    return bug2(start, settings.goal), start
