"""Internal-force servo of a two-contact grasp (thesis §2.2.2, last paragraph).

The sensed internal force is "the minimum of the force sensed by each finger along a line
through the two contact points": with ``u`` the unit vector from contact 1 to contact 2 and
``f_i`` the forces applied on the object, ``f_int = min(f_1 . u, -f_2 . u)`` [N] (positive
when squeezing). The servo is a PI law on its error, with anti-windup clamping; during
phases 2/3 the integral absorbs the exploring finger's disturbance (§2.2.3, Control).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from planner import checks


def sensed_internal_force(p1, p2, f1, f2) -> float:
    """Internal (squeeze) force of two contacts [N].

    Args:
        p1, p2: (2,) contact points [m].
        f1, f2: (2,) sensed forces applied on the object at them [N].

    Returns:
        ``min(f1 . u, -f2 . u)`` with ``u = (p2 - p1)/|p2 - p1|``; 0 if the points coincide.
    """
    dx, dy = p2[0] - p1[0], p2[1] - p1[1]
    d = math.hypot(dx, dy)
    if d == 0.0:
        return 0.0
    ux, uy = dx / d, dy / d
    return min(f1[0] * ux + f1[1] * uy, -(f2[0] * ux + f2[1] * uy))


@dataclass(frozen=True)
class InternalForceGains:
    """PI gains of the internal-force servo.

    Attributes:
        kp: proportional gain [N/N].
        ki: integral gain [1/s].
        max_correction: clamp of the integral term and of the total correction [N].
    """

    kp: float = 0.3
    ki: float = 20.0
    max_correction: float = 2.0

    def __post_init__(self) -> None:
        checks.nonnegative("kp", self.kp)
        checks.nonnegative("ki", self.ki, "1/s")
        checks.positive("max_correction", self.max_correction, "N")


class InternalForcePI:
    """PI servo on the sensed internal force (one instance per grasp; holds the integral).

    Args:
        gains: the :class:`InternalForceGains`.
    """

    def __init__(self, gains: InternalForceGains | None = None) -> None:
        self.gains = gains or InternalForceGains()
        self.integral = 0.0

    def reset(self, integral: float = 0.0) -> None:
        """Restart the integral (e.g. at a phase change) [N]."""
        self.integral = float(integral)

    def command(self, desired: float, sensed: float, dt: float) -> float:
        """Commanded internal force [N] for this control period.

        Args:
            desired: desired internal force [N].
            sensed: sensed internal force (:func:`sensed_internal_force`) [N].
            dt: control period [s].
        """
        g = self.gains
        err = desired - sensed
        lim = g.max_correction
        self.integral = max(-lim, min(lim, self.integral + g.ki * err * dt))
        corr = max(-lim, min(lim, g.kp * err + self.integral))
        return max(0.0, desired + corr)


__all__ = ["InternalForceGains", "InternalForcePI", "sensed_internal_force"]
