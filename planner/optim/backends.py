"""One adapter per QP backend: set up once, update vectors in place, solve.

Every adapter takes a validated :class:`~planner.optim.problem.QPProblem` and exposes
``update(q, h, b, lb, ub)`` (each ``None`` or a new (validated) vector of the same size) and
``solve() -> (x, y, z, z_box)`` with ``x = None`` when the backend reports no solution.
Multipliers follow qpsolvers' convention (see :mod:`planner.optim.solution`).

* ``daqp``: ``daqp.Model`` (setup once, ``update(f=, bupper=, blower=)``): truly in place;
* ``proxqp``: ``proxsuite.proxqp.dense.QP`` (``init`` once, ``update(g=, b=, l=, u=)``,
  warm-started from the previous result): truly in place;
* ``osqp``: ``osqp.OSQP`` (``setup`` once, ``update(q=, l=, u=)``, warm-started): in place;
* ``clarabel``: ``clarabel.DefaultSolver`` with presolve off (``update(q=, b=)``): in place,
  provided the set of finite bounds does not change;
* any other qpsolvers backend (``quadprog`` ...): rebuilt at every solve.
"""

from __future__ import annotations

import numpy as np

from planner.errors import InvalidParameter
from planner.optim.problem import QPProblem

__all__ = ["IN_PLACE", "make_backend"]

#: Backends whose adapter updates the solver's own data instead of rebuilding it.
IN_PLACE = ("daqp", "proxqp", "osqp", "clarabel")

_DAQP_INF = 1e30
_PROXQP_INF = 1e20


def _sizes(pb: QPProblem) -> tuple[int, int, int]:
    n_eq = 0 if pb.A is None else pb.A.shape[0]
    n_in = 0 if pb.G is None else pb.G.shape[0]
    return pb.n, n_eq, n_in


def _box(pb: QPProblem) -> tuple[np.ndarray, np.ndarray] | None:
    if pb.lb is None and pb.ub is None:
        return None
    n = pb.n
    lb = np.full(n, -np.inf) if pb.lb is None else pb.lb
    ub = np.full(n, np.inf) if pb.ub is None else pb.ub
    return lb, ub


def _rows(pb: QPProblem) -> np.ndarray:
    mats = [m for m in (pb.A, pb.G) if m is not None]
    return np.vstack(mats) if mats else np.zeros((0, pb.n))


class _Backend:
    """What every adapter offers besides ``update`` and ``solve``."""

    def solve(self):  # pragma: no cover - every adapter overrides it
        raise NotImplementedError

    def solve_x(self) -> np.ndarray | None:
        """The primal solution only (``None``: no solution); adapters may skip multipliers."""
        return self.solve()[0]


