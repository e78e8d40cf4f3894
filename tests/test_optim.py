"""The one QP/LP entry point (planner.optim): problems, solutions, workspaces, replay."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.errors import InfeasibleProblem, InvalidParameter
from planner.optim import (
    QPProblem,
    QPWorkspace,
    available_solvers,
    replay,
    solve_lp,
    solve_problem,
    solve_qp,
)

SOLVERS = available_solvers()
IN_PLACE = [s for s in ("daqp", "proxqp", "osqp", "clarabel") if s in SOLVERS]


def box_problem() -> QPProblem:
    """min 1/2|x|^2 - (1,1).x  s.t.  x0 + x1 <= 1, x0 - x1 = 0.05, x0 >= -1, x1 <= 0.4.

    Closed form: the equality and the inequality are active: x = (0.525, 0.475), until the
    bound x1 <= 0.4 is lowered below 0.475.
    """
    return QPProblem(
        np.eye(2),
        [-1.0, -1.0],
        G=[[1.0, 1.0]],
        h=[1.0],
        A=[[1.0, -1.0]],
        b=[0.05],
        lb=[-1.0, -np.inf],
        ub=[np.inf, 0.6],
    )


@pytest.mark.parametrize("solver", SOLVERS)
def test_small_qp_closed_form(solver):
    # min 1/2 |x|^2 - (1, 1).x  s.t. x0 + x1 <= 1  ->  x = (0.5, 0.5), z = 0.5
    sol = solve_qp(np.eye(2), [-1.0, -1.0], G=[[1.0, 1.0]], h=[1.0], solver=solver)
    assert np.allclose(sol.x, [0.5, 0.5], atol=1e-7)
    assert sol.primal_residual <= 1e-7
    assert sol.objective == pytest.approx(0.25 - 1.0, abs=1e-7)
    assert sol.solver == solver and sol.solve_time_s >= 0


@pytest.mark.parametrize("solver", SOLVERS)
def test_residuals_and_multipliers_with_all_constraint_kinds(solver):
    sol = solve_problem(box_problem(), solver=solver)
    assert np.allclose(sol.x, [0.525, 0.475], atol=1e-6)
    # KKT: P x + q + A^T y + G^T z = 0 with z = 0.5 - ... ; here z = 0.5, y = -0.025
    assert sol.primal_residual <= 1e-6
    assert sol.dual_residual <= 1e-6
    assert sol.duality_gap <= 1e-5
    assert sol.z[0] == pytest.approx(0.5, abs=1e-5)
    assert sol.y[0] == pytest.approx(-0.025, abs=1e-5)
    assert np.allclose(sol.z_box, 0.0, atol=1e-6)


@pytest.mark.parametrize(
    "solver", [s for s in ("osqp", "clarabel", "proxqp", "daqp") if s in SOLVERS]
)
def test_lp(solver):
    sol = solve_lp([-1.0, -2.0], G=[[1.0, 1.0]], h=[1.0], lb=[0.0, 0.0], solver=solver)
    assert np.allclose(sol.x, [0.0, 1.0], atol=1e-6)
    assert sol.objective == pytest.approx(-2.0, abs=1e-6)


@pytest.mark.parametrize("solver", SOLVERS)
def test_infeasible_saves_a_replayable_problem(solver, tmp_path):
    with pytest.raises(InfeasibleProblem) as err:
        solve_qp(np.eye(1), [0.0], G=[[1.0], [-1.0]], h=[-1.0, -1.0], solver=solver)
    assert isinstance(err.value.problem, QPProblem)
    assert err.value.problem.G.shape == (2, 1)
    assert err.value.solver == solver
    path = err.value.save(tmp_path / "failed")
    assert path.name == "failed.npz"
    loaded = QPProblem.load(path)
    assert np.array_equal(loaded.G, [[1.0], [-1.0]]) and np.array_equal(loaded.h, [-1.0, -1.0])
    with pytest.raises(InfeasibleProblem):
        replay(path)  # the recorded solver, still infeasible
    # the same file with a relaxed bound solves: the replay really re-solves
    data = dict(np.load(path))
    data["h"] = np.array([1.0, 1.0])
    np.savez(tmp_path / "relaxed.npz", **data)
    assert replay(tmp_path / "relaxed.npz").x == pytest.approx([0.0], abs=1e-6)


def test_problem_round_trip(tmp_path):
    pb = box_problem()
    back = QPProblem.load(pb.save(tmp_path / "pb.npz"))
    for a, b in zip(pb.unpack(), back.unpack(), strict=True):
        assert np.array_equal(a, b)


@pytest.mark.parametrize("solver", IN_PLACE)
def test_workspace_updates_match_one_shot_solves(solver):
    ws = QPWorkspace(box_problem(), solver)
    assert ws.in_place
    rng = np.random.default_rng(3)
    for _ in range(5):
        b, h, ub1 = rng.uniform(-0.2, 0.2), rng.uniform(0.5, 1.5), rng.uniform(0.2, 0.8)
        q = rng.uniform(-1.5, -0.5, 2)
        ws.update(q=q, b=[b], h=[h], ub=[np.inf, ub1])
        got = ws.solve()
        ref = solve_qp(
            np.eye(2),
            q,
            [[1.0, 1.0]],
            [h],
            [[1.0, -1.0]],
            [b],
            [-1.0, -np.inf],
            [np.inf, ub1],
            solver=solver,
        )
        assert np.allclose(got.x, ref.x, atol=1e-6)
        assert got.dual_residual <= 1e-6
        assert np.allclose(ws.solve_primal(), ref.x, atol=1e-6)


@settings(max_examples=25, deadline=None, derandomize=True)
@given(st.floats(-2.0, 2.0), st.floats(0.1, 3.0))
def test_workspace_daqp_projection_property(c, radius):
    # projection of c (1, 1) on the box [-r, r]^2: clip, for every c and r
    ws = QPWorkspace(QPProblem(np.eye(2), [0.0, 0.0], lb=[-1.0, -1.0], ub=[1.0, 1.0]), "daqp")
    ws.update(q=[-c, -c], lb=[-radius, -radius], ub=[radius, radius])
    assert np.allclose(ws.solve().x, np.clip([c, c], -radius, radius), atol=1e-9)


def test_workspace_rebuild_backend_and_clarabel_pattern():
    if "quadprog" in SOLVERS:
        ws = QPWorkspace(box_problem(), "quadprog")
        assert not ws.in_place
        ws.update(b=[0.0])
        assert np.allclose(ws.solve().x, [0.5, 0.5], atol=1e-7)
    if "clarabel" in SOLVERS:
        ws = QPWorkspace(box_problem(), "clarabel")
        with pytest.raises(InvalidParameter, match="ub: expected the same finite entries"):
            ws.update(ub=[1.0, 0.6])


def test_osqp_emits_no_deprecation_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        solve_qp(np.eye(2), [-1.0, -1.0], G=[[1.0, 1.0]], h=[1.0], solver="osqp")
        with pytest.raises(InfeasibleProblem):
            solve_qp(np.eye(1), [0.0], G=[[1.0], [-1.0]], h=[-1.0, -1.0], solver="osqp")


def test_error_messages_name_the_argument_and_expectation():
    with pytest.raises(
        InvalidParameter, match=r"solver: expected one of \[.*'osqp'.*\], got 'nope'"
    ):
        solve_qp(np.eye(2), [0, 0], solver="nope")
    with pytest.raises(InvalidParameter, match=r"P: expected shape \(2, 2\), got shape \(3, 3\)"):
        solve_qp(np.eye(3), [0, 0])
    with pytest.raises(InvalidParameter, match="G, h: expected both or neither, got only G"):
        solve_qp(np.eye(2), [0, 0], G=[[1, 0]])
    with pytest.raises(InvalidParameter, match=r"q: expected finite values"):
        solve_qp(np.eye(2), [np.nan, 0])
    with pytest.raises(InvalidParameter, match="P: expected a symmetric matrix"):
        QPProblem([[1.0, 1.0], [0.0, 1.0]], [0, 0])
    with pytest.raises(InvalidParameter, match=r"lb, ub: expected lb <= ub, got lb\[1\] = 2"):
        QPProblem(np.eye(2), [0, 0], lb=[0, 2], ub=[1, 1])
    with pytest.raises(InvalidParameter, match=r"ub: expected numbers \(or \+inf for no bound\)"):
        QPProblem(np.eye(2), [0, 0], ub=[1, -np.inf])
    with pytest.raises(InvalidParameter, match=r"h: expected shape \(1,\), got shape \(2,\)"):
        QPWorkspace(box_problem(), "daqp").update(h=[1.0, 2.0])
    with pytest.raises(InvalidParameter, match="the problem was built without lb"):
        QPWorkspace(QPProblem(np.eye(1), [0.0]), "daqp").update(lb=[0.0])
    with pytest.raises(InvalidParameter, match="problem: expected a QPProblem, got dict"):
        QPWorkspace({"P": np.eye(1)}, "daqp")
    with pytest.raises(InvalidParameter, match="tolerance: expected a finite number > 0"):
        solve_qp(np.eye(1), [0.0], tolerance=0.0)


def test_infeasible_problem_without_data_cannot_be_saved(tmp_path):
    with pytest.raises(InvalidParameter, match="problem: expected QP data to save, got NoneType"):
        InfeasibleProblem("no data").save(tmp_path / "x.npz")
