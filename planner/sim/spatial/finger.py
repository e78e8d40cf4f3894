"""The 3GM five-bar as constrained Pinocchio dynamics, reduced to its three motor angles.

The Pinocchio tree of :mod:`robots.three_gm.model` has ``q = (θ3, θ1, γ1-θ1, θ2, γ2-θ2)``;
the loop closure ``c(q) = closure_a - closure_b = 0`` (two independent rows: the five-bar is
planar) leaves three degrees of freedom, the motor angles ``θ = (θ1, θ2, θ3)``. The passive
angles follow from θ in closed form (eq. C.5, elbow-up), so the loop is closed exactly at
every step, and velocities are ``v = S(q) θ̇`` with

.. math:: S = \\begin{bmatrix} I \\\\ -J_{c,p}^{-1} J_{c,a} \\end{bmatrix}

(actuated rows identity, passive rows from ``J_c v = 0``, ``J_c`` the in-plane rows of the
closure Jacobian). The reduced (Lagrange-d'Alembert) equations of motion are

.. math:: M_r \\ddot\\theta + b_r = \\tau + J^T f, \\qquad M_r = S^T M S, \\qquad
          b_r = S^T \\,\\mathrm{rnea}(q, v, \\dot S\\dot\\theta),

where ``Ṡθ̇`` is the passive acceleration that keeps the loop closed at ``θ̈ = 0``
(``J_c,p a_p = -J̇_c v``, from Pinocchio's classical frame accelerations), and ``M``, ``rnea``
are Pinocchio's CRBA and RNEA on the tree (link masses, fingertip, armature of
:mod:`robots.three_gm.params`). This equals Pinocchio's ``constraintDynamics`` with the
``closure_constraint`` (tested). The fingertip centre is the ``endpoint`` frame; its linear
and angular Jacobians in the WCS are ``J = J_e S`` and ``J_ω = J_ω,e S``.

Singularities: the closed form fails when the loop cannot close, and ``J_c,p`` is singular
when links l3 and l4 are aligned; both raise :class:`~planner.errors.SingularConfiguration`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from planner.errors import SingularConfiguration
from robots.three_gm import closed_form as cf
from robots.three_gm.model import ACTUATED, PASSIVE

__all__ = ["FingerDynamics", "FingerState", "tcs_rotation"]

_ACT = list(ACTUATED)
_PAS = list(PASSIVE)
_LWA = pin.LOCAL_WORLD_ALIGNED


def tcs_rotation(gamma1: float, theta3: float) -> np.ndarray:
    """``R_TW`` (3, 3) of the simulated OWTS: TCS -> WCS.

    The TCS has its origin at the fingertip centre and its ``z`` axis (the sensor's pole)
    along the distal link, ``z_T = (cos θ3 cos γ1, sin θ3 cos γ1, sin γ1)``; ``y_T`` is the
    five-bar plane normal ``(-sin θ3, cos θ3, 0)``: ``R_TW = R_z(θ3) R_y(π/2 - γ1)``.

    Note: eq. 4.1 of the thesis (``robots.three_gm.rotation_tcs_to_wcs``) is written in the
    thesis' axes, where the five-bar plane at θ3 = 0 is the x-y plane; in hapex' WCS (z
    vertical, eq. C.6) its third column is horizontal, not along the distal link.
    """
    c3, s3 = math.cos(theta3), math.sin(theta3)
    cg, sg = math.cos(gamma1), math.sin(gamma1)
    # R_y(pi/2 - g1) columns: (sin g1, 0, -cos g1), (0, 1, 0), (cos g1, 0, sin g1)
    return np.array(
        [
            [c3 * sg, -s3, c3 * cg],
            [s3 * sg, c3, s3 * cg],
            [-cg, 0.0, sg],
        ]
    )


@dataclass(frozen=True)
class FingerState:
    """Kinematics and reduced dynamics at one state.

    Attributes:
        q: (5,) tree configuration [rad]; v: (5,) tree velocity [rad/s].
        center: (3,) fingertip centre in the WCS [m].
        J: (3, 3) d center / dθ [m/rad]; Jw: (3, 3) distal-link angular velocity / θ̇ [-].
        M: (3, 3) reduced mass matrix M_r [kg m²]; b: (3,) bias b_r [N m].
        gamma1: passive angle γ1 [rad] (for the TCS).
    """

    q: np.ndarray
    v: np.ndarray
    center: np.ndarray
    J: np.ndarray
    Jw: np.ndarray
    M: np.ndarray
    b: np.ndarray
    gamma1: float


class FingerDynamics:
    """Reduced dynamics of a :class:`~robots.three_gm.ThreeGM` (see the module docstring).

    Args:
        gm: the finger (its ``model`` is copied; gravity is set here).
        gravity: (3,) gravity in the WCS [m/s²].
    """

    def __init__(self, gm, gravity=(0.0, 0.0, -9.81)) -> None:
        self.gm = gm
        self.params = gm.params
        self.model = gm.model.copy()
        self.model.gravity = pin.Motion(np.asarray(gravity, float), np.zeros(3))
        self.data = self.model.createData()
        self.fid = [self.model.getFrameId(n) for n in ("endpoint", "closure_a", "closure_b")]
        self.j1 = self.model.getJointId("theta1")
        self._zero = np.zeros(self.model.nv)

    def passive(self, theta: np.ndarray) -> tuple[float, float]:
        """``(γ1, γ2)`` [rad] in closed form (raises SingularConfiguration)."""
        st = cf.five_bar_state(self.params, theta)
        return st.gamma1, st.gamma2

    def configuration(self, theta: np.ndarray) -> np.ndarray:
        """(5,) tree q with the loop closed."""
        g1, g2 = self.passive(theta)
        return np.array([theta[2], theta[0], g1 - theta[0], theta[1], g2 - theta[1]])

    def center(self, theta: np.ndarray) -> np.ndarray:
        """Fingertip centre (3,) in the WCS [m] (closed form, eq. C.6)."""
        return cf.five_bar_state(self.params, theta).position

    def evaluate(self, theta: np.ndarray, theta_dot: np.ndarray) -> FingerState:
        """Kinematics, ``M_r`` and ``b_r`` at ``(θ, θ̇)`` [rad, rad/s]."""
        m, d = self.model, self.data
        q = self.configuration(theta)
        pin.computeJointJacobians(m, d, q)
        pin.updateFramePlacements(m, d)
        Je = pin.getFrameJacobian(m, d, self.fid[0], _LWA)
        Ja = pin.getFrameJacobian(m, d, self.fid[1], _LWA)[:3]
        Jb = pin.getFrameJacobian(m, d, self.fid[2], _LWA)[:3]
        E = d.oMi[self.j1].rotation[:, :2]  # in-plane axes of the five-bar
        Jc = E.T @ (Ja - Jb)
        Jcp = Jc[:, _PAS]
        det = Jcp[0, 0] * Jcp[1, 1] - Jcp[0, 1] * Jcp[1, 0]
        scale = float(np.abs(Jcp).max()) ** 2
        if abs(det) <= 1e-9 * scale:
            raise SingularConfiguration(
                f"3GM links l3 and l4 are aligned at theta = {np.round(theta, 6).tolist()} rad "
                f"(closure Jacobian determinant {det:.3g})",
                value=float(det),
            )
        inv = np.array([[Jcp[1, 1], -Jcp[0, 1]], [-Jcp[1, 0], Jcp[0, 0]]]) / det
        S = np.zeros((5, 3))
        S[_ACT, [0, 1, 2]] = 1.0
        S[_PAS] = -inv @ Jc[:, _ACT]
        v = S @ theta_dot
        pin.forwardKinematics(m, d, q, v, self._zero)
        aa = pin.getFrameClassicalAcceleration(m, d, self.fid[1], _LWA).linear
        ab = pin.getFrameClassicalAcceleration(m, d, self.fid[2], _LWA).linear
        a0 = np.zeros(5)
        a0[_PAS] = -inv @ (E.T @ (aa - ab))
        b = S.T @ pin.rnea(m, d, q, v, a0)
        M = pin.crba(m, d, q)
        M = np.triu(M) + np.triu(M, 1).T
        Mr = S.T @ M @ S
        center = d.oMf[self.fid[0]].translation.copy()
        return FingerState(q, v, center, Je[:3] @ S, Je[3:] @ S, Mr, b, float(q[1] + q[2]))
