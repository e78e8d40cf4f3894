"""Control: the project's single QP entry point and the grasp-force distribution QP."""

from planner.control.force_distribution import (
    ForceDistribution,
    GraspForceQP,
    distribute_forces,
)
from planner.control.qp import QPSolution, available_solvers, solve_lp, solve_qp

__all__ = [
    "ForceDistribution",
    "GraspForceQP",
    "QPSolution",
    "distribute_forces",
    "available_solvers",
    "solve_lp",
    "solve_qp",
]
