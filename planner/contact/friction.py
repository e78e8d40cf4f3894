"""Friction constraints of thesis §2.2.2: point contact (eq. 2.1), soft finger (eq. 2.2).

Point contact with friction (eq. 2.1): ``f_tx^2 + f_ty^2 <= c1 f_n^2`` with ``c1 = μ^2``
(the friction cone of Fig. 2.6).

Soft finger (eq. 2.2): ``g(f_tx, f_ty, m_z) <= c2 f_n``. The thesis takes the limit surface
``g`` from Kao and Cutkosky; here it is the common **elliptic approximation**

.. math:: g = \\sqrt{f_{tx}^2 + f_{ty}^2 + (m_z / ρ)^2}, \\qquad c_2 = μ,

where ``ρ`` [m] is the torsional friction length: the largest spin moment the contact can
resist is ``μ ρ f_n``. For a circular patch of radius ``a`` under uniform pressure
``ρ = 2a/3``; under Hertzian pressure ``ρ = 3πa/16``. The ellipsoid is exact at its three
axes and slightly conservative (inside the true limit surface) in between.
"""

from __future__ import annotations

import math

import numpy as np

from planner.errors import InvalidParameter


def _coef(name: str, value: float) -> float:
    x = float(value)
    if not math.isfinite(x) or x < 0:
        raise InvalidParameter(f"{name} must be a finite number >= 0, got {value!r}")
    return x


def point_contact_margin(f_t, f_n, mu: float) -> np.ndarray:
    """Margin of the point-contact friction cone, eq. 2.1: ``μ f_n - |f_t|``.

    Args:
        f_t: (..., 2) tangential force ``(f_tx, f_ty)`` [N].
        f_n: (...) normal force, pushing positive [N].
        mu: friction coefficient (``c1 = μ^2``).

    Returns:
        (...) margin [N]; ``>= 0`` means no sliding.
    """
    mu = _coef("mu", mu)
    ft = np.asarray(f_t, dtype=float)
    if ft.shape[-1:] != (2,):
        raise InvalidParameter(f"f_t must have shape (..., 2), got {ft.shape}")
    return mu * np.asarray(f_n, dtype=float) - np.linalg.norm(ft, axis=-1)


def soft_finger_margin(f_t, m_z, f_n, mu: float, torsion_length: float) -> np.ndarray:
    """Margin of the soft-finger limit surface, eq. 2.2 (elliptic approximation).

    Args:
        f_t: (..., 2) tangential force [N]; m_z: (...) moment about the normal [N m].
        f_n: (...) normal force [N].
        mu: friction coefficient (``c2 = μ``).
        torsion_length: ``ρ`` [m] (see the module docstring; ``2a/3`` for a uniform patch).

    Returns:
        (...) ``μ f_n - sqrt(|f_t|^2 + (m_z/ρ)^2)`` [N]; ``>= 0`` means no slip or spin.
    """
    mu = _coef("mu", mu)
    rho = _coef("torsion_length", torsion_length)
    if rho == 0.0:
        raise InvalidParameter(
            "torsion_length must be > 0 [m] (0 is a point contact: use point_contact_margin)"
        )
    ft = np.asarray(f_t, dtype=float)
    if ft.shape[-1:] != (2,):
        raise InvalidParameter(f"f_t must have shape (..., 2), got {ft.shape}")
    g = np.sqrt(np.sum(ft**2, axis=-1) + (np.asarray(m_z, dtype=float) / rho) ** 2)
    return mu * np.asarray(f_n, dtype=float) - g


__all__ = ["point_contact_margin", "soft_finger_margin"]
