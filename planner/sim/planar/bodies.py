"""Body records of the planar world and the mass properties of free outlines."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner.errors import InvalidParameter
from planner.geometry.profiles import Profile
from planner.sim.planar.outline import Outline

__all__ = ["Body", "area_properties"]

FIXED, FREE, TIP = 0, 1, 2


@dataclass
class Body:
    """One body of the planar world.

    Attributes:
        name: its handle.
        kind: ``FIXED`` (pose never changes), ``FREE`` (3 DOF) or ``TIP`` (a fingertip,
            moved by the hand's joints).
        outline: the compiled outline in the body frame (for free bodies: centred on the
            centre of mass).
        friction: Coulomb coefficient mu [-].
        index: free bodies: row in the state arrays; tips: finger index (0 left, 1 right).
        pose: fixed bodies: (x, y, angle) [m, rad].
        mass, inertia: free bodies [kg], [kg m^2] (about the centre of mass).
        com: free bodies: (2,) centre of mass in the profile's own frame [m].
    """

    name: str
    kind: int
    outline: Outline
    friction: float
    index: int = -1
    pose: tuple[float, float, float] = (0.0, 0.0, 0.0)
    mass: float = 0.0
    inertia: float = 0.0
    com: tuple[float, float] = (0.0, 0.0)


def area_properties(profile: Profile) -> tuple[float, np.ndarray, float]:
    """Area [m^2], centroid (2,) [m] and polar second moment about the centroid [m^4] of a
    closed profile (Green's theorem on a 1e-5-length sampling: relative error ~1e-10, used
    for mass properties only, never for contact geometry)."""
    if not profile.closed:
        raise InvalidParameter("a free body needs a closed profile (got an open one)")
    P = profile.sample(profile.length * 1e-5).points
    x, y = P[:, 0], P[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cr = x * yn - xn * y
    A = 0.5 * cr.sum()
    cx = ((x + xn) * cr).sum() / (6 * A)
    cy = ((y + yn) * cr).sum() / (6 * A)
    Jo = ((x * x + x * xn + xn * xn + y * y + y * yn + yn * yn) * cr).sum() / 12.0
    A, Jo = abs(A), abs(Jo)
    J = Jo - A * (cx * cx + cy * cy)
    if not A > 0 or not math.isfinite(J):
        raise InvalidParameter("the profile encloses no area")
    return A, np.array([cx, cy]), J
