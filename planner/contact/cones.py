"""Friction cones of Fig. 2.5 (eqs. 2.1, 2.2, 2.9): their edges, facets and generators.

In the plane the cone of a point contact with friction is exact: two edges. In space it is
inscribed by an ``m``-facet pyramid (edges at angle ``atan(mu)`` from the normal, so every edge
force satisfies eq. 2.1 exactly and the pyramid approaches the cone as ``m`` grows). The soft
finger (eq. 2.2) adds a moment about the normal bounded by the elliptic approximation of the
limit surface (Kao and Cutkosky)::

    |f_t|^2 / mu^2 + m_z^2 / e_n^2 <= f_n^2

with ``e_n`` the torsional friction length [m]. The same cones are given by their edges
(:func:`planar_cone_edges`, :func:`pyramid_cone_edges`, for wrench-space hulls) and by their
facets (:func:`cone_halfspaces`, for QPs).
"""

from __future__ import annotations

import numpy as np

from planner import checks
from planner.errors import InvalidParameter

__all__ = [
    "cone_halfspaces",
    "planar_cone_edges",
    "pyramid_cone_edges",
    "soft_finger_generators",
    "tangent_basis",
    "unit_directions",
]


def unit_directions(name: str, value, dim: int | None = None) -> np.ndarray:
    """Validate a (k, d) array of non-zero direction vectors and return it with unit rows.

    Args:
        name: the argument's name, for the message.
        value: (k, 2) or (k, 3) directions (e.g. contact normals).
        dim: the required ``d`` (2 or 3), if any.

    Raises:
        InvalidParameter: wrong shape, NaN/inf, or a (near-)zero row.
    """
    arr = checks.points(name, value, dims=(dim,) if dim else (2, 3), unit="")
    norms = np.linalg.norm(arr, axis=1)
    if np.any(norms < 1e-12):
        raise InvalidParameter(
            f"{name}: expected non-zero direction vectors, got row {int(np.argmin(norms))} "
            f"of norm {norms.min():.3g}"
        )
    return arr / norms[:, None]


def planar_cone_edges(normals, mu: float) -> np.ndarray:
    """Unit edge forces of planar friction cones (exact, eq. 2.9).

    Args:
        normals: (k, 2) inward unit contact normals (pointing into the object).
        mu: friction coefficient (>= 0).

    Returns:
        (k, 2, 2) unit forces ``[i, j]`` of edge ``j`` (``j = 0`` rotated clockwise from the
        normal, ``j = 1`` counter-clockwise), each at angle ``atan(mu)`` from the normal.
    """
    n = unit_directions("normals", normals, 2)
    mu = checks.nonnegative("mu", mu)
    t = np.stack([-n[:, 1], n[:, 0]], axis=1)  # normal rotated +90 deg
    c = 1.0 / np.sqrt(1.0 + mu * mu)
    s = mu * c
    return np.stack([c * n - s * t, c * n + s * t], axis=1)


