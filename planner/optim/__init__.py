"""The one optimization entry point of hapex: every QP and LP goes through here (a leaf).

Problems are stated in the qpsolvers convention::

    minimize    1/2 x^T P x + q^T x
    subject to  G x <= h,   A x = b,   lb <= x <= ub

Public names:

* :class:`QPProblem` — the problem, validated at construction, ``save``/``load`` to ``.npz``;
* :class:`QPSolution` — ``x``, objective, primal/dual residuals, duality gap, multipliers,
  solver and solve time;
* :func:`solve_qp`, :func:`solve_lp`, :func:`solve_problem` — one-shot solves;
* :class:`QPWorkspace` — a QP built once and re-solved after in-place updates of its vectors
  (DAQP, ProxQP, OSQP and Clarabel through their own update APIs): the control-loop path;
* :func:`replay` — re-solve a problem saved by :meth:`planner.errors.InfeasibleProblem.save`;
* :func:`available_solvers`, :data:`KNOWN_SOLVERS`, :data:`DEFAULT_SETTINGS`.

Backends: ``"osqp"`` (default), ``"daqp"``, ``"proxqp"``, ``"clarabel"``, ``"quadprog"``.
"""

from planner.optim.problem import QPProblem
from planner.optim.settings import DEFAULT_SETTINGS, KNOWN_SOLVERS, available_solvers
from planner.optim.solution import QPSolution
from planner.optim.solve import replay, solve_lp, solve_problem, solve_qp
from planner.optim.workspace import QPWorkspace

__all__ = [
    "DEFAULT_SETTINGS",
    "KNOWN_SOLVERS",
    "QPProblem",
    "QPSolution",
    "QPWorkspace",
    "available_solvers",
    "replay",
    "solve_lp",
    "solve_problem",
    "solve_qp",
]
