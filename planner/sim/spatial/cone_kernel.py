"""The exact circular-cone contact problem of one sphere contact in scalar code (numba).

The same cases and arithmetic as :func:`planner.sim.spatial.friction_cone.solve_impulse`
(separate; stick by the adjugate of ``W``; slide by Newton on ``g(φ)`` from the direction
opposite to the sticking impulse), for the compiled step of
:mod:`planner.sim.spatial.step_kernel`. When the sliding Newton does not return a valid root
the caller falls back to the general path (roots of the quartic).
"""

from __future__ import annotations

import math

from planner.jit import njit

__all__ = ["cone_impulse", "slide_newton"]


@njit(cache=True)
def slide_newton(W, ut0, ut1, un, mu, phi, lam):
    """Newton on ``g(φ)`` (:func:`.friction_cone._slide_newton`); False: no valid root."""
    a, w1, w2 = W[0, 0], W[1, 0], W[2, 0]
    t11, t12, t22 = W[1, 1], W[1, 2], W[2, 2]
    dt_ = t22 - t11
    ok = False
    for _ in range(30):
        c, s = math.cos(phi), math.sin(phi)
        A = a - mu * (w1 * c + w2 * s)
        B = -s * ut0 + c * ut1
        Pp = dt_ * c * s + t12 * (c * c - s * s)
        Q = -s * w1 + c * w2
        g = A * B + un * (mu * Pp - Q)
        dA = -mu * (-w1 * s + w2 * c)
        dB = -c * ut0 - s * ut1
        dP = dt_ * (c * c - s * s) - 4.0 * t12 * c * s
        dQ = -c * w1 - s * w2
        dg = dA * B + A * dB + un * (mu * dP - dQ)
        if dg == 0.0:
            break
        step = g / dg
        phi -= step
        if abs(step) <= 1e-15:
            ok = True
            break
    c, s = math.cos(phi), math.sin(phi)
    den = a - mu * (w1 * c + w2 * s)
    if not ok or den <= 0.0:
        return False
    lam_n = -un / den
    u0 = ut0 + lam_n * (w1 - mu * (t11 * c + t12 * s))
    u1 = ut1 + lam_n * (w2 - mu * (t12 * c + t22 * s))
    slip = c * u0 + s * u1
    if lam_n < 0.0 or slip < 0.0 or abs(-s * u0 + c * u1) > 1e-12 * abs(slip) + 1e-15:
        return False
    lam[0], lam[1], lam[2] = lam_n, -mu * lam_n * c, -mu * lam_n * s
    return True


@njit(cache=True)
def cone_impulse(W, un, u1, u2, mu, lam):
    """One contact with the exact circular cone (:func:`.friction_cone.solve_impulse`):
    ``lam`` (3,) [N s]; returns 1 separate, 2 stick, 3 slide, -1 (no valid sliding root)."""
    lam[0], lam[1], lam[2] = 0.0, 0.0, 0.0
    if un >= 0.0:
        return 1
    A_ = W[1, 1] * W[2, 2] - W[1, 2] * W[2, 1]
    B_ = W[1, 2] * W[2, 0] - W[1, 0] * W[2, 2]
    C_ = W[1, 0] * W[2, 1] - W[1, 1] * W[2, 0]
    det = W[0, 0] * A_ + W[0, 1] * B_ + W[0, 2] * C_
    D_ = W[0, 2] * W[2, 1] - W[0, 1] * W[2, 2]
    E_ = W[0, 0] * W[2, 2] - W[0, 2] * W[2, 0]
    F_ = W[0, 1] * W[2, 0] - W[0, 0] * W[2, 1]
    G_ = W[0, 1] * W[1, 2] - W[0, 2] * W[1, 1]
    H_ = W[0, 2] * W[1, 0] - W[0, 0] * W[1, 2]
    I_ = W[0, 0] * W[1, 1] - W[0, 1] * W[1, 0]
    l0 = -(A_ * un + D_ * u1 + G_ * u2) / det
    l1 = -(B_ * un + E_ * u1 + H_ * u2) / det
    l2 = -(C_ * un + F_ * u1 + I_ * u2) / det
    if l0 >= 0.0 and math.hypot(l1, l2) <= mu * l0:
        lam[0], lam[1], lam[2] = l0, l1, l2
        return 2
    if mu <= 1e-14:
        lam[0] = -un / W[0, 0]
        return 3
    phi = math.atan2(-l2, -l1) if (l1 != 0.0 or l2 != 0.0) else math.atan2(u2, u1)
    return 3 if slide_newton(W, u1, u2, un, mu, phi, lam) else -1
