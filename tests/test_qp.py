"""The single QP entry point (planner.control.qp)."""

from __future__ import annotations

import numpy as np
import pytest

from planner.control.qp import available_solvers, solve_lp, solve_qp
from planner.errors import InfeasibleProblem, InvalidParameter

SOLVERS = available_solvers()


@pytest.mark.parametrize("solver", SOLVERS)
def test_small_qp_closed_form(solver):
    # min 1/2 |x|^2 - (1, 1).x  s.t. x0 + x1 <= 1  ->  x = (0.5, 0.5)
    sol = solve_qp(np.eye(2), [-1.0, -1.0], G=[[1.0, 1.0]], h=[1.0], solver=solver)
    assert np.allclose(sol.x, [0.5, 0.5], atol=1e-7)
    assert sol.primal_residual <= 1e-7
    assert sol.objective == pytest.approx(0.25 - 1.0, abs=1e-7)


@pytest.mark.parametrize("solver", [s for s in ("osqp", "clarabel", "proxqp") if s in SOLVERS])
def test_lp(solver):
    sol = solve_lp([-1.0, -2.0], G=[[1.0, 1.0]], h=[1.0], lb=[0.0, 0.0], solver=solver)
    assert np.allclose(sol.x, [0.0, 1.0], atol=1e-6)


@pytest.mark.parametrize("solver", [s for s in ("osqp", "daqp", "clarabel") if s in SOLVERS])
def test_infeasible_raises_with_replayable_problem(solver):
    with pytest.raises(InfeasibleProblem) as err:
        solve_qp(np.eye(1), [0.0], G=[[1.0], [-1.0]], h=[-1.0, -1.0], solver=solver)
    assert err.value.problem["G"].shape == (2, 1)
    assert err.value.solver == solver


def test_bad_inputs():
    with pytest.raises(InvalidParameter, match="unknown or uninstalled QP solver"):
        solve_qp(np.eye(2), [0, 0], solver="nope")
    with pytest.raises(InvalidParameter, match="P must have shape"):
        solve_qp(np.eye(3), [0, 0])
    with pytest.raises(InvalidParameter, match="together"):
        solve_qp(np.eye(2), [0, 0], G=[[1, 0]])
    with pytest.raises(InvalidParameter, match="NaN"):
        solve_qp(np.eye(2), [np.nan, 0])
