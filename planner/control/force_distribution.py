"""Grasp-force distribution: contact forces inside the friction cones that realize a desired
object wrench plus an internal squeeze (§2.2.2 "internal force", eqs. 2.1, 2.6, 2.9).

The QP, in the contact forces ``f`` ((k d,) stacked, applied on the object, WCS)::

    minimize    1/2 f^T H f
    subject to  G f = w                       (object wrench, eq. 2.6 with G of grasp_matrix)
                n_i . f_i >= f_squeeze         (internal squeeze: minimum normal force)
                f_i in the friction cone       (planar: exact 2 edges; spatial: m-facet pyramid)

with ``H`` chosen by ``objective``:

* ``"min_norm"`` — ``H = I``: the smallest total force (classic minimum-norm distribution);
* ``"max_margin"`` — ``H = P_t + 1e-3 I`` with ``P_t`` the projector on the contact tangents:
  the smallest tangential forces, i.e. every force as close to its cone axis as the wrench
  allows (largest friction margin), with a small norm term to keep the QP strictly convex.

The problem is *built once* for a grasp and re-solved for new wrenches and squeezes by
changing only constraint bounds: with ``solver="osqp"`` a native OSQP object is set up once and
updated in place (``update(l=..., u=...)``, warm-started), with ``"daqp"`` the dense data are
prebuilt and DAQP is called directly; other backends go through
:func:`planner.control.qp.solve_qp` each time.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from planner.control.qp import available_solvers, solve_qp
from planner.errors import InfeasibleProblem, InvalidParameter

OBJECTIVES = ("min_norm", "max_margin")


@dataclass(frozen=True)
class ForceDistribution:
    """Solution of the grasp-force QP.

    Attributes:
        forces: (k, d) contact forces applied on the object, WCS [N].
        normal: (k,) normal components ``n_i . f_i`` [N].
        tangential: (k,) tangential magnitudes [N].
        wrench_residual: ``max |G f - w|`` [N or N m].
        cone_margin: ``min_i (mu n_i.f_i - |f_t,i|)`` [N] (>= 0 up to tolerance: inside cones;
            for pyramids measured against the inscribed pyramid).
        solver: the backend used; solve_time_s: wall-clock time of the solve [s].
    """

    forces: np.ndarray
    normal: np.ndarray
    tangential: np.ndarray
    wrench_residual: float
    cone_margin: float
    solver: str
    solve_time_s: float


class GraspForceQP:
    """The grasp-force distribution QP of one grasp, built once, re-solved in place.

    Args:
        points: (k, 2) or (k, 3) contact points, WCS [m].
        normals: (k, d) inward unit normals (normalized here).
        mu: friction coefficient (>= 0).
        objective: ``"min_norm"`` or ``"max_margin"`` (see the module docstring).
        solver: QP backend (``"osqp"`` default; ``"daqp"``, ``"proxqp"``, ``"clarabel"``, ...).
        torque_reference: (d,) point about which the wrench's torque is given [m]
            (default: the contacts' centroid).
        facets: spatial pyramids' facets (>= 3).
        native: use the native in-place solver object where one exists (osqp, daqp).
    """

    def __init__(
        self,
        points,
        normals,
        mu: float,
        *,
        objective: str = "min_norm",
        solver: str = "osqp",
        torque_reference=None,
        facets: int = 8,
        native: bool = True,
    ):
        from planner.grasp.cones import check_mu, tangent_basis
        from planner.grasp.grasp_matrix import grasp_matrix
        from planner.grasp.wrenches import check_contacts

        p, n = check_contacts(points, normals, 1)
        self.mu = check_mu(mu)
        if objective not in OBJECTIVES:
            raise InvalidParameter(
                f"objective must be one of {list(OBJECTIVES)}, got {objective!r}"
            )
        if solver not in available_solvers():
            raise InvalidParameter(
                f"unknown or uninstalled QP solver {solver!r}; expected one "
                f"of {list(available_solvers())}"
            )
        k, d = p.shape
        self.k, self.d, self.solver, self.objective = k, d, solver, objective
        self.normals = n
        self.G = grasp_matrix(p, torque_reference)
        nv = k * d
        # friction-cone rows C f <= 0 and normal rows N f (>= squeeze)
        rows = []
        N = np.zeros((k, nv))
        tangents = []
        for i in range(k):
            sl = slice(d * i, d * (i + 1))
            N[i, sl] = n[i]
            if d == 2:
                t = np.array([-n[i, 1], n[i, 0]])
                tangents.append(t[None, :])
                for sgn in (1.0, -1.0):
                    r = np.zeros(nv)
                    r[sl] = sgn * t - self.mu * n[i]
                    rows.append(r)
            else:
                t1, t2 = tangent_basis(n[i : i + 1])
                tangents.append(np.vstack([t1, t2]))
                m = int(facets)
                for a in range(m):
                    ang = 2 * np.pi * (a + 0.5) / m
                    u = np.cos(ang) * t1[0] + np.sin(ang) * t2[0]
                    r = np.zeros(nv)
                    r[sl] = u - self.mu * np.cos(np.pi / m) * n[i]
                    rows.append(r)
        self.C = np.array(rows)
        self.N = N
        self._tangents = tangents
        if objective == "min_norm":
            H = np.eye(nv)
        else:
            H = 1e-3 * np.eye(nv)
            for i, T in enumerate(tangents):
                sl = slice(d * i, d * (i + 1))
                H[sl, sl] += T.T @ T
        self.H = H
        self.native = bool(native) and solver in ("osqp", "daqp")
        self._osqp = None
        self._A_all = np.vstack([self.G, self.C, self.N])
        if self.native and solver == "osqp":
            import osqp
            from scipy import sparse

            self._osqp = osqp.OSQP()
            m_all = self._A_all.shape[0]
            self._osqp.setup(
                sparse.csc_matrix(np.triu(H)),
                np.zeros(nv),
                sparse.csc_matrix(self._A_all),
                -np.inf * np.ones(m_all),
                np.inf * np.ones(m_all),
                verbose=False,
                eps_abs=1e-9,
                eps_rel=1e-9,
                polishing=True,
                max_iter=40000,
                warm_starting=True,
            )

    def _bounds(self, w: np.ndarray, squeeze: float) -> tuple[np.ndarray, np.ndarray]:
        nc, k = self.C.shape[0], self.k
        lo = np.concatenate([w, np.full(nc, -np.inf), np.full(k, squeeze)])
        up = np.concatenate([w, np.zeros(nc), np.full(k, np.inf)])
        return lo, up

    def solve(self, wrench, squeeze: float = 0.0) -> ForceDistribution:
        """Contact forces realizing ``wrench`` with every normal force >= ``squeeze``.

        Args:
            wrench: (3,) planar ``(f_x, f_y, tau_z)`` or (6,) spatial ``(f, tau)`` object wrench
                to be applied by the contacts, torques about the torque reference [N, N m].
            squeeze: minimum normal force at every contact (internal force) [N], >= 0.

        Returns:
            The :class:`ForceDistribution` with its residuals.

        Raises:
            InvalidParameter: wrong wrench shape, negative squeeze.
            InfeasibleProblem: the wrench cannot be realized inside the cones.
        """
        w = np.asarray(wrench, dtype=float).ravel()
        if w.shape != (self.G.shape[0],) or not np.all(np.isfinite(w)):
            raise InvalidParameter(
                f"wrench must be {self.G.shape[0]} finite numbers, got {np.shape(wrench)}"
            )
        squeeze = float(squeeze)
        if not np.isfinite(squeeze) or squeeze < 0:
            raise InvalidParameter(f"squeeze must be >= 0 [N], got {squeeze!r}")
        t0 = time.perf_counter()
        if self._osqp is not None:
            lo, up = self._bounds(w, squeeze)
            self._osqp.update(l=lo, u=up)
            res = self._osqp.solve()
            x = res.x
            ok = res.info.status_val in (1, 2) and x is not None and np.all(np.isfinite(x))
        elif self.native and self.solver == "daqp":
            import daqp

            lo, up = self._bounds(w, squeeze)
            sense = np.zeros(lo.size, dtype=np.int32)
            sense[: w.size] = 5  # equality rows: active + immutable
            x, _, flag, _ = daqp.solve(
                self.H,
                np.zeros(self.H.shape[0]),
                self._A_all,
                np.where(np.isinf(up), 1e30, up),
                np.where(np.isinf(lo), -1e30, lo),
                sense,
            )
            ok = flag == 1
        else:
            try:
                sol = solve_qp(
                    self.H,
                    np.zeros(self.H.shape[0]),
                    np.vstack([self.C, -self.N]),
                    np.concatenate([np.zeros(self.C.shape[0]), np.full(self.k, -squeeze)]),
                    self.G,
                    w,
                    solver=self.solver,
                )
                x, ok = sol.x, True
            except InfeasibleProblem:
                x, ok = None, False
        dt = time.perf_counter() - t0
        problem = {
            "H": self.H,
            "G": self.G,
            "C": self.C,
            "N": self.N,
            "wrench": w,
            "squeeze": squeeze,
        }
        if not ok:
            raise InfeasibleProblem(
                f"no contact forces inside the friction cones realize the "
                f"wrench {w.tolist()} with squeeze {squeeze} N "
                f"(solver {self.solver})",
                problem=problem,
                solver=self.solver,
            )
        x = np.asarray(x, dtype=float)
        res_w = float(np.max(np.abs(self.G @ x - w)))
        if res_w > 1e-5 * max(1.0, float(np.max(np.abs(w))), squeeze):
            raise InfeasibleProblem(
                f"solver {self.solver} returned forces with wrench residual "
                f"{res_w:.3g}: the wrench is not realizable inside the cones",
                problem=problem,
                solver=self.solver,
            )
        f = x.reshape(self.k, self.d)
        fn = np.sum(f * self.normals, axis=1)
        ft = np.linalg.norm(f - fn[:, None] * self.normals, axis=1)
        return ForceDistribution(
            f, fn, ft, res_w, float(np.min(self.mu * fn - ft)), self.solver, dt
        )


def distribute_forces(
    points,
    normals,
    mu: float,
    wrench,
    squeeze: float = 0.0,
    *,
    objective: str = "min_norm",
    solver: str = "osqp",
    torque_reference=None,
) -> ForceDistribution:
    """One-shot grasp-force distribution (builds a :class:`GraspForceQP` and solves it once)."""
    qp = GraspForceQP(
        points, normals, mu, objective=objective, solver=solver, torque_reference=torque_reference
    )
    return qp.solve(wrench, squeeze)


__all__ = ["OBJECTIVES", "ForceDistribution", "GraspForceQP", "distribute_forces"]
