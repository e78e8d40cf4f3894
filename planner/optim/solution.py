"""The result of one QP solve, with the residuals that say how good it is (qpsolvers' convention).

With multipliers ``y`` (equalities), ``z >= 0`` (inequalities) and ``z_box`` (bounds: negative
where a lower bound is active, positive where an upper bound is), the optimality conditions are

* primal residual ``max(|A x - b|_inf, [G x - h]^+, [lb - x]^+, [x - ub]^+)``,
* dual residual ``|P x + q + A^T y + G^T z + z_box|_inf``,
* duality gap ``|x^T P x + q^T x + b^T y + h^T z + lb^T z_box^- + ub^T z_box^+|``,

all zero at the optimum.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner.optim.problem import QPProblem

__all__ = ["QPSolution", "duality_gap", "dual_residual", "primal_residual"]


def primal_residual(problem: QPProblem, x: np.ndarray) -> float:
    """Largest constraint violation of ``x`` (0 when feasible) [units of the rows]."""
    P, q, G, h, A, b, lb, ub = problem.unpack()
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


def dual_residual(problem: QPProblem, x, y, z, z_box) -> float:
    """``|P x + q + A^T y + G^T z + z_box|_inf``; NaN when a needed multiplier is unknown."""
    P, q, G, _, A, _, lb, ub = problem.unpack()
    g = P @ x + q
    for mat, mult in ((A, y), (G, z)):
        if mat is not None:
            if mult is None:
                return math.nan
            g = g + mat.T @ mult
    if lb is not None or ub is not None:
        if z_box is None:
            return math.nan
        g = g + z_box
    return float(np.max(np.abs(g), initial=0.0))


def duality_gap(problem: QPProblem, x, y, z, z_box) -> float:
    """``|x^T P x + q^T x + b^T y + h^T z + lb^T z_box^- + ub^T z_box^+|``; NaN if unknown."""
    P, q, _, h, _, b, lb, ub = problem.unpack()
    gap = float(x @ P @ x + q @ x)
    for vec, mult in ((b, y), (h, z)):
        if vec is not None:
            if mult is None:
                return math.nan
            gap += float(vec @ mult)
    if lb is not None or ub is not None:
        if z_box is None:
            return math.nan
        for bound, part in ((lb, np.minimum(z_box, 0.0)), (ub, np.maximum(z_box, 0.0))):
            if bound is not None:
                fin = np.isfinite(bound)
                gap += float(bound[fin] @ part[fin])
    return abs(gap)


@dataclass(frozen=True)
class QPSolution:
    """Result of one solve.

    Attributes:
        x: (n,) primal solution.
        objective: ``1/2 x^T P x + q^T x`` at ``x``.
        primal_residual: max violation of the constraints (>= 0) [units of the rows].
        dual_residual: stationarity residual (NaN when the backend gives no multipliers).
        duality_gap: complementarity gap (NaN when the backend gives no multipliers).
        solver: the backend that produced it.
        solve_time_s: wall-clock time of the backend call (update + solve) [s].
        y: (p,) equality multipliers, or ``None``.
        z: (m,) inequality multipliers (>= 0), or ``None``.
        z_box: (n,) bound multipliers, or ``None``.
    """

    x: np.ndarray
    objective: float
    primal_residual: float
    dual_residual: float
    duality_gap: float
    solver: str
    solve_time_s: float
    y: np.ndarray | None = None
    z: np.ndarray | None = None
    z_box: np.ndarray | None = None

    @classmethod
    def from_solve(
        cls, problem: QPProblem, x, y, z, z_box, solver: str, solve_time_s: float
    ) -> QPSolution:
        """Build the solution of ``problem`` (anything with ``unpack()``) with its residuals."""
        x = np.asarray(x, dtype=float)
        P, q = problem.unpack()[:2]
        return cls(
            x=x,
            objective=float(0.5 * x @ P @ x + q @ x),
            primal_residual=primal_residual(problem, x),
            dual_residual=dual_residual(problem, x, y, z, z_box),
            duality_gap=duality_gap(problem, x, y, z, z_box),
            solver=solver,
            solve_time_s=solve_time_s,
            y=y,
            z=z,
            z_box=z_box,
        )
