"""Objects of the ch. 2 experiments and their placement on the palm.

:func:`circle_with_ridge` is the ball of §2.3.2 (Fig. 2.15): a circle with a rectangular
ridge standing on it (3 mm high, 4 mm wide in the thesis). Profiles are closed and run
clockwise about the object frame's origin (the convention of
:mod:`planner.geometry.profiles`).
"""

from __future__ import annotations

import math

import numpy as np

from planner import checks
from planner.geometry.primitives import Arc, Line
from planner.geometry.profiles import Profile


def circle_with_ridge(
    radius: float = 0.05, width: float = 0.004, height: float = 0.003, angle: float = 0.0
) -> Profile:
    """A circle of ``radius`` with a ridge of ``width`` x ``height`` centred at polar
    ``angle`` [m, m, m, rad] (its top an arc as wide as its base, so the sides lean in
    slightly and the outline stays star-shaped about the origin)."""
    R = checks.positive("radius", radius, "m")
    w = checks.positive("width", width, "m")
    h = checks.positive("height", height, "m")
    a = float(angle)
    if w >= R:
        raise checks.InvalidParameter(f"width: expected < radius {R} [m], got {width!r}")
    d = w / (2.0 * R)  # half-angle of the ridge's base
    top = R + h
    e = w / (2.0 * top)  # half-angle of its top (same width: sides slightly inclined)

    def pt(rad, ang):
        return (rad * math.cos(ang), rad * math.sin(ang))

    pieces = (
        Arc((0.0, 0.0), R, a - d, -(2 * math.pi - 2 * d)),
        Line(pt(R, a + d - 2 * math.pi), pt(top, a + e)),
        Arc((0.0, 0.0), top, a + e, -2 * e),
        Line(pt(top, a - e), pt(R, a - d)),
    )
    return Profile(pieces, closed=True, name="circle_with_ridge")


def rest_height(profile: Profile, angle: float = 0.0) -> float:
    """Height [m] of the object frame's origin when the profile, rotated by ``angle``
    [rad], rests on the palm (its lowest point at y = 0)."""
    pts = profile.sample(5e-4).points
    c, s = math.cos(angle), math.sin(angle)
    return float(-np.min(s * pts[:, 0] + c * pts[:, 1]))


def mean_radius(profile: Profile) -> float:
    """Radius [m] of the circle with the profile's area (the default nominal shape)."""
    P = profile.sample(5e-4).points
    x, y = P[:, 0], P[:, 1]
    area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    return float(math.sqrt(area / math.pi))


__all__ = ["circle_with_ridge", "mean_radius", "rest_height"]
