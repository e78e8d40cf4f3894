"""Fingertip impedance of the exploring finger (thesis §2.2.3 Control, §2.3.2).

During phases 2 and 3 the moving fingertip is controlled on its own: a commanded normal
force (0.3 N in the experiment of §2.3.2) along the contact normal and an impedance (PD) on
the fingertip position along the tangent and on its orientation, "completely defining the
control problem for a three degree-of-freedom finger". The force applied on the object is::

    f = f_n n + P_t (K_p (x_d - x) + K_v (xd_d - xd)),    P_t = I - n n^T

and the moment on the distal link ``m = k_phi (phi_d - phi) - d_phi phid``. Scalar arithmetic
only (runs on floats and CasADi symbols).
"""

from __future__ import annotations

from dataclasses import dataclass

from planner import checks


@dataclass(frozen=True)
class FingertipImpedanceGains:
    """Gains of the exploring finger.

    Attributes:
        normal_force: commanded normal force [N] (0.3 in §2.3.2).
        kp: tangential stiffness [N/m]; kv: tangential damping [N s/m].
        k_phi: orientation stiffness [N m/rad]; d_phi: orientation damping [N m s/rad].
    """

    normal_force: float = 0.3
    kp: float = 40.0
    kv: float = 2.0
    k_phi: float = 0.2
    d_phi: float = 0.01

    def __post_init__(self) -> None:
        checks.positive("normal_force", self.normal_force, "N")
        checks.nonnegative("kp", self.kp, "N/m")
        checks.nonnegative("kv", self.kv, "N s/m")
        checks.nonnegative("k_phi", self.k_phi, "N m/rad")
        checks.nonnegative("d_phi", self.d_phi, "N m s/rad")


def fingertip_force(x, xd, x_des, xd_des, normal, normal_force, kp, kv):
    """Force the exploring fingertip applies on the object [N].

    Args:
        x, xd: (2,) fingertip point and velocity [m, m/s]; x_des, xd_des: their commands.
        normal: (2,) unit contact normal pointing into the object.
        normal_force: commanded normal force [N]; kp, kv: tangential gains.

    Returns:
        list ``[f_x, f_y]`` [N].
    """
    ex = kp * (x_des[0] - x[0]) + kv * (xd_des[0] - xd[0])
    ey = kp * (x_des[1] - x[1]) + kv * (xd_des[1] - xd[1])
    nx, ny = normal[0], normal[1]
    en = ex * nx + ey * ny
    return [normal_force * nx + ex - en * nx, normal_force * ny + ey - en * ny]


def holding_force(x, xd, anchor, direction, force, kp, kv, mu, sqrt=None):
    """Force the HOLDING fingertip applies on the object (phases 2/3) [N].

    ``force`` [N] along ``direction`` (unit, towards the palm contact: it presses the
    object against the palm) plus a stiff 2-D impedance ``kp`` [N/m], ``kv`` [N s/m] about
    the contact's ``anchor`` [m] (where it was at the phase start). The 2-D spring matters:
    a holder that is only force-controlled along ``direction`` yields to the object rolling
    on the palm into it, and the exploring finger's friction then rolls the object backwards.
    The press grows with the spring's sideways part ``s_t`` (``force + |s_t| / mu``) so the
    holding force stays inside the friction cone (``mu`` [-] with margin) instead of being
    cut by it (a holder at its cone let the object roll away). ``sqrt``: the square root to
    use (``casadi.sqrt`` in the compiled step; default ``math.sqrt``).
    """
    import math

    root = sqrt or math.sqrt
    sx = kp * (anchor[0] - x[0]) - kv * xd[0]
    sy = kp * (anchor[1] - x[1]) - kv * xd[1]
    along = sx * direction[0] + sy * direction[1]
    tx, ty = sx - along * direction[0], sy - along * direction[1]
    press = force + root(tx * tx + ty * ty + 1e-8) / mu
    return [press * direction[0] + sx, press * direction[1] + sy]


def orientation_moment(phi, phid, phi_des, k_phi, d_phi):
    """Moment on the distal link holding the fingertip orientation [N m]."""
    return k_phi * (phi_des - phi) - d_phi * phid


__all__ = ["FingertipImpedanceGains", "fingertip_force", "holding_force", "orientation_moment"]