class _Daqp(_Backend):
    """DAQP through ``daqp.Model``: bounds ``[box; A; G]``, equality rows with sense 5."""

    def __init__(self, pb: QPProblem, settings: dict, initvals) -> None:
        import daqp

        n, n_eq, n_in = _sizes(pb)
        box = _box(pb)
        self._nb = 0 if box is None else n
        self._n_eq, self._n_in = n_eq, n_in
        m = self._nb + n_eq + n_in
        self._up, self._lo = np.empty(m), np.full(m, -_DAQP_INF)  # G rows: no lower bound
        self._set(box, pb.b, pb.h)
        sense = np.zeros(m, dtype=np.int32)
        sense[self._nb : self._nb + n_eq] = 5  # equality rows: active and immutable
        self._model = daqp.Model()
        if settings:
            self._model.settings = {**self._model.settings, **settings}
        start = None if initvals is None else np.asarray(initvals, dtype=float)
        flag, _ = self._model.setup(
            pb.P, pb.q, _rows(pb), self._up, self._lo, sense, primal_start=start
        )
        self._setup_ok = flag >= 0

    def _set(self, box, b, h) -> None:
        nb, n_eq = self._nb, self._n_eq
        if box is not None:
            np.clip(box[1], -_DAQP_INF, _DAQP_INF, out=self._up[:nb])
            np.clip(box[0], -_DAQP_INF, _DAQP_INF, out=self._lo[:nb])
        if b is not None:
            self._up[nb : nb + n_eq] = b
            self._lo[nb : nb + n_eq] = b
        if h is not None:
            self._up[nb + n_eq :] = h

    def update(self, q, h, b, lb, ub) -> None:
        if q is not None:
            self._model.update(f=q)
        if h is not None or b is not None or lb is not None or ub is not None:
            box = (
                None
                if lb is None and ub is None
                else (
                    self._lo[: self._nb] if lb is None else lb,
                    self._up[: self._nb] if ub is None else ub,
                )
            )
            self._set(box, b, h)
            self._model.update(bupper=self._up, blower=self._lo)

    def solve_x(self) -> np.ndarray | None:
        if not self._setup_ok:
            return None
        x, _, flag, _ = self._model.solve()
        return x if flag >= 1 else None

    def solve(self):
        if not self._setup_ok:
            return None, None, None, None
        x, _, flag, info = self._model.solve()
        if flag < 1:
            return None, None, None, None
        lam = info["lam"]
        nb, n_eq = self._nb, self._n_eq
        y = lam[nb : nb + n_eq] if n_eq else None
        z = lam[nb + n_eq :] if self._n_in else None
        return x, y, z, (lam[:nb] if nb else None)


class _Proxqp(_Backend):
    """ProxQP's dense backend: ``A x = b`` and ``l <= C x <= u`` with ``C = [G; I]``.

    Bounds are plain rows of ``C`` (one code path for the multipliers).
    """

    def __init__(self, pb: QPProblem, settings: dict, initvals) -> None:
        from proxsuite import proxqp

        n, n_eq, n_in = _sizes(pb)
        box = _box(pb)
        self._n_in, self._box = n_in, box is not None
        C = np.vstack([np.zeros((0, n))] + ([pb.G] if n_in else []) + ([np.eye(n)] if box else []))
        self._l = np.concatenate([np.full(n_in, -_PROXQP_INF)] + ([box[0]] if box else []))
        self._u = np.concatenate([pb.h if n_in else np.zeros(0)] + ([box[1]] if box else []))
        np.clip(self._l, -_PROXQP_INF, _PROXQP_INF, out=self._l)
        np.clip(self._u, -_PROXQP_INF, _PROXQP_INF, out=self._u)
        self._qp = proxqp.dense.QP(n, n_eq, C.shape[0])
        for key, value in settings.items():
            setattr(self._qp.settings, key, value)
        self._solved = proxqp.QPSolverOutput.PROXQP_SOLVED
        has_c = C.shape[0] > 0
        self._qp.init(
            pb.P,
            pb.q,
            pb.A,
            pb.b,
            C if has_c else None,
            self._l if has_c else None,
            self._u if has_c else None,
        )
        # warm start from the previous result only once there is one (else ProxQP segfaults)
        self._warm = proxqp.InitialGuess.WARM_START_WITH_PREVIOUS_RESULT
        self._x0 = None if initvals is None else np.asarray(initvals, dtype=float)

    def update(self, q, h, b, lb, ub) -> None:
        n_in = self._n_in
        if h is not None:
            self._u[:n_in] = h
        if lb is not None:
            np.clip(lb, -_PROXQP_INF, _PROXQP_INF, out=self._l[n_in:])
        if ub is not None:
            np.clip(ub, -_PROXQP_INF, _PROXQP_INF, out=self._u[n_in:])
        kw = {"g": q, "b": b}
        if lb is not None:
            kw["l"] = self._l
        if h is not None or ub is not None:
            kw["u"] = self._u
        self._qp.update(**{k: v for k, v in kw.items() if v is not None})

    def solve(self):
        if self._x0 is not None:
            self._qp.solve(self._x0, None, None)
            self._x0 = None
        else:
            self._qp.solve()
        self._qp.settings.initial_guess = self._warm
        res = self._qp.results
        if res.info.status != self._solved:
            return None, None, None, None
        z_all = np.array(res.z)
        return (
            np.array(res.x),
            np.array(res.y) if res.y.size else None,
            z_all[: self._n_in] if self._n_in else None,
            z_all[self._n_in :] if self._box else None,
        )


