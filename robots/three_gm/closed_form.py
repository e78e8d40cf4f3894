"""Closed-form kinematics of the 3GM five-bar finger (thesis App. C.2, eqs. C.4-C.11, 4.1).

Geometry (Fig. C.5, as implied by eqs. C.4-C.6). In the plane of the five-bar, with
coordinates (r, z): motor 1 at the origin drives link l1 to ``P1 = l1 u(θ1)``; motor 2 at
``(0, -h1)`` drives link l2 to ``P2 = (0, -h1) + l2 u(θ2)``, where ``u(a) = (cos a, sin a)``.
A passive link leaves P1 at angle γ1; at distance l4 from P1 it is joined to the passive link
l3 from P2 (angle γ2); its end, at distance l5 from P1, is the endpoint. The loop closure is

.. math:: P_1 + l_4 u(\\gamma_1) = P_2 + l_3 u(\\gamma_2).

With ``a = P1 - P2 = (a1, a2)`` (eq. C.4) the closure gives ``a·u(γ1) = b1`` and
``a·u(γ2) = b2`` (eq. C.5's b1, b2), hence ``γ_i = c ∓ arccos(b_i/|a|)``; the elbow-up branch
used in the thesis takes the minus sign for both (the plus sign for γ2 would not close the
loop with γ1's minus sign). The base rotates the plane by θ3 about the vertical z axis, with
offsets h2 (radial) and h3 (lateral) of the endpoint (eq. C.6).

Jacobian (eq. C.7). Differentiating the closure and projecting on u(γ2) gives

.. math::

    \\frac{\\partial\\gamma_1}{\\partial\\theta_1} = \\frac{l_1\\sin(\\theta_1-\\gamma_2)}
        {l_4\\sin(\\gamma_2-\\gamma_1)},\\qquad
    \\frac{\\partial\\gamma_1}{\\partial\\theta_2} = \\frac{l_2\\sin(\\gamma_2-\\theta_2)}
        {l_4\\sin(\\gamma_2-\\gamma_1)},

so ``c1 = l5 ∂γ1/∂θ1`` and ``c2 = l5 ∂γ1/∂θ2``. The OCR'd eq. C.8 prints ``sin(θ1 - γ1)``
in c1 (it must be ``sin(θ1 - γ2)``) and ``∂r/∂θ2 = -cos θ3 sin θ1`` (it must be
``-c2 sin γ1``); both are corrected here and checked against finite differences and
Pinocchio. Eq. C.9 is then correct as printed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner.errors import SingularConfiguration


@dataclass(frozen=True)
class FiveBarState:
    """Intermediate quantities of eqs. C.4-C.6 at one configuration.

    Attributes:
        a1, a2: components of P1 - P2 [m] (eq. C.4/C.5).
        b1, b2: projections of (P1 - P2) on u(γ1), u(γ2) [m] (eq. C.5).
        c: direction of (a1, a2) [rad].
        gamma1, gamma2: passive angles [rad] (eq. C.5, elbow-up).
        r: in-plane radial coordinate of the endpoint [m] (eq. C.6).
        position: (3,) endpoint (x, y, z) in the WCS [m] (eq. C.6).
    """

    a1: float
    a2: float
    b1: float
    b2: float
    c: float
    gamma1: float
    gamma2: float
    r: float
    position: np.ndarray


def five_bar_state(p: dict[str, float], theta: np.ndarray) -> FiveBarState:
    """Evaluate eqs. C.4-C.6.

    Args:
        p: parameters ``l1..l5, h1..h3`` [m].
        theta: (3,) joint angles (θ1, θ2, θ3) [rad].

    Raises:
        SingularConfiguration: an arccos argument ``b_i/|a|`` of eq. C.5 leaves [-1, 1] (the
            loop cannot close), or ``|a| = 0``; ``value`` holds the offending argument.
    """
    t1, t2, t3 = float(theta[0]), float(theta[1]), float(theta[2])
    l1, l2, l3, l4, l5 = p["l1"], p["l2"], p["l3"], p["l4"], p["l5"]
    c1, s1 = math.cos(t1), math.sin(t1)
    a1 = l1 * c1 - l2 * math.cos(t2)
    a2 = l1 * s1 - l2 * math.sin(t2) + p["h1"]
    aa = a1 * a1 + a2 * a2
    na = math.sqrt(aa)
    if na < 1e-12:
        raise SingularConfiguration(
            f"the passive joints P1 and P2 coincide (|a| = {na:.3g} m) at theta = "
            f"{np.asarray(theta).tolist()} rad",
            value=float(na),
        )
    b1 = (l3 * l3 - l4 * l4 - aa) / (2.0 * l4)
    b2 = (l3 * l3 - l4 * l4 + aa) / (2.0 * l3)
    c = math.atan2(a2 / na, a1 / na)
    for name, b in (("b1", b1), ("b2", b2)):
        arg = b / na
        if not -1.0 <= arg <= 1.0:
            raise SingularConfiguration(
                f"five-bar cannot close at theta = {np.asarray(theta).tolist()} rad: arccos "
                f"argument {name}/|a| = {arg:.6g} of eq. C.5 is outside [-1, 1]",
                value=float(arg),
            )
    g1 = c - math.acos(b1 / na)
    g2 = c - math.acos(b2 / na)
    r = l1 * c1 + l5 * math.cos(g1)
    z = l1 * s1 + l5 * math.sin(g1)
    h2, h3 = p["h2"], p["h3"]
    c3, s3 = math.cos(t3), math.sin(t3)
    pos = np.array([(r + h2) * c3 + h3 * s3, (r + h2) * s3 - h3 * c3, z])
    return FiveBarState(a1, a2, b1, b2, c, g1, g2, r, pos)


def jacobian_from_state(
    p: dict[str, float], theta: np.ndarray, st: FiveBarState, min_sin: float = 1e-9
) -> np.ndarray:
    """The (3, 3) Jacobian d(x, y, z)/d(θ1, θ2, θ3) [m/rad] (eqs. C.7-C.9, corrected C.8).

    Raises:
        SingularConfiguration: links l3 and l4 are aligned (``sin(γ2 - γ1) = 0``), where the
            passive angles are not differentiable; ``value`` holds ``sin(γ2 - γ1)``.
    """
    t1, t2, t3 = float(theta[0]), float(theta[1]), float(theta[2])
    g1, g2 = st.gamma1, st.gamma2
    den = math.sin(g2 - g1)
    if abs(den) < min_sin:
        raise SingularConfiguration(
            f"links l3 and l4 are aligned at theta = {np.asarray(theta).tolist()} rad "
            f"(sin(gamma2 - gamma1) = {den:.3g}); the Jacobian is singular",
            value=float(den),
        )
    l1, l2, l4, l5 = p["l1"], p["l2"], p["l4"], p["l5"]
    c1 = l1 * l5 * math.sin(t1 - g2) / (l4 * den)
    c2 = l2 * l5 * math.sin(g2 - t2) / (l4 * den)
    sg1, cg1 = math.sin(g1), math.cos(g1)
    dr1 = -l1 * math.sin(t1) - c1 * sg1
    dr2 = -c2 * sg1
    c3, s3 = math.cos(t3), math.sin(t3)
    rh = st.r + p["h2"]
    h3 = p["h3"]
    return np.array(
        [
            [dr1 * c3, dr2 * c3, -rh * s3 + h3 * c3],
            [dr1 * s3, dr2 * s3, rh * c3 + h3 * s3],
            [l1 * math.cos(t1) + c1 * cg1, c2 * cg1, 0.0],
        ]
    )


def rotation_tcs_to_wcs(gamma1: float, theta3: float) -> np.ndarray:
    """R_TW of eq. 4.1: maps TCS coordinates into the WCS [-].

    ``α = π/2 + γ1``, ``β = π/2 - θ3``; the printed matrix is ``Rz(α) Rx(β)`` (checked).
    """
    al = np.pi / 2 + gamma1
    be = np.pi / 2 - theta3
    ca, sa, cb, sb = np.cos(al), np.sin(al), np.cos(be), np.sin(be)
    return np.array([[ca, -sa * cb, sa * sb], [sa, ca * cb, -ca * sb], [0.0, sb, cb]])
