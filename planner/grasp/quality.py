"""Ferrari–Canny ε grasp quality with the L1 (unit sum of contact forces) bound.

The grasp wrench space is ``W_L1 = conv(∪_i {w_ij})`` over the primitive wrenches of
:mod:`planner.grasp.wrenches` (unit-norm cone-edge forces); ε is the radius of the largest
origin-centred ball inside it, i.e. the smallest facet distance of the hull from the origin,
and 0 when the origin is not strictly inside (no force closure).

**Normalization.** Wrenches are ``(f, τ/ρ)`` [N]: torques are taken about the centroid of the
contacts (or ``torque_reference``) and divided by ``ρ``, the largest distance of a contact from
that point (or ``torque_scale``). ε is therefore dimensionless per unit total contact force,
at most 1, and invariant under rigid motions and uniform scaling of the grasp.

For two planar contacts the hull is a tetrahedron of four wrenches and ε has the closed form
of :func:`epsilon_two_planar` (vectorized over batches); otherwise Qhull is used.
"""

from __future__ import annotations

import numpy as np

from planner import checks
from planner.grasp.closure import HULL_TOL, hull_offsets
from planner.grasp.wrenches import check_contacts, primitive_wrenches

# vertex triples of the 4 faces of a tetrahedron and the omitted vertex of each
_FACES = ((1, 2, 3, 0), (0, 2, 3, 1), (0, 1, 3, 2), (0, 1, 2, 3))


