"""Control: the project's single QP entry point and the grasp-force distribution QP."""

from planner.control.qp import QPSolution, available_solvers, solve_lp, solve_qp

__all__ = ["QPSolution", "available_solvers", "solve_lp", "solve_qp"]
