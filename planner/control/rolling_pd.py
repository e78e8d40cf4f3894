"""Explicit rolling control: a PD law on the contact location (thesis §2.2.2, eq. 2.8).

With three joints per finger the contact location can be commanded independently of the
object pose ("explicit rolling", Fig. 2.8). The contact location is measured on the
fingertip as an arclength ``s`` [m] along its outline, counter-clockwise, zero at the tip's
apex (the point on the distal link's axis): for a round tip of radius ``r`` with the contact
at angle ``beta`` in the fingertip frame, ``s = r (beta - pi/2)``; for the flat pad with the
contact at ``u`` across it, ``s = -u``. It is sensed (tactile-array centroid, or the force
direction of a round tip), not taken from the simulator.

Eq. (2.8) reads ``tau = K_p (s_d - s) + K_v (sd_d - sd)``. Rolling the fingertip
counter-clockwise by ``d phi`` over an object moves the contact on the fingertip by
``ds = -d phi / (k_f + k_o)`` (eq. 2.4, curvatures k_f of the tip and k_o of the object;
``k_f = 1/r``, 0 for the pad), so the moment about the contact that drives ``s`` towards
``s_d`` has the opposite sign of the error; :func:`rolling_moment` returns that moment
(applied to the distal link, [N m]) and its joint torques are ``(1, 1, 1) m`` — a pure
moment, which a point contact cannot resist, so it rolls the tip without changing the
contact force.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from planner import checks


@dataclass(frozen=True)
class RollingGains:
    """Gains of eq. (2.8) for the moment form.

    Attributes:
        kp: stiffness on the contact-location error [N m/m].
        kv: damping on its rate [N m s/m].
        max_moment: saturation of the rolling moment [N m].
    """

    kp: float = 0.8
    kv: float = 0.02
    max_moment: float = 0.05

    def __post_init__(self) -> None:
        checks.nonnegative("kp", self.kp, "N m/m")
        checks.nonnegative("kv", self.kv, "N m s/m")
        checks.positive("max_moment", self.max_moment, "N m")


def contact_arclength(offset_x: float, offset_y: float, tip: str, tip_radius: float) -> float:
    """Contact location on the fingertip as an arclength [m] (see the module docstring).

    Args:
        offset_x, offset_y: contact point in the fingertip frame [m].
        tip: ``"round"`` or ``"flat"``.
        tip_radius: radius of a round tip [m].
    """
    if tip == "flat":
        return -offset_x
    return tip_radius * (math.atan2(offset_y, offset_x) - 0.5 * math.pi)


def contact_offset(s: float, tip: str, tip_radius: float) -> tuple[float, float]:
    """Inverse of :func:`contact_arclength`: the fingertip-frame contact point [m]."""
    if tip == "flat":
        return -s, 0.0
    beta = s / tip_radius + 0.5 * math.pi
    return tip_radius * math.cos(beta), tip_radius * math.sin(beta)


def rolling_moment(s, sd, s_des, sd_des, gains: RollingGains) -> float:
    """Moment on the distal link that rolls the contact towards ``s_des`` (eq. 2.8).

    Args:
        s, sd: sensed contact location on the fingertip [m] and its rate [m/s].
        s_des, sd_des: commanded location [m] and rate [m/s].
        gains: the :class:`RollingGains`.

    Returns:
        the moment [N m], saturated at ``gains.max_moment``.
    """
    m = -(gains.kp * (s_des - s) + gains.kv * (sd_des - sd))
    return max(-gains.max_moment, min(gains.max_moment, m))


__all__ = ["RollingGains", "contact_arclength", "contact_offset", "rolling_moment"]