class _Osqp(_Backend):
    """OSQP: rows ``[A; G; I]`` with ``l <= rows x <= u`` (I only when there are bounds)."""

    def __init__(self, pb: QPProblem, settings: dict, initvals) -> None:
        import osqp
        from scipy import sparse

        n, n_eq, n_in = _sizes(pb)
        box = _box(pb)
        self._n_eq, self._n_in, self._box = n_eq, n_in, box is not None
        mats = [_rows(pb)] + ([np.eye(n)] if box is not None else [])
        self._l = np.concatenate(
            [pb.b if n_eq else [], np.full(n_in, -np.inf)] + ([box[0]] if box else [])
        )
        self._u = np.concatenate(
            [pb.b if n_eq else [], pb.h if n_in else []] + ([box[1]] if box else [])
        )
        self._solver = osqp.OSQP()
        self._solver.setup(
            sparse.csc_matrix(np.triu(pb.P)),
            pb.q,
            sparse.csc_matrix(np.vstack(mats)),
            self._l,
            self._u,
            **{"verbose": False, "warm_starting": True, **settings},
        )
        if initvals is not None:
            self._solver.warm_start(x=np.asarray(initvals, dtype=float))

    def update(self, q, h, b, lb, ub) -> None:
        n_eq, n_in = self._n_eq, self._n_in
        if b is not None:
            self._l[:n_eq] = b
            self._u[:n_eq] = b
        if h is not None:
            self._u[n_eq : n_eq + n_in] = h
        if lb is not None:
            self._l[n_eq + n_in :] = lb
        if ub is not None:
            self._u[n_eq + n_in :] = ub
        kw = {"q": q}
        if b is not None or lb is not None:
            kw["l"] = self._l
        if b is not None or h is not None or ub is not None:
            kw["u"] = self._u
        self._solver.update(**{k: v for k, v in kw.items() if v is not None})

    def solve(self):
        res = self._solver.solve(raise_error=False)  # failures are reported by status
        x = res.x
        if res.info.status_val not in (1, 2) or x is None or not np.all(np.isfinite(x)):
            return None, None, None, None
        n_eq, n_in = self._n_eq, self._n_in
        y = res.y
        return (
            x,
            y[:n_eq] if n_eq else None,
            y[n_eq : n_eq + n_in] if n_in else None,
            y[n_eq + n_in :] if self._box else None,
        )


