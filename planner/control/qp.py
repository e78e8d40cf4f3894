"""The single QP entry point of hapex: every quadratic (and linear) program goes through here.

Problems are stated in the qpsolvers convention::

    minimize    1/2 x^T P x + q^T x
    subject to  G x <= h,   A x = b,   lb <= x <= ub

and solved by a selectable backend (``"osqp"`` by default; ``"daqp"``, ``"proxqp"``,
``"clarabel"`` and ``"quadprog"`` when installed). Tolerances are tightened per backend so that
force errors stay far below sensor resolution (OSQP's default 1e-3 leaves ~1e-2 N errors), and
ProxQP is called through its native API with ``eps_primal_inf = 1e-12`` because its default
reports false "primal infeasible" on SI-scaled problems.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from planner.errors import InfeasibleProblem, InvalidParameter

#: Backends the entry point knows how to drive (those installed are in :func:`available_solvers`).
KNOWN_SOLVERS = ("osqp", "daqp", "proxqp", "clarabel", "quadprog")

#: Settings applied unless the caller overrides them (keyword arguments of :func:`solve_qp`).
DEFAULT_SETTINGS: dict[str, dict[str, object]] = {
    "osqp": {"eps_abs": 1e-9, "eps_rel": 1e-9, "max_iter": 40000, "polishing": True},
    "proxqp": {"eps_abs": 1e-9, "eps_rel": 0.0, "eps_primal_inf": 1e-12, "eps_dual_inf": 1e-12},
    "clarabel": {"tol_gap_abs": 1e-10, "tol_gap_rel": 1e-10, "tol_feas": 1e-10},
    "daqp": {},
    "quadprog": {},
}


def available_solvers() -> tuple[str, ...]:
    """Backends of :data:`KNOWN_SOLVERS` that are installed on this machine."""
    import qpsolvers

    return tuple(s for s in KNOWN_SOLVERS if s in qpsolvers.available_solvers)


@dataclass(frozen=True)
class QPSolution:
    """Result of one solve.

    Attributes:
        x: (n,) primal solution.
        objective: 1/2 x^T P x + q^T x at ``x``.
        primal_residual: max violation of ``G x <= h``, ``A x = b`` and the bounds (>= 0).
        solver: backend that produced it.
        solve_time_s: wall-clock time of the backend call [s].
    """

    x: np.ndarray
    objective: float
    primal_residual: float
    solver: str
    solve_time_s: float


def _as_matrix(name: str, m, n: int) -> np.ndarray | None:
    if m is None:
        return None
    arr = np.atleast_2d(np.asarray(m, dtype=float))
    if arr.ndim != 2 or arr.shape[1] != n:
        raise InvalidParameter(f"{name} must have shape (m, {n}), got {np.shape(m)}")
    if not np.all(np.isfinite(arr)):
        raise InvalidParameter(f"{name} contains NaN or inf")
    return arr


def _as_vector(name: str, v, n: int | None) -> np.ndarray | None:
    if v is None:
        return None
    arr = np.atleast_1d(np.asarray(v, dtype=float)).ravel()
    if n is not None and arr.shape != (n,):
        raise InvalidParameter(f"{name} must have shape ({n},), got {np.shape(v)}")
    if np.any(np.isnan(arr)):
        raise InvalidParameter(f"{name} contains NaN")
    return arr


def primal_residual(x: np.ndarray, G=None, h=None, A=None, b=None, lb=None, ub=None) -> float:
    """Largest constraint violation of ``x`` (0 when feasible)."""
    r = 0.0
    if G is not None:
        r = max(r, float(np.max(G @ x - h, initial=0.0)))
    if A is not None:
        r = max(r, float(np.max(np.abs(A @ x - b), initial=0.0)))
    if lb is not None:
        r = max(r, float(np.max(lb - x, initial=0.0)))
    if ub is not None:
        r = max(r, float(np.max(x - ub, initial=0.0)))
    return r


def _solve_proxqp_native(P, q, G, h, A, b, lb, ub, settings) -> np.ndarray | None:
    from proxsuite import proxqp

    n = q.size
    rows, lo, up = [], [], []
    if G is not None:
        rows.append(G)
        lo.append(np.full(h.size, -1e20))
        up.append(h)
    if lb is not None or ub is not None:
        rows.append(np.eye(n))
        lo.append(lb if lb is not None else np.full(n, -1e20))
        up.append(ub if ub is not None else np.full(n, 1e20))
    C = np.vstack(rows) if rows else None
    n_eq = 0 if A is None else A.shape[0]
    n_in = 0 if C is None else C.shape[0]
    qp = proxqp.dense.QP(n, n_eq, n_in)
    for key, value in settings.items():
        setattr(qp.settings, key, value)
    qp.init(
        P,
        q,
        A,
        b,
        C,
        None if C is None else np.concatenate(lo),
        None if C is None else np.concatenate(up),
    )
    qp.solve()
    if qp.results.info.status != proxqp.QPSolverOutput.PROXQP_SOLVED:
        return None
    return np.array(qp.results.x)


def solve_qp(
    P,
    q,
    G=None,
    h=None,
    A=None,
    b=None,
    lb=None,
    ub=None,
    *,
    solver: str = "osqp",
    initvals=None,
    tolerance: float = 1e-6,
    **settings,
) -> QPSolution:
    """Solve a convex QP (or an LP when ``P`` is zero) with the selected backend.

    Args:
        P: (n, n) positive semi-definite cost matrix.
        q: (n,) linear cost.
        G, h: (m, n), (m,) inequalities ``G x <= h`` (optional).
        A, b: (p, n), (p,) equalities ``A x = b`` (optional).
        lb, ub: (n,) bounds (optional; may hold +-inf).
        solver: one of :data:`KNOWN_SOLVERS` that is installed.
        initvals: (n,) warm-start guess (used by backends that accept one).
        tolerance: accepted primal residual of the returned solution [units of the rows].
        **settings: backend settings overriding :data:`DEFAULT_SETTINGS`.

    Returns:
        The solution with its primal residual and solve time.

    Raises:
        InvalidParameter: bad shapes, NaN, or an unknown/uninstalled solver.
        InfeasibleProblem: the backend found no solution, or its solution violates the
            constraints by more than ``tolerance``; ``.problem`` holds the arrays to replay it.
    """
    q = _as_vector("q", q, None)
    n = q.size
    P = _as_matrix("P", P, n)
    if P.shape != (n, n):
        raise InvalidParameter(f"P must have shape ({n}, {n}), got {P.shape}")
    G = _as_matrix("G", G, n)
    A = _as_matrix("A", A, n)
    h = _as_vector("h", h, None if G is None else G.shape[0])
    b = _as_vector("b", b, None if A is None else A.shape[0])
    lb = _as_vector("lb", lb, n)
    ub = _as_vector("ub", ub, n)
    if (G is None) != (h is None) or (A is None) != (b is None):
        raise InvalidParameter("G and h (and A and b) must be given together")
    installed = available_solvers()
    if solver not in installed:
        raise InvalidParameter(
            f"unknown or uninstalled QP solver {solver!r}; expected one of {list(installed)}"
        )
    opts = {**DEFAULT_SETTINGS.get(solver, {}), **settings}
    problem = {"P": P, "q": q, "G": G, "h": h, "A": A, "b": b, "lb": lb, "ub": ub}
    t0 = time.perf_counter()
    if solver == "proxqp":
        x = _solve_proxqp_native(P, q, G, h, A, b, lb, ub, opts)
    else:
        import qpsolvers

        if solver in ("osqp", "clarabel"):  # sparse backends: avoid qpsolvers' conversion
            from scipy import sparse

            P, G, A = (None if m is None else sparse.csc_matrix(m) for m in (P, G, A))
        x = qpsolvers.solve_qp(P, q, G, h, A, b, lb, ub, solver=solver, initvals=initvals, **opts)
    dt = time.perf_counter() - t0
    if x is None or not np.all(np.isfinite(x)):
        raise InfeasibleProblem(
            f"QP solver {solver!r} found no solution (n={n})", problem=problem, solver=solver
        )
    res = primal_residual(x, problem["G"], h, problem["A"], b, lb, ub)
    if res > tolerance:
        raise InfeasibleProblem(
            f"QP solver {solver!r} returned a point violating the "
            f"constraints by {res:.3g} > tolerance {tolerance:g}",
            problem=problem,
            solver=solver,
        )
    P = problem["P"]
    return QPSolution(
        x=x,
        objective=float(0.5 * x @ P @ x + q @ x),
        primal_residual=res,
        solver=solver,
        solve_time_s=dt,
    )


def solve_lp(
    c,
    G=None,
    h=None,
    A=None,
    b=None,
    lb=None,
    ub=None,
    *,
    solver: str = "osqp",
    tolerance: float = 1e-6,
    **settings,
) -> QPSolution:
    """Solve the LP ``min c^T x`` s.t. the same constraints as :func:`solve_qp` (``P = 0``).

    Only backends that accept a zero Hessian are meaningful here (``osqp``, ``clarabel``,
    ``proxqp``).
    """
    c = _as_vector("c", c, None)
    return solve_qp(
        np.zeros((c.size, c.size)),
        c,
        G,
        h,
        A,
        b,
        lb,
        ub,
        solver=solver,
        tolerance=tolerance,
        **settings,
    )


__all__ = [
    "DEFAULT_SETTINGS",
    "KNOWN_SOLVERS",
    "QPSolution",
    "available_solvers",
    "primal_residual",
    "solve_lp",
    "solve_qp",
]
