"""Object impedance control of a two-finger grasp (thesis §2.2.2, eqs. 2.5-2.7).

The fingertip forces that move the object (the *external* forces) come from a PD servo on
the object pose with the object's mass fed forward (eq. 2.7)::

    F = -m g + M xdd_d + K_p (x_d - x) + K_v (xd_d - xd)

(the thesis writes the gravity term as ``G``; here it is the wrench that balances the
object's weight, ``-m g``, written out so it is not confused with the grasp matrix). ``x`` is
the planar object pose ``(x, y, theta)`` [m, m, rad] and ``F`` the wrench ``(f_x, f_y,
tau_z)`` [N, N, N m] the contacts must apply, torque about the object reference point.

The object velocity is estimated from the encoders through eqs. 2.5-2.6: under rolling the
material points of the fingertips at the contacts move with the object, ``v_i = J_i qdot``
(eq. 2.5), and eq. 2.6 ``v_c = G^T xd_obj`` is inverted in the least-squares sense. For two
contacts ``p_1, p_2`` this is closed form: ``omega = (v_2 - v_1) . (e_z x d) / |d|^2`` with
``d = p_2 - p_1``, and the velocity of a reference point ``c`` is the mean contact velocity
plus ``omega e_z x (c - (p_1 + p_2)/2)``.

Every function here uses only scalar arithmetic on its arguments, so the same code runs on
floats (the reference implementation) and on CasADi symbols (the generated control step).
"""

from __future__ import annotations

from dataclasses import dataclass

from planner import checks


@dataclass(frozen=True)
class ObjectImpedanceGains:
    """Gains of eq. (2.7).

    Attributes:
        kp: (3,) stiffness ``(k_x, k_y, k_theta)`` [N/m, N/m, N m/rad].
        kv: (3,) damping ``(d_x, d_y, d_theta)`` [N s/m, N s/m, N m s/rad].
    """

    kp: tuple[float, float, float] = (60.0, 60.0, 0.6)
    kv: tuple[float, float, float] = (4.0, 4.0, 0.02)

    def __post_init__(self) -> None:
        kp = checks.vector("kp", self.kp, 3, "N/m, N/m, N m/rad")
        kv = checks.vector("kv", self.kv, 3, "N s/m, N s/m, N m s/rad")
        for name, v in (("kp", kp), ("kv", kv)):
            for i, x in enumerate(v):
                checks.nonnegative(f"{name}[{i}]", float(x))
        object.__setattr__(self, "kp", tuple(float(v) for v in kp))
        object.__setattr__(self, "kv", tuple(float(v) for v in kv))


def object_wrench(x, xd, x_des, xd_des, xdd_des, mass, inertia, gravity, kp, kv):
    """The object wrench commanded by the impedance law, eq. (2.7).

    Args:
        x, xd: current object pose (3,) and twist (3,) estimates [m, rad; m/s, rad/s].
        x_des, xd_des, xdd_des: desired pose, twist and acceleration (3,) each.
        mass: object mass [kg]; inertia: its moment of inertia about the reference [kg m^2].
        gravity: (2,) gravity in the hand plane [m/s^2].
        kp, kv: (3,) gains of :class:`ObjectImpedanceGains`.

    Returns:
        list of 3 entries ``(f_x, f_y, tau_z)`` [N, N, N m] to be applied by the contacts.
    """
    return [
        mass * (xdd_des[0] - gravity[0]) + kp[0] * (x_des[0] - x[0]) + kv[0] * (xd_des[0] - xd[0]),
        mass * (xdd_des[1] - gravity[1]) + kp[1] * (x_des[1] - x[1]) + kv[1] * (xd_des[1] - xd[1]),
        inertia * xdd_des[2] + kp[2] * (x_des[2] - x[2]) + kv[2] * (xd_des[2] - xd[2]),
    ]


def object_twist_two_contacts(p1, p2, v1, v2, c):
    """Least-squares object twist from two contact velocities (eq. 2.6 inverted).

    Args:
        p1, p2: (2,) contact points [m]; v1, v2: (2,) their velocities [m/s] (eq. 2.5).
        c: (2,) object reference point [m].

    Returns:
        list ``(v_x, v_y, omega)`` of the reference point [m/s, m/s, rad/s].
    """
    dx, dy = p2[0] - p1[0], p2[1] - p1[1]
    omega = ((v2[0] - v1[0]) * (-dy) + (v2[1] - v1[1]) * dx) / (dx * dx + dy * dy)
    rx = c[0] - 0.5 * (p1[0] + p2[0])
    ry = c[1] - 0.5 * (p1[1] + p2[1])
    return [
        0.5 * (v1[0] + v2[0]) - omega * ry,
        0.5 * (v1[1] + v2[1]) + omega * rx,
        omega,
    ]


def contact_accelerations(c, xdd, omega, points):
    """Accelerations of object material points at ``points`` for a desired object motion.

    ``a_i = a_c + alpha e_z x r_i - omega^2 r_i`` with ``r_i = p_i - c`` (rigid body).

    Args:
        c: (2,) reference point [m]; xdd: (3,) its acceleration and the angular one
            [m/s^2, rad/s^2]; omega: angular velocity [rad/s]; points: list of (2,) [m].

    Returns:
        list of ``[a_x, a_y]`` [m/s^2], one per point.
    """
    out = []
    for p in points:
        rx, ry = p[0] - c[0], p[1] - c[1]
        out.append(
            [
                xdd[0] - xdd[2] * ry - omega * omega * rx,
                xdd[1] + xdd[2] * rx - omega * omega * ry,
            ]
        )
    return out


__all__ = [
    "ObjectImpedanceGains",
    "contact_accelerations",
    "object_twist_two_contacts",
    "object_wrench",
]
