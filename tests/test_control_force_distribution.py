"""Grasp-force distribution QP (planner.control.force_distribution)."""

from __future__ import annotations

import numpy as np
import pytest

from planner.control import GraspForceQP, distribute_forces
from planner.errors import InfeasibleProblem, InvalidParameter
from planner.optim import available_solvers


def three_contacts():
    t = np.array([0.0, 2.3, 4.1])
    p = 0.05 * np.stack([np.cos(t), np.sin(t)], axis=1)
    return p, -p / 0.05


@pytest.mark.parametrize("solver", available_solvers())
@pytest.mark.parametrize("objective", ["min_norm", "max_margin"])
def test_wrench_realized_inside_cones_across_backends(solver, objective):
    p, n = three_contacts()
    w = np.array([0.3, -1.2, 0.004])
    ref = GraspForceQP(p, n, 0.8, objective=objective, solver="daqp").solve(w, 1.0)
    for native in (True, False):
        qp = GraspForceQP(p, n, 0.8, objective=objective, solver=solver, native=native)
        for _ in range(2):  # re-solve in place
            d = qp.solve(w, 1.0)
        assert d.wrench_residual < 1e-6
        assert d.cone_margin > -1e-6
        assert np.all(d.normal >= 1.0 - 1e-6)
        assert np.allclose(d.forces, ref.forces, atol=1e-5)


def test_antipodal_squeeze_closed_form():
    p = np.array([[-0.05, 0.0], [0.05, 0.0]])
    n = np.array([[1.0, 0.0], [-1.0, 0.0]])
    d = distribute_forces(p, n, 0.5, [0.0, 0.0, 0.0], squeeze=2.0)
    assert np.allclose(d.forces, [[2.0, 0.0], [-2.0, 0.0]], atol=1e-6)
    # a vertical load is shared and stays inside the cones: f_t = 0.5 each
    d = distribute_forces(p, n, 0.5, [0.0, 1.0, 0.0], squeeze=2.0)
    assert np.allclose(d.tangential, [0.5, 0.5], atol=1e-6)


def test_spatial_grasp():
    t = np.array([0.0, 2 * np.pi / 3, 4 * np.pi / 3])
    p = np.stack([np.cos(t), np.sin(t), np.zeros(3)], axis=1) * 0.04
    d = distribute_forces(p, -p / 0.04, 0.7, [0, 0, -1.0, 0, 0, 0], squeeze=1.0)
    assert d.forces.shape == (3, 3)
    assert d.wrench_residual < 1e-6 and d.cone_margin > -1e-6


def test_infeasible_and_bad_inputs():
    p = np.array([[-0.05, 0.0], [0.05, 0.0]])
    n = np.array([[1.0, 0.0], [-1.0, 0.0]])
    with pytest.raises(InfeasibleProblem, match="friction cones"):
        # frictionless antipodal contacts cannot carry a vertical load
        GraspForceQP(p, n, 0.0).solve([0.0, 5.0, 0.0], squeeze=1.0)
    qp = GraspForceQP(p, n, 0.1)
    with pytest.raises(InvalidParameter, match=r"wrench: expected shape \(3,\) \[N, N m\]"):
        qp.solve([0.0, 1.0])
    with pytest.raises(
        InvalidParameter, match=r"squeeze: expected a finite number >= 0 \[N\], got -1"
    ):
        qp.solve([0.0, 0.0, 0.0], squeeze=-1)
    with pytest.raises(
        InvalidParameter,
        match=r"objective: expected one of \[.min_norm., .max_margin.\], got .fast.",
    ):
        GraspForceQP(p, n, 0.5, objective="fast")


def test_infeasible_grasp_force_problem_replays(tmp_path):
    from planner.optim import QPProblem, replay

    p = np.array([[-0.05, 0.0], [0.05, 0.0]])
    n = np.array([[1.0, 0.0], [-1.0, 0.0]])
    with pytest.raises(InfeasibleProblem) as err:
        GraspForceQP(p, n, 0.0, solver="daqp").solve([0.0, 5.0, 0.0], squeeze=1.0)
    path = err.value.save(tmp_path / "grasp_force")
    pb = QPProblem.load(path)
    assert pb.A.shape == (3, 4) and np.allclose(pb.b, [0.0, 5.0, 0.0])
    assert np.allclose(pb.h[-2:], [-1.0, -1.0])  # the squeeze rows
    with pytest.raises(InfeasibleProblem):
        replay(path)


@pytest.mark.parametrize("solver", available_solvers())
def test_in_place_solves_track_changing_wrenches_and_squeezes(solver):
    p, n = three_contacts()
    qp = GraspForceQP(p, n, 0.8, solver=solver)
    rng = np.random.default_rng(2)
    for _ in range(4):
        w, sq = rng.normal(scale=[1.0, 1.0, 0.02]), rng.uniform(0.5, 2.0)
        got = qp.solve(w, sq)
        ref = GraspForceQP(p, n, 0.8, solver=solver, native=False).solve(w, sq)
        assert np.allclose(got.forces, ref.forces, atol=1e-5)
        assert np.all(got.normal >= sq - 1e-6)
