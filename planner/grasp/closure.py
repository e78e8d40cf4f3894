"""Force closure: an exact vectorized planar two-contact test and general tests.

* :func:`force_closure_two_planar` — Nguyen's condition: two planar point contacts with
  friction are in force closure iff the line joining them lies strictly inside both
  friction cones with the two forces opposed: the usual squeezing grasp (``p_2 - p_1`` in
  cone 1 and ``p_1 - p_2`` in cone 2) or an expanding one (``p_1 - p_2`` in cone 1 and
  ``p_2 - p_1`` in cone 2, e.g. fingers inside a ring). Vectorized over any batch shape.
* :func:`force_closure` — any number ``k >= 2`` of planar or spatial point contacts with
  friction (a palm contact is just one more contact): the grasp is in force closure iff the
  origin lies strictly inside the convex hull of the primitive wrenches (closed form for two
  planar contacts, Qhull otherwise). Spatial cones are inscribed pyramids, so the spatial test
  is conservative by at most the pyramid's inscription error.
* :func:`force_closure_lp` — the same question as an LP through the project's QP entry point
  (``max t  s.t.  W λ = 0, Σ λ = 1, λ >= t``; closure iff ``W`` has full rank and ``t > 0``):
  the "numerical solution" used by Leveroni, kept as a cross-check and benchmark baseline.
"""

from __future__ import annotations

import numpy as np

from planner import checks
from planner.errors import InfeasibleProblem
from planner.grasp.wrenches import check_contacts, primitive_wrenches
from planner.optim import solve_lp

#: Strictness margin of the hull and LP tests (wrench-space distance, unit-force scale).
HULL_TOL = 1e-10
#: Relative strictness of Nguyen's test: a contact line on a cone edge up to rounding
#: (``|t| = mu n`` within 1e-9) is *not* in force closure, so grids that hit the boundary
#: exactly (e.g. a circle at separation ``pi - 2 atan(mu)``) give the same answer everywhere.
STRICT = 1.0 + 1e-9


def force_closure_two_planar(p1, n1, p2, n2, mu: float, mu2: float | None = None) -> np.ndarray:
    """Nguyen's exact two-contact planar force-closure test, vectorized.

    Args:
        p1, p2: (..., 2) contact points [m] (broadcastable).
        n1, n2: (..., 2) inward unit normals (broadcastable; not re-normalized here).
        mu: friction coefficient (>= 0) at ``p1`` (and at ``p2`` unless ``mu2`` is given).
        mu2: friction coefficient at ``p2`` (e.g. a palm of another material).

    Returns:
        (...) bool: the line ``p1 p2`` lies strictly inside both friction cones, the forces
        along it opposed (squeezing or expanding).
    """
    mu = checks.nonnegative("mu", mu)
    mu2 = mu if mu2 is None else checks.nonnegative("mu2", mu2)
    p1, n1, p2, n2 = (np.asarray(a, dtype=float) for a in (p1, n1, p2, n2))
    dx = p2[..., 0] - p1[..., 0]
    dy = p2[..., 1] - p1[..., 1]
    dot1 = n1[..., 0] * dx + n1[..., 1] * dy
    cr1 = n1[..., 0] * dy - n1[..., 1] * dx
    dot2 = -(n2[..., 0] * dx + n2[..., 1] * dy)
    cr2 = -(n2[..., 0] * dy - n2[..., 1] * dx)
    return (
        (np.abs(cr1) * STRICT < mu * np.abs(dot1))
        & (np.abs(cr2) * STRICT < mu2 * np.abs(dot2))
        & (dot1 * dot2 > 0)
    )


def hull_offsets(w: np.ndarray) -> np.ndarray | None:
    """Facet offsets of the convex hull of the rows of ``w`` (None if it is flat)."""
    from scipy.spatial import ConvexHull, QhullError

    if w.shape[0] <= w.shape[1] or np.linalg.matrix_rank(w, tol=1e-9) < w.shape[1]:
        return None
    try:
        hull = ConvexHull(w)
    except QhullError:
        return None
    return hull.equations[:, -1]


