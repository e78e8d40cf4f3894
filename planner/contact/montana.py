"""Montana's contact equations (thesis App. A.2, eqs. A.12-A.13; Montana 1988).

Two bodies touch at one point. Body ``i`` has a surface chart ``(f_i, U_i)`` with curvature
form ``K_i``, torsion form ``T_i`` and metric ``M_i`` at the contact (App. A.1), and a contact
frame ``C_li`` (its normalized Gauss frame there, ``z_i`` outward). The frames share the
origin, ``z_2 = -z_1``, and ``ψ`` is the contact angle:
``x_2 = cos ψ x_1 - sin ψ y_1``, ``y_2 = -sin ψ x_1 - cos ψ y_1``.

Velocity convention (App. A.2): ``v = (vx, vy, vz)`` and ``omega = (wx, wy, wz)`` are the
translational and rotational velocity of **body 1 relative to body 2**, the translational
part taken at the contact point (of the material point of body 1 there), both expressed in
body 1's contact frame ``C_l1``. Keeping contact requires ``vz = 0``. Rolling is
``vx = vy = 0``, spinning is ``wz != 0``, sliding ``(vx, vy) != 0`` (Table 2.1).

.. math::

    \\dot u_1 = M_1^{-1} (K_1 + \\tilde K_2)^{-1} ([-ω_y, ω_x]^T - \\tilde K_2 [v_x, v_y]^T)

    \\dot u_2 = M_2^{-1} R_ψ (K_1 + \\tilde K_2)^{-1} ([-ω_y, ω_x]^T + K_1 [v_x, v_y]^T)

    \\dot ψ = ω_z + T_1 M_1 \\dot u_1 + T_2 M_2 \\dot u_2

with ``R_ψ = [[cos ψ, -sin ψ], [-sin ψ, -cos ψ]]`` and ``K̃_2 = R_ψ K_2 R_ψ`` (A.13).
"""

from __future__ import annotations

import math

import numpy as np

from planner.errors import ContactLost, InvalidParameter, SingularConfiguration

VZ_TOLERANCE = 1e-9  # |vz| allowed relative to max(1, |vx|, |vy|) [m/s]


def _mat(name: str, value, shape: tuple[int, ...]) -> list[float]:
    """Validate a small matrix and return its entries (row-major) as Python floats.

    Not :mod:`planner.checks`: this runs at every integrator stage (a plain-float check is
    ~10x cheaper than numpy's); the messages follow its format.
    """
    a = np.asarray(value, dtype=float)
    if a.shape != shape and not (shape == (1, 2) and a.shape == (2,)):
        raise InvalidParameter(f"{name}: expected shape {shape}, got shape {a.shape}")
    vals = a.ravel().tolist()
    if not math.isfinite(sum(vals)):
        raise InvalidParameter(f"{name}: expected finite values, got {vals}")
    return vals


def r_psi(psi: float) -> np.ndarray:
    """The reflection ``R_ψ`` of eq. A.13: (2, 2); symmetric, ``R_ψ R_ψ = I``; maps
    tangent coordinates in ``C_l1`` to coordinates in ``C_l2`` and back."""
    c, s = math.cos(psi), math.sin(psi)
    return np.array([[c, -s], [-s, -c]])


