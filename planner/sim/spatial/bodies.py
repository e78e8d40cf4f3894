"""Mutable state of the spatial world's moving bodies: free spheres and the 3GM finger.

Each body exposes what the contact step needs: its sphere centre, the free (contact-less)
velocity update, the contact-point Jacobian and inverse mass, and how to apply an impulse,
integrate positions and project the centre back onto a contact's offset surface.
"""

from __future__ import annotations

import math

import numpy as np

from planner.errors import SingularConfiguration
from planner.sim.spatial import step_kernel as sk
from planner.sim.spatial.finger import tcs_rotation
from planner.sim.spatial.finger_codegen import reduced_dynamics_function

__all__ = ["FingerBody", "SphereBody", "aligning", "quat_from_matrix", "quat_mul_exp", "skew"]


def skew(a: np.ndarray) -> np.ndarray:
    """``[a]×`` (3, 3): ``skew(a) @ b == cross(a, b)``."""
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def quat_mul_exp(q: np.ndarray, w: np.ndarray, h: float) -> np.ndarray:
    """``exp(w h) ⊗ q``: rotate the unit quaternion ``q`` (wxyz) by the world-frame rotation
    vector ``w h`` (exact exponential map) and renormalize."""
    ang = float(np.linalg.norm(w)) * h
    if ang < 1e-300:
        return q
    a = w * (h * math.sin(ang / 2) / ang)
    c = math.cos(ang / 2)
    w0, x0, y0, z0 = q
    out = np.array(
        [
            c * w0 - a[0] * x0 - a[1] * y0 - a[2] * z0,
            c * x0 + a[0] * w0 + a[1] * z0 - a[2] * y0,
            c * y0 - a[0] * z0 + a[1] * w0 + a[2] * x0,
            c * z0 + a[0] * y0 - a[1] * x0 + a[2] * w0,
        ]
    )
    return out / np.linalg.norm(out)


