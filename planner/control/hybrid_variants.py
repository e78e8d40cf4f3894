"""Variants of the normal-force part of the hybrid law (thesis §4.3, the issue's item 1).

The law of §4.3 presses with an **open-loop** normal force (eqs. 4.12-4.13) and, when the
torques ``τ = τ_g + Jᵀ f`` exceed the motor limits, scales the whole Cartesian force ``f``
down (App. C.2.1): the normal force drops with the tangential one. Two variants:

* ``"closed_loop"``: a PI loop on the sensed normal force (the fingertip force sensor projected
  on the filtered contact normal) sets the force the law presses with
  (:func:`planner.control.hybrid_kernel.normal_force_pi`, compiled);
* ``"qp"``: when the law is torque limited, the force is the solution of a small QP that keeps
  the normal force first and gives up tangential force (:class:`TorqueLimitQP`, solved through
  :mod:`planner.optim`); unsaturated steps are the open-loop law (the QP's unconstrained
  optimum is the law's own force, so no solve is needed).

The QP keeps the directions of the law's tangential force ``f_t`` and normal force
``f_n n_W`` and chooses how much of each to keep, ``f = a f_t + s n_W``::

    minimize    1/2 w_t |f_t|² (a - 1)² + 1/2 w_n (s - f_n)²
    subject to  -τ_max <= τ_g + a Jᵀ f_t + s Jᵀ n_W <= τ_max,   0 <= a <= 1,   0 <= s <= f_n

with ``w_n >> w_t`` (the normal force goes first). The law's uniform scaling ``a = σ``,
``s = σ f_n`` is feasible, so the QP is never worse by its own measure; and it never pushes
harder than the law asked, in either direction (a free tangential force would buy normal force
by pushing sideways). The rows depend on the Jacobian, which changes every step, and
:class:`planner.optim.QPWorkspace` updates vectors only (``q``, ``h``, ``b``, bounds): the
problem and its workspace are built afresh on each saturated step (~0.15 ms with
``planner.optim``'s validation, of which DAQP's solve is a few µs), never on the others.
"""

from __future__ import annotations

import numpy as np

from planner.control import hybrid_kernel as hk

__all__ = ["FORCE_CONTROLS", "TorqueLimitQP"]

#: the normal-force variants a :class:`~planner.control.hybrid_law.HybridSettings` selects
FORCE_CONTROLS = ("open_loop", "closed_loop", "qp")


class TorqueLimitQP:
    """The torque-limit QP of the ``"qp"`` variant (see the module doc).

    Args:
        limits: (3,) motor torque limits τ_max [N m].
        weights: ``(w_t, w_n)`` weights of the tangential and normal force errors [1/N²].

    Attributes:
        solves, failures: QPs solved and QPs the solver failed on (the law's torques stood).
        solver: a :mod:`planner.optim` solver (``"daqp"`` by default).
    """

    def __init__(self, limits, weights=(1.0, 100.0), solver: str = "daqp") -> None:
        self.limits = np.asarray(limits, float).copy()
        self.w_t, self.w_n = (float(w) for w in weights)
        self.solver = solver
        self.last = np.zeros(2)
        self.solves = 0
        self.failures = 0

    def split(self, out: np.ndarray, normal: np.ndarray) -> tuple[np.ndarray, float]:
        """``(f_t, f_n)``: the law's tangential force (3,) [N] (WCS) and normal force [N]."""
        f = out[hk.O_F : hk.O_F + 3]
        fn = float(f @ normal)
        return f - fn * normal, fn

    def solve(self, out: np.ndarray, normal: np.ndarray) -> np.ndarray | None:
        """Torques (3,) [N m] of the QP for the step whose outputs are ``out`` (see
        :mod:`~planner.control.hybrid_kernel`) and filtered normal ``normal`` (3,); None when
        gravity alone exceeds a limit or the solver fails (the law's scaled torques stand).
        :attr:`last` holds ``(a, s)`` of the solution."""
        from planner.errors import HapexError
        from planner.optim import QPProblem, QPWorkspace

        J = out[hk.O_J : hk.O_J + 9].reshape(3, 3)
        tg = np.array([out[hk.O_TG], out[hk.O_TG + 1], 0.0])
        room_hi, room_lo = self.limits - tg, self.limits + tg
        if np.any(room_hi <= 0.0) or np.any(room_lo <= 0.0):
            return None
        ft, fn = self.split(out, normal)
        M = np.column_stack([J.T @ ft, J.T @ normal])  # torques per unit of (a, s)
        wt = max(self.w_t * float(ft @ ft), 1e-12)
        self.solves += 1
        try:
            problem = QPProblem(
                np.diag([wt, self.w_n]),
                np.array([-wt, -self.w_n * fn]),
                np.vstack([M, -M]),
                np.concatenate([room_hi, room_lo]),
                lb=np.zeros(2),
                ub=np.array([1.0, max(fn, 0.0)]),
            )
            x = QPWorkspace(problem, solver=self.solver).solve_primal()
        except HapexError:
            self.failures += 1
            return None
        self.last = np.array(x, float)
        return np.clip(tg + M @ self.last, -self.limits, self.limits)

    def apply(self, out: np.ndarray, normal: np.ndarray) -> bool:
        """Replace the law's scaled torques ``out[0:3]`` and normal-force command ``out[18]``
        by the QP's when the step was torque limited; returns whether it did."""
        if out[13] == 0.0:
            return False
        tau = self.solve(out, normal)
        if tau is None:
            return False
        out[0:3] = tau
        out[18] = float(self.last[1])
        return True
