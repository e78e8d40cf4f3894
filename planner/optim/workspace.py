"""A QP built once and re-solved after in-place updates: the control-loop path.

:class:`QPWorkspace` sets a backend up on a :class:`~planner.optim.problem.QPProblem` once;
:meth:`QPWorkspace.update` then changes the vectors ``q``, ``h``, ``b``, ``lb``, ``ub`` in the
backend's own data (DAQP's ``Model.update``, ProxQP's ``QP.update``, OSQP's ``update``,
Clarabel's ``update``; see :mod:`planner.optim.backends`) and :meth:`QPWorkspace.solve`
re-solves, warm-started where the backend allows it. The matrices ``P``, ``G``, ``A`` are
fixed: build a new workspace when they change.

Example::

    ws = QPWorkspace(QPProblem(P, q, G, h, A, b), solver="daqp")
    for b_k in targets:
        ws.update(b=b_k)
        x = ws.solve_primal()    # the fastest path: the primal solution only
    sol = ws.solve()             # a QPSolution with residuals and multipliers
"""

from __future__ import annotations

import time

import numpy as np

from planner import checks
from planner.errors import InfeasibleProblem, InvalidParameter
from planner.optim.backends import IN_PLACE, make_backend
from planner.optim.problem import QPProblem
from planner.optim.settings import DEFAULT_SETTINGS, available_solvers
from planner.optim.solution import QPSolution

__all__ = ["QPWorkspace"]

_VECTORS = ("q", "h", "b", "lb", "ub")


class QPWorkspace:
    """A QP set up once on one backend, updated in place and re-solved.

    Args:
        problem: the QP (its matrices are fixed for the workspace's life).
        solver: one of :func:`~planner.optim.settings.available_solvers`; ``daqp``,
            ``proxqp``, ``osqp`` and ``clarabel`` are updated in place, others are rebuilt at
            every solve (:attr:`in_place` says which).
        tolerance: accepted primal residual of a solution [units of the rows].
        initvals: (n,) first-solve warm-start guess (osqp, daqp, proxqp).
        **settings: backend settings overriding
            :data:`~planner.optim.settings.DEFAULT_SETTINGS`.

    Raises:
        InvalidParameter: ``problem`` is not a :class:`QPProblem`, the solver is unknown or not
            installed, or the tolerance is not > 0.
    """

    def __init__(
        self,
        problem: QPProblem,
        solver: str = "osqp",
        *,
        tolerance: float = 1e-6,
        initvals=None,
        **settings,
    ) -> None:
        if not isinstance(problem, QPProblem):
            raise InvalidParameter(f"problem: expected a QPProblem, got {type(problem).__name__}")
        self.solver = str(checks.choice("solver", solver, available_solvers()))
        self.tolerance = checks.positive("tolerance", tolerance)
        if initvals is not None:
            initvals = checks.vector("initvals", initvals, problem.n)
        self._P, self._G, self._A = problem.P, problem.G, problem.A
        self._vec = {
            k: None if getattr(problem, k) is None else getattr(problem, k).copy() for k in _VECTORS
        }
        opts = {**DEFAULT_SETTINGS.get(self.solver, {}), **settings}
        self._backend = make_backend(self.solver, problem, opts, initvals)

    @property
    def in_place(self) -> bool:
        """Whether updates change the backend's own data (``False``: rebuilt per solve)."""
        return self.solver in IN_PLACE

    @property
    def n(self) -> int:
        """Number of variables."""
        return self._vec["q"].size

    @property
    def problem(self) -> QPProblem:
        """The current problem (a validated copy: for saving and replaying)."""
        return QPProblem(*self.unpack())

    def unpack(self) -> tuple:
        """The current ``(P, q, G, h, A, b, lb, ub)`` (views: do not modify)."""
        v = self._vec
        return self._P, v["q"], self._G, v["h"], self._A, v["b"], v["lb"], v["ub"]

    def update(self, *, q=None, h=None, b=None, lb=None, ub=None, validate: bool = True) -> None:
        """Replace some of the vectors ``q``, ``h``, ``b``, ``lb``, ``ub`` in place.

        Args:
            q, h, b, lb, ub: the new vectors (``None``: unchanged), each of the size it had.
            validate: check sizes and values (default). ``False`` is for hot loops whose
                caller has already checked the vectors (float arrays of the right sizes, no
                NaN): a wrong vector then fails inside the backend or gives a wrong answer.

        Raises:
            InvalidParameter: a vector of another size than at construction, a vector the
                problem did not have (e.g. ``h`` without ``G``), or NaN.
        """
        given = {"q": q, "h": h, "b": b, "lb": lb, "ub": ub}
        for name, value in given.items():
            if value is not None:
                current = self._vec[name] if not validate else self._checked(name, value)
                current[:] = value
                given[name] = current
        self._backend.update(**given)

    def _checked(self, name: str, value) -> np.ndarray:
        """The stored vector ``name`` after checking that ``value`` can replace it."""
        current = self._vec[name]
        if current is None:
            raise InvalidParameter(
                f"{name}: the problem was built without {name}; build a new workspace"
            )
        arr = np.asarray(value, dtype=float)
        if arr.shape != current.shape:
            raise InvalidParameter(f"{name}: expected shape {current.shape}, got shape {arr.shape}")
        if not np.isfinite(arr).all() if name in ("q", "h", "b") else np.isnan(arr).any():
            raise InvalidParameter(f"{name}: expected finite values, got {arr.tolist()}")
        return current

    def _failure(self, message: str) -> InfeasibleProblem:
        return InfeasibleProblem(
            f"QP solver {self.solver!r} {message} (n={self.n})",
            problem=self.problem,
            solver=self.solver,
        )

    def solve_primal(self) -> np.ndarray:
        """Solve and return the primal solution ``x`` (n,) only: no residuals, no copy.

        Raises:
            InfeasibleProblem: the backend reports no solution.
        """
        x = self._backend.solve_x()
        if x is None:
            raise self._failure("found no solution")
        return x

    def solve(self) -> QPSolution:
        """Solve and return the :class:`QPSolution` with residuals and multipliers.

        Raises:
            InfeasibleProblem: no solution, or one violating the constraints by more than
                ``tolerance``; ``.problem`` holds the :class:`QPProblem` to replay it.
        """
        t0 = time.perf_counter()
        x, y, z, z_box = self._backend.solve()
        dt = time.perf_counter() - t0
        if x is None:
            raise self._failure("found no solution")
        sol = QPSolution.from_solve(self, np.array(x), y, z, z_box, self.solver, dt)
        if sol.primal_residual > self.tolerance:
            raise self._failure(
                f"returned a point violating the constraints by {sol.primal_residual:.3g} > "
                f"tolerance {self.tolerance:g}"
            )
        return sol