class _Clarabel(_Backend):
    """Clarabel: ``[A; G; I_ub; -I_lb] x + s = [b; h; ub; -lb]``, ``s`` in zero/nonneg cones."""

    def __init__(self, pb: QPProblem, settings: dict, initvals) -> None:
        import clarabel
        from scipy import sparse

        n, n_eq, n_in = _sizes(pb)
        box = _box(pb)
        eye = np.eye(n)
        self._iu = np.flatnonzero(np.isfinite(box[1])) if box else np.zeros(0, int)
        self._il = np.flatnonzero(np.isfinite(box[0])) if box else np.zeros(0, int)
        self._n_eq, self._n_in, self._box = n_eq, n_in, box is not None
        M = np.vstack([_rows(pb), eye[self._iu], -eye[self._il]])
        self._rhs = np.concatenate(
            [
                pb.b if n_eq else [],
                pb.h if n_in else [],
                box[1][self._iu] if box else [],
                -box[0][self._il] if box else [],
            ]
        )
        cones = [clarabel.ZeroConeT(n_eq)] if n_eq else []
        if M.shape[0] > n_eq:
            cones.append(clarabel.NonnegativeConeT(M.shape[0] - n_eq))
        opts = clarabel.DefaultSettings()
        opts.verbose = False
        opts.presolve_enable = False  # keeps data updates allowed
        for key, value in settings.items():
            setattr(opts, key, value)
        self._ok = (clarabel.SolverStatus.Solved, clarabel.SolverStatus.AlmostSolved)
        self._solver = clarabel.DefaultSolver(
            sparse.csc_matrix(np.triu(pb.P)), pb.q, sparse.csc_matrix(M), self._rhs, cones, opts
        )

    def update(self, q, h, b, lb, ub) -> None:
        n_eq, n_in = self._n_eq, self._n_in
        nu = self._iu.size
        for name, v, idx in (("lb", lb, self._il), ("ub", ub, self._iu)):
            if v is not None and not np.array_equal(np.flatnonzero(np.isfinite(v)), idx):
                raise InvalidParameter(
                    f"{name}: expected the same finite entries as at construction "
                    f"(clarabel's in-place update keeps the constraint rows), got {v.tolist()}"
                )
        if b is not None:
            self._rhs[:n_eq] = b
        if h is not None:
            self._rhs[n_eq : n_eq + n_in] = h
        if ub is not None:
            self._rhs[n_eq + n_in : n_eq + n_in + nu] = ub[self._iu]
        if lb is not None:
            self._rhs[n_eq + n_in + nu :] = -lb[self._il]
        kw = {"q": q, "b": self._rhs if any(v is not None for v in (b, h, lb, ub)) else None}
        self._solver.update(**{k: v for k, v in kw.items() if v is not None})

    def solve(self):
        sol = self._solver.solve()
        if sol.status not in self._ok:
            return None, None, None, None
        x, zc = np.array(sol.x), np.array(sol.z)
        n_eq, n_in = self._n_eq, self._n_in
        z_box = None
        if self._box:
            z_box = np.zeros(x.size)
            nu = self._iu.size
            z_box[self._iu] += zc[n_eq + n_in : n_eq + n_in + nu]
            z_box[self._il] -= zc[n_eq + n_in + nu :]
        return x, zc[:n_eq] if n_eq else None, zc[n_eq : n_eq + n_in] if n_in else None, z_box


class _Rebuild(_Backend):
    """Any other qpsolvers backend: the problem is handed to ``qpsolvers`` at every solve."""

    def __init__(self, pb: QPProblem, settings: dict, initvals, name: str) -> None:
        self._data = dict(zip(("P", "q", "G", "h", "A", "b", "lb", "ub"), pb.unpack(), strict=True))
        self._settings, self._initvals, self._name = settings, initvals, name

    def update(self, q, h, b, lb, ub) -> None:
        for key, v in (("q", q), ("h", h), ("b", b), ("lb", lb), ("ub", ub)):
            if v is not None:
                self._data[key] = v

    def solve(self):
        import qpsolvers

        problem = qpsolvers.Problem(**self._data)
        sol = qpsolvers.solve_problem(
            problem, solver=self._name, initvals=self._initvals, **self._settings
        )
        if not sol.found or sol.x is None or not np.all(np.isfinite(sol.x)):
            return None, None, None, None
        return sol.x, sol.y, sol.z, sol.z_box


_ADAPTERS = {"daqp": _Daqp, "proxqp": _Proxqp, "osqp": _Osqp, "clarabel": _Clarabel}


def make_backend(name: str, problem: QPProblem, settings: dict, initvals=None):
    """The adapter of backend ``name`` set up on ``problem`` (see the module docstring)."""
    if name in _ADAPTERS:
        return _ADAPTERS[name](problem, settings, initvals)
    return _Rebuild(problem, settings, initvals, name)