def montana_rates(
    K1, T1, M1, K2, T2, M2, psi: float, v, omega
) -> tuple[np.ndarray, np.ndarray, float]:
    """Contact-point rates from the relative motion of two bodies (eqs. A.12-A.13).

    Args:
        K1, K2: (2, 2) curvature forms of bodies 1 and 2 at the contact (A.2) [1/m].
        T1, T2: (1, 2) torsion forms (A.3) [1/m] (a length-2 vector is accepted).
        M1, M2: (2, 2) metrics (A.4) [m per unit of u]; diagonal for orthogonal charts.
        psi: contact angle ``ψ`` between ``x_1`` and ``x_2`` [rad].
        v: (3,) translational velocity ``(vx, vy, vz)`` of body 1 relative to body 2 at the
            contact, in ``C_l1`` [m/s]; ``vz`` must be 0 (within
            ``VZ_TOLERANCE * max(1, |vx|, |vy|)``).
        omega: (3,) rotational velocity ``(wx, wy, wz)`` of body 1 relative to body 2, in
            ``C_l1`` [rad/s].

    Returns:
        ``(u1_dot, u2_dot, psi_dot)``: (2,) rates of the contact coordinates on body 1 and 2
        [units of u per s], and ``ψ̇`` [rad/s].

    Raises:
        InvalidParameter: bad shapes or non-finite values.
        ContactLost: ``vz != 0`` (the bodies separate or interpenetrate).
        SingularConfiguration: ``K1 + K̃2`` or a metric is singular (e.g. two planes, or a
            ball in a socket of the same radius: the contact point is not determined).
    """
    k1 = _mat("K1", K1, (2, 2))
    a1, b1, c1, d1 = k1
    a, b, cc, d = _mat("K2", K2, (2, 2))
    t1 = _mat("T1", T1, (1, 2))
    t2 = _mat("T2", T2, (1, 2))
    m1 = _mat("M1", M1, (2, 2))
    m2 = _mat("M2", M2, (2, 2))
    vx, vy, vz = _mat("v", v, (3,))
    wx, wy, wz = _mat("omega", omega, (3,))
    psi = float(psi)
    if not math.isfinite(psi):
        raise InvalidParameter(f"psi: expected a finite number [rad], got {psi!r}")
    if abs(vz) > VZ_TOLERANCE * max(1.0, abs(vx), abs(vy)):
        raise ContactLost(
            f"vz = {vz!r} m/s: the relative velocity must keep contact "
            f"(vz = 0, eq. A.12); separate or approach the bodies explicitly"
        )
    c, s = math.cos(psi), math.sin(psi)
    # K~2 = Rψ K2 Rψ, with Rψ = [[c, -s], [-s, -c]]
    r00, r01, r11 = c, -s, -c
    p00, p01 = r00 * a + r01 * cc, r00 * b + r01 * d
    p10, p11 = r01 * a + r11 * cc, r01 * b + r11 * d
    kt00, kt01 = p00 * r00 + p01 * r01, p00 * r01 + p01 * r11
    kt10, kt11 = p10 * r00 + p11 * r01, p10 * r01 + p11 * r11
    s00, s01, s10, s11 = a1 + kt00, b1 + kt01, c1 + kt10, d1 + kt11
    det = s00 * s11 - s01 * s10
    scale = max(abs(s00), abs(s01), abs(s10), abs(s11), 1e-300)
    if abs(det) <= 1e-12 * scale * scale:
        raise SingularConfiguration(
            f"K1 + R_psi K2 R_psi is singular (det = {det:.3g}): the relative curvature "
            f"vanishes in some direction (e.g. plane on plane, or equal and opposite "
            f"curvatures), so the contact point motion is not determined",
            value=det,
        )
    q0 = -wy - (kt00 * vx + kt01 * vy)
    q1 = wx - (kt10 * vx + kt11 * vy)
    w0 = (s11 * q0 - s01 * q1) / det  # (K1 + K~2)^-1 q  = M1 u1_dot
    w1 = (-s10 * q0 + s00 * q1) / det
    e0 = -wy + a1 * vx + b1 * vy
    e1 = wx + c1 * vx + d1 * vy
    g0 = (s11 * e0 - s01 * e1) / det
    g1 = (-s10 * e0 + s00 * e1) / det
    h0, h1 = r00 * g0 + r01 * g1, r01 * g0 + r11 * g1  # M2 u2_dot
    u1d = _solve_metric("M1", m1, w0, w1)
    u2d = _solve_metric("M2", m2, h0, h1)
    psi_dot = wz + t1[0] * w0 + t1[1] * w1 + t2[0] * h0 + t2[1] * h1
    return u1d, u2d, float(psi_dot)


def _solve_metric(name: str, m: list[float], a: float, b: float) -> np.ndarray:
    m00, m01, m10, m11 = m
    det = m00 * m11 - m01 * m10
    if abs(det) <= 1e-14 * max(abs(m00), abs(m11), 1e-300) ** 2:
        raise SingularConfiguration(
            f"{name} is singular (det = {det:.3g}): the chart is "
            f"degenerate at the contact (a pole?)",
            value=det,
        )
    return np.array([(m11 * a - m01 * b) / det, (-m10 * a + m00 * b) / det])


__all__ = ["VZ_TOLERANCE", "montana_rates", "r_psi"]
