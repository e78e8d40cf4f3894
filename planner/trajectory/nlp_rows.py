"""Pieces shared by the phase-1 NLPs (:class:`.RollingNLP`, :class:`.OutlineNLP`): the
fingertip frames as a CasADi function and the constraint rows with their bounds."""

from __future__ import annotations

import numpy as np


def tip_frames(hand):
    """``casadi.Function`` ``q (6,) -> (p_L (2,), phi_L, p_R (2,), phi_R)``: the fingertip
    positions [m] and orientations [rad] of the planar hand, walked from its Pinocchio model
    (:func:`planner.control.grasp_kinematics.finger_terms_sx`)."""
    import casadi as cs

    from planner.control.grasp_kinematics import finger_terms_sx

    qk = cs.SX.sym("qk", 6)
    T = finger_terms_sx(hand.model, qk, cs.SX.zeros(6), cs.SX.zeros(4), cs.SX.zeros(2))
    return cs.Function(
        "fk", [qk], [T["left"]["p"], T["left"]["phi"], T["right"]["p"], T["right"]["phi"]]
    )


class ConstraintRows:
    """Constraint rows ``lo <= g(x, p) <= hi`` of an NLP, added one expression at a time
    (every row of a vector expression gets the expression's bounds)."""

    def __init__(self) -> None:
        self.g: list = []
        self._lo: list[float] = []
        self._hi: list[float] = []

    def add(self, expr, lo: float, hi: float) -> None:
        """Append ``lo <= expr <= hi`` (``expr`` a CasADi scalar or column)."""
        self.g.append(expr)
        self._lo.append(lo)
        self._hi.append(hi)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """``(lbg, ubg)``: the bounds of every row, in the order added."""
        sizes = [int(e.shape[0]) for e in self.g]
        lo = np.concatenate([np.full(n, v) for n, v in zip(sizes, self._lo, strict=True)])
        hi = np.concatenate([np.full(n, v) for n, v in zip(sizes, self._hi, strict=True)])
        return lo, hi
