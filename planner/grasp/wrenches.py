"""Primitive contact wrenches: the generators of the grasp wrench space (Ferrari–Canny).

A primitive wrench is the object wrench of one unit-norm friction-cone edge force at one
contact, ``w = (f, (p - c) x f / rho)``: torques about the reference point ``c`` are divided
by the length ``rho`` so that every component is in newtons and the wrench space, hence ε,
is invariant under rigid motions and uniform scaling of the grasp. The default ``c`` is the
centroid of the contacts and the default ``rho`` the largest contact distance from ``c``.
"""

from __future__ import annotations

import numpy as np

from planner import checks
from planner.contact import ContactType
from planner.contact.cones import (
    planar_cone_edges,
    pyramid_cone_edges,
    soft_finger_generators,
    unit_directions,
)
from planner.errors import InvalidParameter


def check_contacts(points, normals, min_contacts: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """Validate contact points (k, d) and inward normals (k, d), d in {2, 3}; unit normals out."""
    p = checks.points("points", points, min_count=min_contacts)
    n = unit_directions("normals", normals, p.shape[1])
    if n.shape != p.shape:
        raise InvalidParameter(
            f"normals: expected the shape of points {p.shape}, got shape {n.shape}"
        )
    return p, n


def torque_frame(
    points: np.ndarray, torque_reference=None, torque_scale=None
) -> tuple[np.ndarray, float]:
    """Reference point ``c`` (d,) [m] and torque length ``rho`` [m] of the wrench normalization."""
    d = points.shape[1]
    if torque_reference is None:
        c = points.mean(axis=0)
    else:
        c = checks.vector("torque_reference", torque_reference, d, "m")
    if torque_scale is None:
        rho = float(np.max(np.linalg.norm(points - c, axis=1)))
        if rho <= 0:
            rho = 1.0  # all contacts coincide: no torque arm; any scale gives the same hull
    else:
        rho = checks.positive("torque_scale", torque_scale, "m")
    return c, rho


def primitive_wrenches(
    points,
    normals,
    mu: float,
    *,
    torque_reference=None,
    torque_scale=None,
    facets: int = 8,
    contact: str = "point_with_friction",
    torsion_length: float = 0.0,
) -> np.ndarray:
    """Primitive wrenches of the contacts (contact models of Fig. 2.5).

    Args:
        points: (k, 2) or (k, 3) contact points [m].
        normals: (k, 2) or (k, 3) inward unit normals.
        mu: friction coefficient (>= 0); 0 gives frictionless contacts (one generator each).
        torque_reference: (d,) torque reference point [m] (default: contact centroid).
        torque_scale: torque length ``rho`` [m] (default: max contact distance from it).
        facets: pyramid edges per contact in 3-D (>= 3).
        contact: ``"point_with_friction"`` (default), ``"frictionless"`` (normal force only,
            ``mu`` ignored) or ``"soft_finger"`` (spatial: adds moments about the normal up to
            ``torsion_length`` per unit normal force, elliptic limit surface of eq. 2.2,
            linearized; planar: same as a point with friction, the extra moment being out of
            the plane).
        torsion_length: soft finger ``e_n`` [m] (> 0 for ``"soft_finger"`` in 3-D).

    Returns:
        Planar: (2k, 3) rows ``(f_x, f_y, tau_z / rho)`` (k rows if ``mu == 0``).
        Spatial: (k facets, 6) rows ``(f, tau / rho)`` (k rows if ``mu == 0``).
    """
    p, n = check_contacts(points, normals, 1)
    mu = checks.nonnegative("mu", mu)
    contact = checks.choice(
        "contact", getattr(contact, "value", contact), [t.value for t in ContactType]
    )
    if contact == "frictionless":
        mu = 0.0
    c, rho = torque_frame(p, torque_reference, torque_scale)
    r = (p - c) / rho
    if p.shape[1] == 2:
        f = n[:, None, :] if mu == 0 else planar_cone_edges(n, mu)
        tau = r[:, None, 0] * f[..., 1] - r[:, None, 1] * f[..., 0]
        return np.concatenate([f, tau[..., None]], axis=-1).reshape(-1, 3)
    if contact == "soft_finger":
        e = checks.positive("torsion_length", torsion_length, "m")
        g = soft_finger_generators(n, mu, e, facets)  # (k, m, 6): unit normal force
        f, m = g[..., :3], g[..., 3:]
        scale = 1.0 / np.linalg.norm(f, axis=-1, keepdims=True)  # unit-norm forces (L1)
        f, m = f * scale, m * scale
        tau = np.cross(np.broadcast_to(r[:, None, :], f.shape), f) + m / rho
        return np.concatenate([f, tau], axis=-1).reshape(-1, 6)
    f = n[:, None, :] if mu == 0 else pyramid_cone_edges(n, mu, facets, reference=-r)
    tau = np.cross(np.broadcast_to(r[:, None, :], f.shape), f)
    return np.concatenate([f, tau], axis=-1).reshape(-1, 6)


__all__ = ["check_contacts", "primitive_wrenches", "torque_frame"]