def quat_from_matrix(R: np.ndarray) -> np.ndarray:
    """Unit quaternion (wxyz) of the rotation matrix ``R`` (Shepperd's method)."""
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    if tr > 0:
        s = 2.0 * math.sqrt(1.0 + tr)
        q = [0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(R)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(1.0 + R[i, i] - R[j, j] - R[k, k])
        q = [0.0, 0.0, 0.0, 0.0]
        q[0] = (R[k, j] - R[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (R[j, i] + R[i, j]) / s
        q[1 + k] = (R[k, i] + R[i, k]) / s
    out = np.array(q)
    return out / np.linalg.norm(out) * (1.0 if out[0] >= 0 else -1.0)


class SphereBody:
    """A free solid ball: position, orientation (wxyz), linear and angular velocity (WCS).

    Inverse mass ``M⁻¹ = diag(1/m I3, 1/I I3)``, ``I = 2/5 m r²`` [kg m²].
    """

    def __init__(self, name, radius, mass, position, velocity, angular_velocity, friction):
        self.name, self.radius, self.mass = name, radius, mass
        self.inertia = 0.4 * mass * radius * radius
        self.p = np.array(position, float)
        self.quat = np.array([1.0, 0.0, 0.0, 0.0])
        self.v = np.array(velocity, float)
        self.w = np.array(angular_velocity, float)
        self.friction = friction
        self.minv = np.array([1 / mass] * 3 + [1 / self.inertia] * 3)

    @property
    def center(self) -> np.ndarray:
        return self.p

    def free_velocity(self, h: float, gravity: np.ndarray, tau) -> np.ndarray:
        """(6,) ``(v, ω)`` after a contact-free step [m/s, rad/s]."""
        return np.concatenate([self.v + h * gravity, self.w])

    def point_jacobian(self, n: np.ndarray) -> np.ndarray:
        """(3, 6) velocity of the material point at ``c - r n``: ``v + r n × ω``."""
        return np.hstack([np.eye(3), self.radius * skew(n)])

    def centre_jacobian(self) -> np.ndarray:
        return np.hstack([np.eye(3), np.zeros((3, 3))])

    def apply(self, nu: np.ndarray) -> None:
        self.v, self.w = nu[:3].copy(), nu[3:].copy()

    def integrate(self, h: float) -> None:
        self.p = self.p + h * self.v
        self.quat = quat_mul_exp(self.quat, self.w, h)

    def project(self, dc: np.ndarray, minv_jt: np.ndarray | None = None) -> None:
        """Move the centre by ``dc`` (3,) [m] (a translation keeps the orientation)."""
        self.p = self.p + dc

    def pose(self) -> np.ndarray:
        return np.concatenate([self.p, self.quat])

    def velocity(self) -> np.ndarray:
        return np.concatenate([self.v, self.w])


def aligning(sin_before: float, sin_after: float, floor: float = sk.SINGULAR_SIN) -> bool:
    """Whether a step that took ``sin(γ2 - γ1)`` of the 3GM's five-bar from ``sin_before`` to
    ``sin_after`` ends singular: below ``floor`` (``FingerBody.SINGULAR_SIN``), or nearer
    zero than the step moved it (one more such step aligns links l3 and l4, or the step
    crossed alignment). The reduced dynamics grow like 1/sin there, beyond what one explicit
    step resolves: a free finger under constant torque went 0.082 -> 0.0029 in a 1 ms
    step, its rates jumped from 78 to 391 rad/s, and the next step closed the loop on its
    other branch 160 mm away (a runaway; found by Hypothesis). In the bundled scenarios
    ``|sin|`` stays above 0.98. Mirrored by the compiled step (``step_kernel``)."""
    return abs(sin_after) < max(floor, abs(sin_after - sin_before))


class FingerBody:
    """The 3GM: motor angles ``θ`` and rates ``θ̇`` (3,); reduced dynamics per step from the
    generated functions of :mod:`planner.sim.spatial.finger_codegen` (equal to the Pinocchio
    path of :class:`~planner.sim.spatial.finger.FingerDynamics`, tested).

    The whole state (angles, rates, centre, Jacobians, ``M_r⁻¹``, the last contact) lives in
    one vector :attr:`x` (layout of :mod:`planner.sim.spatial.step_kernel`), stepped in
    place by the kernel; the attributes below read (copies) and write it."""

    #: |sin(γ2 - γ1)| below which the 3GM is reported singular (links l3, l4 aligned).
    SINGULAR_SIN = sk.SINGULAR_SIN

    def __init__(self, name, gm, theta, theta_dot, tip_radius, friction, gravity):
        self.name, self.gm, self.radius, self.friction = name, gm, tip_radius, friction
        # own copies of the generated functions: their buffers belong to this body
        self.fn = reduced_dynamics_function(gm, gravity).clone()
        self.kin = reduced_dynamics_function(gm, gravity, kinematics=True).clone()
        self.x = np.zeros(sk.STATE_SIZE)
        self.x[sk.TH : sk.TH + 3] = theta
        self.x[sk.THD : sk.THD + 3] = theta_dot
        #: views of x: (θ, θ̇) (6,) and θ̇ (3,) (read-only use: the run loop's guards)
        self.state_view = self.x[sk.TH : sk.THD + 3]
        self.rate_view = self.x[sk.THD : sk.THD + 3]
        self.limits = np.asarray(gm.joint_limits, float)
        self._zero = np.zeros(3)
        self._eval(np.zeros(3), 0.0)

    def _get(i: int, n: int):  # noqa: N805 - property factory
        def get(self):
            return self.x[i : i + n].copy()

        def set_(self, value):
            self.x[i : i + n] = value

        return property(get, set_)

    th = _get(sk.TH, 3)
    thd = _get(sk.THD, 3)

    def _mat(i: int):  # noqa: N805 - property factory
        def get(self):
            return self.x[i : i + 9].reshape(3, 3).copy()

        def set_(self, value):
            self.x[i : i + 9] = np.asarray(value, float).ravel()

        return property(get, set_)

    J = _mat(sk.J)
    Jw = _mat(sk.JW)
    minv = _mat(sk.MINV)
    del _get, _mat

    @property
    def gamma1(self) -> float:
        return float(self.x[sk.G1])

    def _singular(self, sin_c: float) -> SingularConfiguration:
        return SingularConfiguration(
            f"3GM singular at theta = {np.round(self.th, 6).tolist()} rad: the five-bar loop "
            f"cannot close or links l3 and l4 align, or are one step from it (sin(gamma2 - "
            f"gamma1) = {sin_c:.3g})",
            value=float(sin_c),
        )

    def _eval(self, tau, h: float) -> np.ndarray:
        c, J, Jw, Minv, thd_f, g1, _, _, sin_c = self.fn(self.th, self.thd, tau, h)
        if (
            not (np.isfinite(c[0]) and np.isfinite(thd_f).all())
            or abs(sin_c[0]) < self.SINGULAR_SIN
        ):
            raise self._singular(sin_c[0])
        x = self.x
        x[sk.C : sk.C + 3] = c
        self.J, self.Jw, self.minv = J, Jw, Minv
        x[sk.G1], x[sk.SIN] = g1[0], sin_c[0]
        return thd_f.copy()

    @property
    def center(self) -> np.ndarray:
        return self.x[sk.C : sk.C + 3].copy()

    def free_velocity(self, h: float, gravity: np.ndarray, tau) -> np.ndarray:
        return self._eval(tau, h)

    def point_jacobian(self, n: np.ndarray) -> np.ndarray:
        """(3, 3) velocity of the tip's material point at ``c - r n``: ``J + r [n]× J_ω``."""
        return self.J + self.radius * (skew(n) @ self.Jw)

    def centre_jacobian(self) -> np.ndarray:
        return self.J

    def apply(self, nu: np.ndarray) -> None:
        self.thd = nu

    def integrate(self, h: float) -> None:
        self.th = self.th + h * self.thd
        self._refresh_center()

    def project(self, dc: np.ndarray, dq: np.ndarray | None = None) -> None:
        """Move the joints by ``dq`` (3,) [rad] (the caller's mass-weighted correction).

        The projection's corrections are tiny (|dq| ~ 1e-9 rad): the centre is moved by
        ``J dq``, exact to O(|dq|²) ~ 1e-18 m; the next step re-evaluates everything."""
        self.th = self.th + dq
        self.shift_center(self.J @ dq)

    def _refresh_center(self) -> None:
        """Kinematics at the new angles (centre, J, J_ω, γ1; M_r⁻¹ is left for the step).

        Singular also when the step brought the links closer to alignment than one more
        such step would (:func:`aligning`)."""
        c, J, Jw, g1, sin_c, _ = self.kin(self.th)
        if not np.isfinite(c[0]) or aligning(float(self.x[sk.SIN]), sin_c[0], self.SINGULAR_SIN):
            raise self._singular(sin_c[0])
        self.x[sk.C : sk.C + 3] = c
        self.J, self.Jw = J, Jw
        self.x[sk.G1], self.x[sk.SIN] = g1[0], sin_c[0]

    def shift_center(self, dc: np.ndarray) -> None:
        """Move the cached centre by ``dc`` [m] (first-order update after a tiny projection)."""
        self.x[sk.C : sk.C + 3] += dc

    def tcs(self) -> np.ndarray:
        return tcs_rotation(self.gamma1, float(self.x[sk.TH + 2]))

    def pose(self) -> np.ndarray:
        """(7,) tip centre [m] and the TCS as a quaternion (wxyz): R_z(θ3) R_y(π/2 - γ1)."""
        x = self.x
        a, b = 0.5 * float(x[sk.TH + 2]), 0.5 * (math.pi / 2 - float(x[sk.G1]))
        ca, sa, cb, sb = math.cos(a), math.sin(a), math.cos(b), math.sin(b)
        return np.array([x[sk.C], x[sk.C + 1], x[sk.C + 2], ca * cb, -sa * sb, ca * sb, sa * cb])

    def velocity(self) -> np.ndarray:
        x = self.x
        thd = x[sk.THD : sk.THD + 3]
        return np.concatenate(
            [x[sk.J : sk.J + 9].reshape(3, 3) @ thd, x[sk.JW : sk.JW + 9].reshape(3, 3) @ thd]
        )