def tangent_basis(normals, reference=None) -> tuple[np.ndarray, np.ndarray]:
    """Two unit tangents ``(t1, t2)``, each (k, 3), completing each normal to a right frame.

    Args:
        normals: (k, 3) unit normals.
        reference: (k, 3) optional directions whose tangential part becomes ``t1`` (e.g. the
            direction to the grasp centroid: this makes pyramids move with the grasp under
            rigid motions); rows with a (near-)zero tangential part fall back to a fixed axis.
    """
    n = unit_directions("normals", normals, 3)
    fallback = np.where(np.abs(n[:, [0]]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    t1 = np.cross(np.cross(n, fallback), n)
    if reference is not None:
        ref = np.asarray(reference, dtype=float).reshape(n.shape)
        proj = ref - np.sum(ref * n, axis=1, keepdims=True) * n
        ok = np.linalg.norm(proj, axis=1) > 1e-9 * np.maximum(1.0, np.linalg.norm(ref, axis=1))
        t1 = np.where(ok[:, None], proj, t1)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    return t1, np.cross(n, t1)


def pyramid_cone_edges(normals, mu: float, facets: int = 8, reference=None) -> np.ndarray:
    """Unit edge forces of ``facets``-sided pyramids inscribed in spatial friction cones (eq. 2.1).

    Args:
        normals: (k, 3) inward unit contact normals.
        mu: friction coefficient (>= 0).
        facets: number of pyramid edges (>= 3).
        reference: (k, 3) optional directions fixing the first edge (see :func:`tangent_basis`).

    Returns:
        (k, facets, 3) unit edge forces, each at angle ``atan(mu)`` from its normal.
    """
    facets = checks.integer("facets", facets, 3)
    n = unit_directions("normals", normals, 3)
    mu = checks.nonnegative("mu", mu)
    t1, t2 = tangent_basis(n, reference)
    a = 2 * np.pi * np.arange(int(facets)) / int(facets)
    c = 1.0 / np.sqrt(1.0 + mu * mu)
    s = mu * c
    return c * n[:, None, :] + s * (
        np.cos(a)[None, :, None] * t1[:, None, :] + np.sin(a)[None, :, None] * t2[:, None, :]
    )


def soft_finger_generators(
    normals, mu: float, torsion_length: float, facets: int = 8
) -> np.ndarray:
    """Generators of the linearized soft-finger cone (elliptic limit surface of eq. 2.2).

    Each generator is a unit-normal-force contact wrench ``(f (3,), m_z n (3,))`` in the contact
    point's frame: the pyramid edges of :func:`pyramid_cone_edges` with no moment, plus the two
    pure-torsion extremes ``(n, +-e_n n)``. Every generator satisfies the ellipse
    ``|f_t|^2/mu^2 + m_z^2/e_n^2 <= f_n^2`` and their convex cone is inscribed in it.

    Args:
        normals: (k, 3) inward unit normals.
        mu: friction coefficient (>= 0).
        torsion_length: ``e_n`` >= 0, the largest moment about the normal per unit normal
            force [m].
        facets: pyramid edges (>= 3).

    Returns:
        (k, facets + 2, 6) generators ``[force (3), moment (3)]``, forces scaled to unit normal
        component.
    """
    e = checks.nonnegative("torsion_length", torsion_length, "m")
    facets = checks.integer("facets", facets, 3)
    n = unit_directions("normals", normals, 3)
    edges = pyramid_cone_edges(n, mu, facets) * np.sqrt(1.0 + checks.nonnegative("mu", mu) ** 2)
    k = n.shape[0]
    gens = np.zeros((k, facets + 2, 6))
    gens[:, :facets, :3] = edges
    gens[:, facets:, :3] = n[:, None, :]
    gens[:, facets, 3:] = e * n
    gens[:, facets + 1, 3:] = -e * n
    return gens


def cone_halfspaces(normals, mu: float, facets: int = 8) -> np.ndarray:
    """Facet normals ``c`` of the friction cones: a force ``f`` is inside iff ``c . f <= 0``.

    Planar (eq. 2.9): the two exact facets ``+-t - mu n``. Spatial (eq. 2.1): the ``facets``
    facets ``u_a - mu cos(pi/m) n`` of the pyramid *inscribed* in the cone, ``u_a`` the
    tangent direction at angle ``2 pi (a + 1/2) / m`` from ``t1`` of :func:`tangent_basis`.

    Args:
        normals: (k, 2) or (k, 3) inward contact normals (normalized here).
        mu: friction coefficient (>= 0).
        facets: spatial pyramids' facets (>= 3).

    Returns:
        (k, 2, 2) planar or (k, facets, 3) spatial facet normals [dimensionless].
    """
    n = unit_directions("normals", normals)
    mu = checks.nonnegative("mu", mu)
    if n.shape[1] == 2:
        t = np.stack([-n[:, 1], n[:, 0]], axis=1)
        return np.stack([t - mu * n, -t - mu * n], axis=1)
    m = checks.integer("facets", facets, 3)
    t1, t2 = tangent_basis(n)
    ang = 2 * np.pi * (np.arange(m) + 0.5) / m
    u = np.cos(ang)[None, :, None] * t1[:, None, :] + np.sin(ang)[None, :, None] * t2[:, None, :]
    return u - mu * np.cos(np.pi / m) * n[:, None, :]
