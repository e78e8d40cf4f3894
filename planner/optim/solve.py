"""The one-shot QP/LP entry points: every quadratic (and linear) program of hapex goes here.

``solve_qp(P, q, G, h, A, b, lb, ub, solver=...)`` takes the arrays (qpsolvers' signature),
``solve_problem(problem, solver=...)`` a :class:`~planner.optim.problem.QPProblem`;
``replay(path)`` re-solves a problem saved by :meth:`planner.errors.InfeasibleProblem.save`.
For repeated solves of one structure use :class:`~planner.optim.workspace.QPWorkspace`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from planner.optim.problem import QPProblem
from planner.optim.solution import QPSolution
from planner.optim.workspace import QPWorkspace

__all__ = ["replay", "solve_lp", "solve_problem", "solve_qp"]


def solve_problem(
    problem: QPProblem,
    *,
    solver: str = "osqp",
    initvals=None,
    tolerance: float = 1e-6,
    **settings,
) -> QPSolution:
    """Solve a :class:`QPProblem` once with the selected backend.

    Args:
        problem: the validated QP.
        solver: one of :func:`~planner.optim.settings.available_solvers`.
        initvals: (n,) warm-start guess (osqp, daqp, proxqp use it).
        tolerance: accepted primal residual of the solution [units of the rows].
        **settings: backend settings overriding
            :data:`~planner.optim.settings.DEFAULT_SETTINGS`.

    Returns:
        The solution with its primal and dual residuals, duality gap and solve time.

    Raises:
        InvalidParameter: an unknown or uninstalled solver, a bad ``initvals``.
        InfeasibleProblem: no solution, or one violating the constraints by more than
            ``tolerance``; ``.problem`` is the :class:`QPProblem` (``.save(path)`` replays).
    """
    ws = QPWorkspace(problem, solver, tolerance=tolerance, initvals=initvals, **settings)
    return ws.solve()


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
    """Solve ``min 1/2 x^T P x + q^T x`` s.t. ``G x <= h, A x = b, lb <= x <= ub``.

    Args:
        P: (n, n) positive semi-definite cost matrix; q: (n,) linear cost.
        G, h: (m, n), (m,) inequalities (optional, together).
        A, b: (p, n), (p,) equalities (optional, together).
        lb, ub: (n,) bounds (optional; may hold -inf / +inf).
        solver, initvals, tolerance, settings: as :func:`solve_problem`.

    Raises:
        InvalidParameter: bad shapes or values (see :class:`QPProblem`), unknown solver.
        InfeasibleProblem: as :func:`solve_problem`.
    """
    problem = QPProblem(P, q, G, h, A, b, lb, ub)
    return solve_problem(problem, solver=solver, initvals=initvals, tolerance=tolerance, **settings)


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
    """Solve the LP ``min c^T x`` under the constraints of :func:`solve_qp` (``P = 0``).

    Only backends that accept a zero Hessian are meaningful (``osqp``, ``clarabel``,
    ``proxqp``, ``daqp``).
    """
    problem = QPProblem.lp(c, G, h, A, b, lb, ub)
    return solve_problem(problem, solver=solver, tolerance=tolerance, **settings)


def replay(path: str | Path, *, solver: str | None = None, **settings) -> QPSolution:
    """Re-solve a problem saved by :meth:`planner.errors.InfeasibleProblem.save`.

    Args:
        path: the ``.npz`` file.
        solver: the backend (default: the one that failed, as recorded in the file).

    Raises:
        InfeasibleProblem: it still has no solution.
    """
    problem = QPProblem.load(path)
    if solver is None:
        with np.load(Path(path), allow_pickle=False) as data:
            solver = str(data["solver"]) if "solver" in data else "osqp"
    return solve_problem(problem, solver=solver, **settings)
