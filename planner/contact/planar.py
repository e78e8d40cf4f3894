"""Planar pure rolling (thesis §2.2.2, eqs. 2.3-2.4, Table 2.1).

With soft-finger contact the spin is held (``ψ̇ = 0``); for planar rolling in the ``x-z``
plane of the contact frame the only relative rate is ``ω_y`` (Table 2.1) and Montana's
equations reduce to eq. 2.3, which with constant ``K, M, ψ`` integrate to eq. 2.4: the
contact points travel equal arc lengths ``s`` on both bodies, ``s = θ / (k1 + k2)`` for a
relative rotation ``θ`` of bodies with curvatures ``k1, k2`` in the rolling plane — for a
fingertip of radius ``r`` on a flat object the familiar ``s = r θ``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Literal

import numpy as np

from planner.contact.montana import montana_rates
from planner.errors import InvalidParameter, SingularConfiguration

Constraint = Literal["maintain_contact", "no_sliding", "no_spin", "planar_rolling"]

#: Table 2.1: the relative-velocity components each contact constraint sets to zero.
TABLE_2_1: dict[str, tuple[str, ...]] = {
    "maintain_contact": ("vz",),
    "no_sliding": ("vx", "vy"),
    "no_spin": ("wz",),
    "planar_rolling": ("wx",),
}
_INDEX = {"vx": 0, "vy": 1, "vz": 2, "wx": 3, "wy": 4, "wz": 5}


def constraint_violations(
    v, omega, constraints: Iterable[str] = tuple(TABLE_2_1), tol: float = 1e-9
) -> dict[str, float]:
    """Which contact-velocity constraints of Table 2.1 a relative motion violates.

    Args:
        v: (3,) relative translational velocity in the contact frame [m/s].
        omega: (3,) relative rotational velocity in the contact frame [rad/s].
        constraints: names among ``TABLE_2_1`` (default: all, i.e. pure planar rolling).
        tol: magnitude below which a component counts as zero.

    Returns:
        ``{constraint: largest offending |component|}`` for the violated ones (empty when
        the motion satisfies them all).
    """
    twist = np.concatenate([np.asarray(v, float).reshape(3), np.asarray(omega, float).reshape(3)])
    out = {}
    for name in constraints:
        if name not in TABLE_2_1:
            raise InvalidParameter(
                f"constraints: expected names in {sorted(TABLE_2_1)}, got {name!r}"
            )
        worst = max(abs(twist[_INDEX[c]]) for c in TABLE_2_1[name])
        if worst > tol:
            out[name] = float(worst)
    return out


def planar_rolling_rates(
    K1, M1, K2, M2, psi: float, omega_y: float
) -> tuple[np.ndarray, np.ndarray]:
    """Eq. 2.3: contact rates of planar pure rolling (``v = 0``, ``ω_x = ω_z = 0``).

    Args:
        K1, K2: (2, 2) curvature forms [1/m]; M1, M2: (2, 2) metrics.
        psi: contact angle [rad] (constant: ``ψ̇ = 0``).
        omega_y: relative rolling rate of body 1 w.r.t. body 2 about ``y`` of ``C_l1``
            [rad/s].

    Returns:
        ``(u1_dot, u2_dot)``, each (2,).
    """
    zero = np.zeros((1, 2))
    u1d, u2d, _ = montana_rates(
        K1, zero, M1, K2, zero, M2, psi, np.zeros(3), np.array([0.0, float(omega_y), 0.0])
    )
    return u1d, u2d


def planar_rolling_arc_length(
    theta: float | np.ndarray, k1: float, k2: float
) -> float | np.ndarray:
    """Eq. 2.4 integrated: arc length rolled on each body for a relative rotation ``θ``.

    Args:
        theta: relative rotation of the bodies about the rolling axis [rad].
        k1, k2: curvatures of the two bodies in the rolling plane, convex positive
            (a fingertip of radius ``r``: ``1/r``; a flat object: 0) [1/m].

    Returns:
        ``s = θ / (k1 + k2)`` [m] (``r θ`` for a fingertip on a flat object).

    Raises:
        SingularConfiguration: ``k1 + k2 <= 0`` (conforming or interpenetrating profiles:
            the contact point is not determined by the rotation).
    """
    total = float(k1) + float(k2)
    if not math.isfinite(total) or total <= 0.0:
        raise SingularConfiguration(
            f"k1 + k2 = {total!r} must be > 0 for rolling: the bodies conform or interpenetrate",
            value=total,
        )
    return np.asarray(theta, dtype=float) / total if np.ndim(theta) else float(theta) / total


__all__ = [
    "TABLE_2_1",
    "constraint_violations",
    "planar_rolling_arc_length",
    "planar_rolling_rates",
]
