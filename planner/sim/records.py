"""Contact records read from a world after a step (planar and spatial).

A :class:`Contact` is plain, frozen data, like MuJoCo's ``MjContact`` or Drake's
``PointPairContactInfo``: which two bodies touch, where, along which normal, with which
forces and which slip. Forces are the *average* forces over the last step, i.e. the contact
impulses of the time-stepping scheme divided by ``dt``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Contact"]


@dataclass(frozen=True)
class Contact:
    """One contact between two bodies.

    Attributes:
        bodies: ``(name_a, name_b)`` handles of the two bodies.
        point: (2,) planar or (3,) spatial contact point in the world frame [m] (on body b's
            surface).
        normal: unit (2,) / (3,) normal pointing from body b toward body a: the normal force
            on body a is ``+normal_force * normal``.
        normal_force: normal force on body a [N], >= 0 (0 for a candidate that did not
            activate).
        tangential_force: planar: signed friction force on body a along the tangent
            ``t = R(+90 deg) normal`` [N]; spatial: (3,) vector in the tangent plane [N].
        slip_velocity: velocity of body a's material point relative to body b's at the contact,
            along ``t`` (planar, signed scalar) or in the tangent plane (spatial, (3,)) [m/s],
            after the step.
        gap: signed distance [m]: >= 0 separated, < 0 penetration.
    """

    bodies: tuple[str, str]
    point: np.ndarray
    normal: np.ndarray
    normal_force: float
    tangential_force: float | np.ndarray
    slip_velocity: float | np.ndarray
    gap: float

    @property
    def active(self) -> bool:
        """Whether the contact carried a force over the last step."""
        return self.normal_force > 0.0

    @property
    def tangent(self) -> np.ndarray:
        """Planar contacts only: the unit tangent ``t = (-n_y, n_x)``."""
        n = np.asarray(self.normal, float)
        if n.shape != (2,):
            raise ValueError("tangent is defined for planar contacts only")
        return np.array([-n[1], n[0]])
