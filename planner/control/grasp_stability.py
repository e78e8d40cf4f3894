"""The grasp-stability check of the gait's control step: ε of two planar contacts, compiled.

:func:`epsilon_two_contacts` is :func:`planner.grasp.epsilon_two_planar` (Ferrari-Canny ε,
L1 bound, torques about the contacts' midpoint over their half-distance) for ONE grasp, as a
numba function of two (2, 2) arrays: the controller evaluates it at every phase-1 control
step ("grasp stability lost", Fig. 2.3), where the vectorized numpy version cost ~100 us
and this one well under 1 us. Same formulas, same operation order (tested equal).
"""

from __future__ import annotations

import math

from planner.grasp.closure import HULL_TOL
from planner.jit import njit


@njit(cache=True, nogil=True)
def epsilon_two_contacts(points, normals, mu: float, sign: float) -> float:  # pragma: no cover
    """ε of the grasp of two planar point contacts with friction ``mu`` [-].

    Args:
        points: (2, 2) contact points [m].
        normals: (2, 2) unit contact normals; ``sign`` * ``normals`` must point INTO the
            object (``sign = -1`` for outward object normals, ``+1`` for inward ones).
        mu: friction coefficient (>= 0, not checked: hot path).
        sign: +1.0 or -1.0.

    Returns:
        ε >= 0 (0 without force closure), as :func:`planner.grasp.epsilon_two_planar`.
    """
    return epsilon_two_scalar(
        points[0, 0], points[0, 1], points[1, 0], points[1, 1], sign * normals[0, 0],
        sign * normals[0, 1], sign * normals[1, 0], sign * normals[1, 1], mu,
    )  # fmt: skip


@njit(cache=True, nogil=True)
def epsilon_two_scalar(p1x, p1y, p2x, p2y, n1x, n1y, n2x, n2y, mu):  # pragma: no cover
    """:func:`epsilon_two_contacts` on scalars: points ``p1``, ``p2`` [m], INWARD unit
    normals ``n1``, ``n2``, friction ``mu`` [-] (for other compiled code)."""
    dx = p2x - p1x
    dy = p2y - p1y
    dist = math.hypot(dx, dy)
    if not dist > 0:
        return 0.0
    ux, uy = dx / dist, dy / dist
    r2 = math.sqrt(2.0)
    cg, sg = 1.0 / math.sqrt(1.0 + mu * mu), mu / math.sqrt(1.0 + mu * mu)
    c, s = n1x * ux + n1y * uy, ux * n1y - uy * n1x
    a1c, a1s, a2c, a2s = c * cg + s * sg, s * cg - c * sg, c * cg - s * sg, s * cg + c * sg
    c, s = n2x * ux + n2y * uy, ux * n2y - uy * n2x
    b1c, b1s, b2c, b2s = c * cg + s * sg, s * cg - c * sg, c * cg - s * sg, s * cg + c * sg
    a1y, a2y, b1z, b2z = r2 * a1s, r2 * a2s, r2 * b1s, r2 * b2s
    eps = math.inf
    inside = True
    # faces (A1, A2, B) omitting the other B
    ex, ey = a2c - a1c, a2y - a1y
    k = ey * a1c - ex * a1y
    lxy = ex * ex + ey * ey
    for i in range(2):
        bx, bz, ox, oz = (b1c, b1z, b2c, b2z) if i == 0 else (b2c, b2z, b1c, b1z)
        nz = -ex * a1y - ey * (bx - a1c)
        sa = bz * k
        so = ey * bz * ox + nz * oz - sa
        nn = math.sqrt(bz * bz * lxy + nz * nz)
        d = abs(sa) / (nn if nn > 1e-12 else 1.0)
        inside = inside and (-sa * so > 0) and (nn > 1e-12) and (d > HULL_TOL)
        eps = min(eps, d)
    # faces (B1, B2, A) omitting the other A
    fx, fz = b2c - b1c, b2z - b1z
    m = fx * b1z - fz * b1c
    lxz = fx * fx + fz * fz
    for i in range(2):
        ax, ay, ox, oy = (a1c, a1y, a2c, a2y) if i == 0 else (a2c, a2y, a1c, a1y)
        ny = fz * (ax - b1c) + fx * b1z
        sa = ay * m
        so = -fz * ay * ox + ny * oy - sa
        nn = math.sqrt(ay * ay * lxz + ny * ny)
        d = abs(sa) / (nn if nn > 1e-12 else 1.0)
        inside = inside and (-sa * so > 0) and (nn > 1e-12) and (d > HULL_TOL)
        eps = min(eps, d)
    return eps if inside else 0.0


__all__ = ["epsilon_two_contacts", "epsilon_two_scalar"]