def _cross3(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def epsilon_two_planar(p1, n1, p2, n2, mu: float, mu2: float | None = None) -> np.ndarray:
    """Closed-form ε of two planar point contacts with friction, vectorized.

    With torques about the midpoint divided by the half-distance ``ρ = |p2 - p1|/2``, the
    four primitive wrenches are ``(f, r × f)`` with ``r = ∓u`` (``u`` the unit contact-line
    direction) and ``f`` the unit cone edges; ε is the smallest distance of the origin to the
    faces of their tetrahedron when the origin is strictly inside it, else 0.

    Computation: in the frame where ``u = (1, 0)`` an edge at angle β gives the wrench
    ``(cos β, sin β, ∓sin β)``; the isometry ``(x, y, z) -> (x, (y - z)/√2, (y + z)/√2)``
    maps contact 1's wrenches to ``A = (cos β, √2 sin β, 0)`` and contact 2's to
    ``B = (cos β', 0, √2 sin β')``, which makes the four face normals cheap.

    Args:
        p1, p2: (..., 2) contact points [m] (broadcastable).
        n1, n2: (..., 2) inward unit normals.
        mu: friction coefficient (>= 0) at ``p1`` (and ``p2`` unless ``mu2`` is given).
        mu2: friction coefficient at ``p2``.

    Returns:
        (...) ε >= 0 (same as :func:`epsilon_quality` on each grasp).
    """
    mu = checks.nonnegative("mu", mu)
    mu2 = mu if mu2 is None else checks.nonnegative("mu2", mu2)
    p1, n1, p2, n2 = (np.asarray(a, dtype=float) for a in (p1, n1, p2, n2))
    dx = p2[..., 0] - p1[..., 0]
    dy = p2[..., 1] - p1[..., 1]
    dist = np.hypot(dx, dy)
    safe = np.where(dist > 0, dist, 1.0)
    ux, uy = dx / safe, dy / safe
    r2 = np.sqrt(2.0)

    def edges(n, m):
        c = n[..., 0] * ux + n[..., 1] * uy  # cos of the normal's angle to u
        s = ux * n[..., 1] - uy * n[..., 0]  # sin
        cg, sg = 1.0 / np.sqrt(1.0 + m * m), m / np.sqrt(1.0 + m * m)
        return ((c * cg + s * sg, s * cg - c * sg), (c * cg - s * sg, s * cg + c * sg))

    (a1c, a1s), (a2c, a2s) = edges(n1, mu)  # contact 1: A = (cos, √2 sin, 0)
    (b1c, b1s), (b2c, b2s) = edges(n2, mu2)  # contact 2: B = (cos, 0, √2 sin)
    a1y, a2y, b1z, b2z = r2 * a1s, r2 * a2s, r2 * b1s, r2 * b2s
    eps = np.full(dist.shape, np.inf)
    inside = dist > 0
    # faces (A1, A2, B) omitting the other B
    ex, ey = a2c - a1c, a2y - a1y
    k = ey * a1c - ex * a1y
    lxy = ex * ex + ey * ey
    for (bx, bz), (ox, oz) in (((b1c, b1z), (b2c, b2z)), ((b2c, b2z), (b1c, b1z))):
        nz = -ex * a1y - ey * (bx - a1c)
        sa = bz * k
        so = ey * bz * ox + nz * oz - sa
        nn = np.sqrt(bz * bz * lxy + nz * nz)
        d = np.abs(sa) / np.where(nn > 1e-12, nn, 1.0)
        inside &= (-sa * so > 0) & (nn > 1e-12) & (d > HULL_TOL)
        eps = np.minimum(eps, d)
    # faces (B1, B2, A) omitting the other A
    fx, fz = b2c - b1c, b2z - b1z
    m = fx * b1z - fz * b1c
    lxz = fx * fx + fz * fz
    for (ax, ay), (ox, oy) in (((a1c, a1y), (a2c, a2y)), ((a2c, a2y), (a1c, a1y))):
        ny = fz * (ax - b1c) + fx * b1z
        sa = ay * m
        so = -fz * ay * ox + ny * oy - sa
        nn = np.sqrt(ay * ay * lxz + ny * ny)
        d = np.abs(sa) / np.where(nn > 1e-12, nn, 1.0)
        inside &= (-sa * so > 0) & (nn > 1e-12) & (d > HULL_TOL)
        eps = np.minimum(eps, d)
    return np.where(inside, eps, 0.0)


def epsilon_quality(
    points,
    normals,
    mu: float,
    *,
    torque_reference=None,
    torque_scale=None,
    facets: int = 8,
    contact: str = "point_with_friction",
    torsion_length: float = 0.0,
) -> float:
    """Ferrari–Canny ε quality (L1: unit-bounded sum of contact forces).

    Args:
        points: (k, 2) or (k, 3) contact points [m], k >= 2.
        normals: (k, 2) or (k, 3) inward unit normals (normalized here).
        mu: friction coefficient (>= 0).
        torque_reference: (d,) point about which torques are measured [m]
            (default: centroid of the contacts).
        torque_scale: length ``ρ`` dividing torques [m] (default: the largest distance of a
            contact from the torque reference).
        facets: spatial only: pyramid edges per friction cone.
        contact: contact model (``"point_with_friction"``, ``"frictionless"``,
            ``"soft_finger"``; see :func:`planner.grasp.wrenches.primitive_wrenches`).
        torsion_length: soft-finger torsional friction length ``e_n`` [m].

    Returns:
        ε in [0, 1]: radius of the largest origin-centred ball in the grasp wrench space of
        wrenches ``(f, τ/ρ)``; 0 when the grasp is not in force closure.
    """
    p, n = check_contacts(points, normals, 2)
    mu = checks.nonnegative("mu", mu)
    w = primitive_wrenches(
        p,
        n,
        mu,
        torque_reference=torque_reference,
        torque_scale=torque_scale,
        facets=facets,
        contact=contact,
        torsion_length=torsion_length,
    )
    if p.shape == (2, 2) and torque_reference is None and torque_scale is None:
        mu = 0.0 if getattr(contact, "value", contact) == "frictionless" else mu
        return float(epsilon_two_planar(p[0], n[0], p[1], n[1], mu))
    offsets = hull_offsets(w)
    if offsets is None or not np.all(offsets < -HULL_TOL):
        return 0.0
    return float(np.min(-offsets))


__all__ = ["epsilon_quality", "epsilon_two_planar"]
