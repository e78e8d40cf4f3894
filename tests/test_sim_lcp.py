"""Lemke's method on random and on Stewart-Trinkle contact LCPs."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.sim.lcp import LCP_OK, LCP_RAY, lcp_residual, solve_lcp


def _check(M, q, z, tol=1e-9):
    w = M @ z + q
    scale = max(1.0, np.abs(q).max())
    assert z.min() >= 0
    assert w.min() >= -tol * scale
    assert abs(w @ z) <= tol * scale * max(1.0, z.max())


@settings(max_examples=60, deadline=None)
@given(n=st.integers(1, 12), seed=st.integers(0, 2**31 - 1))
def test_positive_definite_lcps_are_solved(n, seed):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(n, n))
    M = A @ A.T + 1e-3 * np.eye(n)
    q = rng.normal(size=n)
    z, status, _ = solve_lcp(M, q)
    assert status == LCP_OK
    _check(M, q, z)


def _contact_lcp(rng, nc, nv, dup):
    """A Stewart-Trinkle LCP with nc contacts on nv DOF (dup: duplicated tangent rows)."""
    N = rng.normal(size=(nc, nv))
    T = rng.normal(size=(nc, nv))
    if dup and nc > 1:
        T[1] = T[0]  # two corners of one face share their tangent row
    B = rng.normal(size=(nv, nv))
    Minv = np.linalg.inv(B @ B.T + 0.1 * np.eye(nv))
    mu = rng.uniform(0.0, 1.5, nc)
    R = np.vstack([N, T, -T])
    G = R @ Minv @ R.T
    m = 4 * nc
    A = np.zeros((m, m))
    A[: 3 * nc, : 3 * nc] = G
    for k in range(nc):
        A[nc + k, 3 * nc + k] = A[2 * nc + k, 3 * nc + k] = 1.0
        A[3 * nc + k, k] = mu[k]
        A[3 * nc + k, nc + k] = A[3 * nc + k, 2 * nc + k] = -1.0
    v = rng.normal(size=nv)
    b = np.concatenate([R @ v, np.zeros(nc)])
    # gaps >= 0 (the stepper projects penetrations out first): then q.z >= 0 on every
    # z >= 0 with A z >= 0 and z.A z = 0, the condition under which Lemke processes the LCP
    b[:nc] += rng.uniform(0.0, 0.02, nc) / 1e-3
    return A, b


@settings(max_examples=80, deadline=None)
@given(
    nc=st.integers(1, 4),
    nv=st.integers(3, 9),
    dup=st.booleans(),
    seed=st.integers(0, 2**31 - 1),
)
def test_contact_lcps_are_solved_exactly(nc, nv, dup, seed):
    A, b = _contact_lcp(np.random.default_rng(seed), nc, nv, dup)
    z, status, _ = solve_lcp(A, b)
    assert status == LCP_OK
    _check(A, b, z)


def test_trivial_and_infeasible():
    z, status, pivots = solve_lcp(np.eye(3), np.ones(3))
    assert status == LCP_OK and pivots == 0 and not z.any()
    z, status, _ = solve_lcp(np.eye(2), np.array([-1.0, -2.0]))
    assert status == LCP_OK and np.allclose(z, [1.0, 2.0])
    _, status, _ = solve_lcp(-np.eye(2), -np.ones(2))  # w = -z - 1 >= 0 has no solution
    assert status == LCP_RAY


def test_bad_shapes():
    with pytest.raises(InvalidParameter, match="shape"):
        solve_lcp(np.eye(3), np.ones(2))
    # a 2-D q was a numba TypingError, a non-numeric M a numpy ValueError
    with pytest.raises(
        InvalidParameter, match=r"q: expected a vector of shape \(n,\), got shape \(2, 1\)"
    ):
        solve_lcp(np.eye(2), np.ones((2, 1)))
    with pytest.raises(
        InvalidParameter, match=r"M: expected an array of numbers of shape \(2, 2\), got 'abc'"
    ):
        solve_lcp("abc", np.ones(2))
    with pytest.raises(InvalidParameter, match="q: expected an array of numbers"):
        solve_lcp(np.eye(2), ["a", 1.0])


@pytest.mark.parametrize("where", ["q", "M"])
@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_non_finite_problems_are_never_verified(where, bad):
    """``solve_lcp(I, [nan, 1])`` returned ``z = [nan, 0]`` as LCP_OK: the residual's
    ``max(bad, nan)`` dropped the NaN."""
    M, q = np.eye(2), np.array([-1.0, 1.0])
    if where == "q":
        q[0] = bad
    else:
        M[0, 1] = bad
    z, status, _ = solve_lcp(M, q)
    assert status != LCP_OK
    assert lcp_residual(M, q, z) == np.inf
    assert lcp_residual(np.eye(2), [-1.0, 1.0], [np.nan, 0.0]) == np.inf


def test_residual_measures_each_violation():
    M, q = np.eye(2), np.array([-1.0, 2.0])
    assert lcp_residual(M, q, np.array([1.0, 0.0])) == 0.0
    assert lcp_residual(M, q, np.array([0.5, 0.0])) == pytest.approx(0.25)  # w < 0
    assert lcp_residual(M, q, np.array([1.0, 1.0])) == pytest.approx(1.5)  # z.w != 0
    assert lcp_residual(M, q, np.array([1.0, -0.5])) == pytest.approx(0.375)  # z.w, z < 0


@settings(max_examples=40, deadline=None)
@given(nc=st.integers(2, 8), nv=st.integers(1, 6), seed=st.integers(0, 2**31 - 1))
def test_jammed_projection_lcps_are_solved_or_refused(nc, nv, seed):
    """Position projections ``N M^-1 N^T`` with more rows than DOF (PSD, duplicated rows):
    every answer of the stepper's solve is verified on the original problem."""
    from planner.errors import InfeasibleProblem
    from planner.sim.planar.stepper import _solve

    rng = np.random.default_rng(seed)
    N = rng.normal(size=(nc, nv))
    N[-1] = N[0]  # a corner found twice
    M = N @ N.T
    phi = -np.abs(rng.normal(size=nc)) * 1e-6
    from scipy.optimize import linprog

    # a PSD LCP is solvable iff it is feasible: some z >= 0 with M z + phi >= 0
    feasible = linprog(np.zeros(nc), A_ub=-M, b_ub=phi, bounds=(0, None)).status == 0
    try:
        z = _solve(M, phi, "projection", regularize=1e-9)
    except InfeasibleProblem:
        assert not feasible
        return
    assert lcp_residual(M, phi, z) <= 1e-6
