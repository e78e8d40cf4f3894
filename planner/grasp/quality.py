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

from planner.grasp.closure import HULL_TOL, _hull_offsets
from planner.grasp.cones import check_mu
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

    Args:
        p1, p2: (..., 2) contact points [m] (broadcastable).
        n1, n2: (..., 2) inward unit normals.
        mu: friction coefficient (>= 0) at ``p1`` (and ``p2`` unless ``mu2`` is given).
        mu2: friction coefficient at ``p2``.

    Returns:
        (...) ε >= 0 (same as :func:`epsilon_quality` on each grasp).
    """
    mu = check_mu(mu)
    mu2 = mu if mu2 is None else check_mu(mu2)
    p1, n1, p2, n2 = (np.asarray(a, dtype=float) for a in (p1, n1, p2, n2))
    dx = p2[..., 0] - p1[..., 0]
    dy = p2[..., 1] - p1[..., 1]
    dist = np.hypot(dx, dy)
    with np.errstate(invalid="ignore", divide="ignore"):
        ux = np.where(dist > 0, dx / dist, 0.0)
        uy = np.where(dist > 0, dy / dist, 0.0)
    verts = []
    for n, sign, m in ((n1, -1.0, mu), (n2, 1.0, mu2)):  # r = -u at p1, +u at p2
        c = 1.0 / np.sqrt(1.0 + m * m)
        s = m * c
        nx, ny = n[..., 0], n[..., 1]
        for e in (-1.0, 1.0):
            fx = c * nx - e * s * ny
            fy = c * ny + e * s * nx
            tz = sign * (ux * fy - uy * fx)
            verts.append((fx, fy, tz))
    eps = None
    inside = None
    for a, b, cc, o in _FACES:
        va, vb, vc, vo = verts[a], verts[b], verts[cc], verts[o]
        e1 = tuple(vb[i] - va[i] for i in range(3))
        e2 = tuple(vc[i] - va[i] for i in range(3))
        nrm = _cross3(e1, e2)
        nlen = np.sqrt(nrm[0] ** 2 + nrm[1] ** 2 + nrm[2] ** 2)
        sa = nrm[0] * va[0] + nrm[1] * va[1] + nrm[2] * va[2]  # N . w_a
        so = nrm[0] * vo[0] + nrm[1] * vo[1] + nrm[2] * vo[2] - sa  # N . (w_o - w_a)
        with np.errstate(invalid="ignore", divide="ignore"):
            d = np.where(nlen > 1e-12, np.abs(sa) / np.where(nlen > 0, nlen, 1.0), 0.0)
        ok = (-sa * so > 0) & (nlen > 1e-12) & (d > HULL_TOL)
        eps = d if eps is None else np.minimum(eps, d)
        inside = ok if inside is None else inside & ok
    return np.where(inside & (dist > 0), eps, 0.0)


def epsilon_quality(
    points, normals, mu: float, *, torque_reference=None, torque_scale=None, facets: int = 8
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

    Returns:
        ε in [0, 1]: radius of the largest origin-centred ball in the grasp wrench space of
        wrenches ``(f, τ/ρ)``; 0 when the grasp is not in force closure.
    """
    p, n = check_contacts(points, normals, 2)
    mu = check_mu(mu)
    if p.shape == (2, 2) and torque_reference is None and torque_scale is None:
        return float(epsilon_two_planar(p[0], n[0], p[1], n[1], mu))
    w = primitive_wrenches(
        p, n, mu, torque_reference=torque_reference, torque_scale=torque_scale, facets=facets
    )
    offsets = _hull_offsets(w)
    if offsets is None or not np.all(offsets < -HULL_TOL):
        return 0.0
    return float(np.min(-offsets))


__all__ = ["epsilon_quality", "epsilon_two_planar"]