def force_closure(
    points,
    normals,
    mu: float,
    *,
    facets: int = 8,
    contact: str = "point_with_friction",
    torsion_length: float = 0.0,
) -> bool:
    """Whether the contacts hold the object in force closure.

    Args:
        points: (k, 2) planar or (k, 3) spatial contact points [m], k >= 2.
        normals: (k, 2) or (k, 3) inward unit contact normals (pointing into the object;
            normalized here).
        mu: Coulomb friction coefficient (>= 0), the same at every contact.
        facets: spatial only: edges of the inscribed friction pyramids (>= 3).
        contact: contact model of Fig. 2.5: ``"point_with_friction"`` (default),
            ``"frictionless"`` or ``"soft_finger"`` (see
            :func:`planner.grasp.wrenches.primitive_wrenches`).
        torsion_length: soft-finger torsional friction length ``e_n`` [m].

    Returns:
        True iff every object wrench can be resisted by contact forces inside the cones.
        Closed form (Nguyen) for two planar contacts; convex hull of the primitive wrenches
        otherwise (origin strictly inside).

    Raises:
        InvalidParameter: bad shapes, NaN, zero normals, ``mu < 0``, fewer than 2 contacts.
    """
    p, n = check_contacts(points, normals, 2)
    mu = checks.nonnegative("mu", mu)
    w = primitive_wrenches(
        p, n, mu, facets=facets, contact=contact, torsion_length=torsion_length
    )  # validates the contact model
    if p.shape[1] == 2 and p.shape[0] == 2:
        mu = 0.0 if getattr(contact, "value", contact) == "frictionless" else mu
        return bool(force_closure_two_planar(p[0], n[0], p[1], n[1], mu))
    offsets = hull_offsets(w)
    return offsets is not None and bool(np.all(offsets < -HULL_TOL))


def force_closure_lp(points, normals, mu: float, *, facets: int = 8, solver: str = "osqp") -> bool:
    """Force closure decided by a linear program (through :func:`planner.optim.solve_lp`).

    Solves ``max t  s.t.  W^T λ = 0, Σ λ = 1, λ_i >= t, t <= 1`` over the primitive wrenches
    ``W`` (rows); the grasp is in force closure iff ``W`` has full rank and ``t* > 0``
    (then the origin is a strictly positive combination of spanning wrenches, i.e. interior).

    Args: as :func:`force_closure`, plus ``solver``: QP backend accepting LPs
        (``"osqp"``, ``"clarabel"``, ``"proxqp"``).
    """
    p, n = check_contacts(points, normals, 2)
    w = primitive_wrenches(p, n, checks.nonnegative("mu", mu), facets=facets)
    m, d = w.shape
    if np.linalg.matrix_rank(w, tol=1e-9) < d:
        return False
    # variables x = (λ (m), t)
    c = np.zeros(m + 1)
    c[-1] = -1.0
    A = np.zeros((d + 1, m + 1))
    A[:d, :m] = w.T
    A[d, :m] = 1.0
    b = np.zeros(d + 1)
    b[d] = 1.0
    G = np.hstack([-np.eye(m), np.ones((m, 1))])  # t - λ_i <= 0
    h = np.zeros(m)
    ub = np.full(m + 1, np.inf)
    ub[-1] = 1.0
    try:
        sol = solve_lp(c, G, h, A, b, ub=ub, solver=solver)
    except InfeasibleProblem:  # no combination with unit sum balances: origin not inside
        return False
    return bool(sol.x[-1] > 1e-7 / m)


__all__ = [
    "HULL_TOL",
    "STRICT",
    "force_closure",
    "force_closure_lp",
    "force_closure_two_planar",
    "hull_offsets",
]
