"""Contact models of Fig. 2.5 and their friction constraints (thesis §2.2.2, eqs. 2.1-2.2).

Three contact types (:class:`ContactType`): a frictionless point (force along the inward
normal only), a point with Coulomb friction and a soft finger, which adds a moment about the
contact normal. :func:`wrench_basis` gives the wrenches each type transmits; the margins below
say how far a force is from sliding. The cones themselves are in :mod:`planner.contact.cones`.

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

from enum import Enum

import numpy as np

from planner import checks
from planner.errors import InvalidParameter

__all__ = ["ContactType", "point_contact_margin", "soft_finger_margin", "wrench_basis"]


class ContactType(str, Enum):
    """Contact models of Fig. 2.5."""

    FRICTIONLESS = "frictionless"
    POINT_WITH_FRICTION = "point_with_friction"
    SOFT_FINGER = "soft_finger"


def wrench_basis(contact_type: ContactType | str, normal) -> np.ndarray:
    """The wrenches a spatial contact transmits, about the contact point (Fig. 2.5).

    Args:
        contact_type: a :class:`ContactType` (or its value).
        normal: (3,) inward contact normal (normalized here).

    Returns:
        (6, m) basis ``B``: the contact wrench ``(f, tau)`` is ``B c`` for the contact's
        force coordinates ``c`` with ``m = 1`` (frictionless: ``c = f_n``), ``3`` (point with
        friction: ``c = f``) or ``4`` (soft finger: ``c = (f, m_n)``) [N, N m].
    """
    kind = ContactType(
        checks.choice(
            "contact_type", contact_type, [t.value for t in ContactType] + list(ContactType)
        )
    )
    n = checks.vector("normal", normal, 3)
    norm = float(np.linalg.norm(n))
    if norm < 1e-12:
        raise InvalidParameter(f"normal: expected a non-zero direction, got {n.tolist()}")
    n = n / norm
    if kind is ContactType.FRICTIONLESS:
        return np.concatenate([n, np.zeros(3)])[:, None]
    B = np.zeros((6, 3 if kind is ContactType.POINT_WITH_FRICTION else 4))
    B[:3, :3] = np.eye(3)
    if kind is ContactType.SOFT_FINGER:
        B[3:, 3] = n
    return B


def point_contact_margin(f_t, f_n, mu: float) -> np.ndarray:
    """Margin of the point-contact friction cone, eq. 2.1: ``μ f_n - |f_t|``.

    Args:
        f_t: (..., 2) tangential force ``(f_tx, f_ty)`` [N].
        f_n: (...) normal force, pushing positive [N].
        mu: friction coefficient (``c1 = μ^2``).

    Returns:
        (...) margin [N]; ``>= 0`` means no sliding.
    """
    mu = checks.nonnegative("mu", mu)
    ft = np.asarray(f_t, dtype=float)
    if ft.shape[-1:] != (2,):
        raise InvalidParameter(f"f_t: expected shape (..., 2) [N], got shape {ft.shape}")
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
    mu = checks.nonnegative("mu", mu)
    rho = checks.positive("torsion_length", torsion_length, "m")
    ft = np.asarray(f_t, dtype=float)
    if ft.shape[-1:] != (2,):
        raise InvalidParameter(f"f_t: expected shape (..., 2) [N], got shape {ft.shape}")
    g = np.sqrt(np.sum(ft**2, axis=-1) + (np.asarray(m_z, dtype=float) / rho) ** 2)
    return mu * np.asarray(f_n, dtype=float) - g
