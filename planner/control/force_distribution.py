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

The problem is *built once* for a grasp as a :class:`planner.optim.QPWorkspace` and
re-solved for new wrenches and squeezes by changing only the vectors ``b = w`` and ``h``:
DAQP, ProxQP, OSQP and Clarabel update their own data in place (warm-started where the
backend allows); other backends are rebuilt at every solve.
"""

from __future__ import annotations

import math
import time
from typing import NamedTuple

import numpy as np

from planner import checks
from planner.contact.cones import cone_halfspaces, tangent_basis
from planner.errors import InfeasibleProblem
from planner.grasp.grasp_matrix import grasp_matrix
from planner.grasp.wrenches import check_contacts
from planner.optim import QPProblem, QPWorkspace, available_solvers

__all__ = ["OBJECTIVES", "ForceDistribution", "GraspForceQP", "distribute_forces"]

OBJECTIVES = ("min_norm", "max_margin")


class ForceDistribution(NamedTuple):
    """Solution of the grasp-force QP (a NamedTuple: built in control loops, cheap to make).

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


def _block_rows(blocks: np.ndarray) -> np.ndarray:
    """Block-diagonal rows: (k, m, d) per-contact rows -> (k m, k d) rows acting on ``f``."""
    k, m, d = blocks.shape
    out = np.zeros((k * m, k * d))
    for i in range(k):
        out[m * i : m * (i + 1), d * i : d * (i + 1)] = blocks[i]
    return out


def _cost(objective: str, normals: np.ndarray) -> np.ndarray:
    """The QP's Hessian: ``I`` (min_norm) or the tangent projector ``+ 1e-3 I`` (max_margin)."""
    k, d = normals.shape
    if objective == "min_norm":
        return np.eye(k * d)
    H = 1e-3 * np.eye(k * d)
    for i, n in enumerate(normals):
        sl = slice(d * i, d * (i + 1))
        H[sl, sl] += np.eye(d) - np.outer(n, n)  # sum of t t^T over the tangents
    return H


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
        native: ``True`` (default) keeps one :class:`~planner.optim.QPWorkspace` updated in
            place; ``False`` rebuilds the backend at every solve (for comparison).
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
        p, n = check_contacts(points, normals, 1)
        self.mu = checks.nonnegative("mu", mu)
        self.objective = str(checks.choice("objective", objective, OBJECTIVES))
        self.solver = str(checks.choice("solver", solver, available_solvers()))
        k, d = p.shape
        self.k, self.d, self.normals = k, d, n
        self.G = grasp_matrix(p, torque_reference)
        self.C = _block_rows(cone_halfspaces(n, self.mu, facets))  # C f <= 0: inside cones
        self.N = _block_rows(n[:, None, :])  # N f >= squeeze: normal components
        self.H = _cost(self.objective, n)
        self.native = bool(native)
        # |f_t,i| = |T_i f|: planar one tangent row per contact, spatial two
        tangents = n[:, None, ::-1] * [[-1.0, 1.0]] if d == 2 else np.stack(tangent_basis(n), 1)
        self._T = _block_rows(tangents)
        self._out = np.vstack([self.G, self.N, self._T])  # one product gives G f, N f, T f
        self._squeeze = 0.0
        self._h = np.zeros(self.C.shape[0] + k)
        self._ws = QPWorkspace(self._problem(np.zeros(self.G.shape[0]), 0.0), self.solver)

    def _problem(self, w: np.ndarray, squeeze: float) -> QPProblem:
        h = np.concatenate([np.zeros(self.C.shape[0]), np.full(self.k, -squeeze)])
        return QPProblem(
            self.H, np.zeros(self.H.shape[0]), np.vstack([self.C, -self.N]), h, self.G, w
        )

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
            InfeasibleProblem: the wrench cannot be realized inside the cones; ``.problem``
                is the :class:`~planner.optim.QPProblem` (``.save(path)`` to replay it).
        """
        w = np.asarray(wrench, dtype=float)
        if w.shape != (self.G.shape[0],) or not all(map(math.isfinite, w.tolist())):
            w = checks.vector("wrench", wrench, self.G.shape[0], "N, N m")  # raises
        squeeze = checks.nonnegative("squeeze", squeeze, "N")
        t0 = time.perf_counter()
        try:
            if self.native:
                h = None
                if squeeze != self._squeeze:
                    self._h[self.C.shape[0] :] = -squeeze
                    self._squeeze, h = squeeze, self._h
                self._ws.update(b=w, h=h, validate=False)  # w checked above
                x = self._ws.solve_primal()
            else:
                x = QPWorkspace(self._problem(w, squeeze), self.solver).solve_primal()
        except InfeasibleProblem:
            x = None
        dt = time.perf_counter() - t0
        return self._distribution(x, w, squeeze, dt)

    def _distribution(self, x, w: np.ndarray, squeeze: float, dt: float) -> ForceDistribution:
        """Check the backend's ``x`` (None: failed) and derive forces, margins and residuals.

        Python floats rather than numpy reductions: on these (<= 18,) vectors a numpy
        reduction costs more than the whole loop (this runs in control loops).
        """
        nw, k = w.size, self.k
        wl = w.tolist()
        yl = None if x is None else self._out.dot(x).tolist()  # G x, N x, T x
        res_w = math.inf if yl is None else max([abs(a - b) for a, b in zip(yl, wl, strict=False)])
        if res_w > 1e-5 * max(1.0, max(map(abs, wl)), squeeze):
            why = "found no solution" if x is None else f"left a wrench residual {res_w:.3g}"
            raise InfeasibleProblem(
                f"no contact forces inside the friction cones realize the wrench "
                f"{wl} with squeeze {squeeze} N (solver {self.solver} {why})",
                problem=self._problem(w, squeeze),
                solver=self.solver,
            )
        fn, tl = yl[nw : nw + k], yl[nw + k :]
        ft = [abs(t) for t in tl] if self.d == 2 else list(map(math.hypot, tl[::2], tl[1::2]))
        margin = min([self.mu * a - b for a, b in zip(fn, ft, strict=True)])
        return ForceDistribution(
            x.reshape(k, self.d), np.array(fn), np.array(ft), res_w, margin, self.solver, dt
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
