"""The planar hand's joint actuators: the torque they deliver at a joint speed.

A joint's actuator delivers the held command ``tau`` [N m] (already clipped to the torque
limit by the run loop) up to its rated speed ``v_r`` (``robots.planar_hand.model.
VELOCITY_LIMIT``, 5 rad/s, the URDF's ``velocity``); above it the torque *in the direction
of motion* falls linearly to zero at ``2 v_r``, as a DC motor's torque falls along its
torque-speed line (the back-EMF eats the supply voltage), simplified to a knee at the rated
speed:

.. math::

    \\tau_{out} = \\tau \\, \\mathrm{clip}\\left(\\frac{2 v_r - |\\dot q|}{v_r}, 0, 1\\right)
    \\quad \\text{if } \\tau \\dot q > 0, \\qquad \\tau_{out} = \\tau \\text{ otherwise.}

Braking torque (against the motion) is delivered in full. The envelope only ever removes
driving torque, so it cannot add energy: the explicit use of the step's starting speed is
stable at any step (unlike a back-EMF damping term ``-b qd``, stiff for the 50 g distal
link).

Why: the hand's links carry no motor inertia, so without the envelope a finger that let go
and is driven at its 2 N m limit reached 240 rad/s (0.48 rad per 2 ms step) and the next
step's linearized contact rows met a 19 cm "penetration": the run ended as a simulator
fault (2 of 192 ``bench_gait`` runs, 2026-11-24). With it the free finger tops out near
``2 v_r`` (0.02 rad per step). Runs whose joints stay below ``v_r`` are unchanged to the
bit (the 10 cm ball's gait peaks at 4.3 rad/s). The MJCF export (MuJoCo, Drake) has no such
envelope: comparisons hold while the joints stay below ``v_r``.
"""

from __future__ import annotations

import numpy as np

from planner.sim.lcp import njit
from robots.planar_hand.model import VELOCITY_LIMIT

#: rated joint speed of the hand's actuators [rad/s] (a numba compile-time constant)
RATED_SPEED = float(VELOCITY_LIMIT)


@njit(cache=True)
def delivered(tau: float, qd: float) -> float:
    """Torque [N m] the actuator delivers for the command ``tau`` [N m] at joint speed
    ``qd`` [rad/s] (module docstring)."""
    if tau * qd <= 0.0:
        return tau
    s = abs(qd)
    if s <= RATED_SPEED:
        return tau
    if s >= 2.0 * RATED_SPEED:
        return 0.0
    return tau * (2.0 * RATED_SPEED - s) / RATED_SPEED


def delivered_array(tau: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """:func:`delivered` of each joint: ``tau``, ``qd`` (n,) -> (n,) [N m]."""
    return np.array([delivered(float(a), float(b)) for a, b in zip(tau, qd, strict=True)])


__all__ = ["RATED_SPEED", "delivered", "delivered_array"]
