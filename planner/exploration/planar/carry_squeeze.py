"""The phase-1 squeeze that carries the object off the palm (§2.2.2: in phase 1 "palm contact
is optional"; the rolling NLP plans the object free of it).

The phase-1 NLP (:class:`planner.trajectory.RollingNLP`) moves the object's centre freely
(within its travel) while it rotates: it brings the object back over the hand's middle. That
plan is only honest if the fingers carry the object's weight. They can only do so within
their friction cones, and how much they can carry grows with the squeeze: with both contacts
above the centre (the left pad at 150 deg, the right tip at 20 deg on a 3 cm circle) the
commanded 1 N squeeze could not hold the 0.49 N weight inside the controller's cones
(``mu (1 - friction_margin)`` = 0.8). The palm kept 0.14-0.7 N, the object rolled along it
12 mm to the right per 23 deg (``R theta``) where the plan moved it 10 mm left, and from
5.4 s on every phase 1 ended at the right base joint's stop after 6-8 of the 27.5 planned
degrees ("no progress" at 54 deg).

:func:`carrying_squeeze` is the smallest internal force (the controller's measure: the
smaller of the two fingers' forces along the line through the contacts) at which two
contacts on a circle hold a vertical load inside their cones without a moment on the
object: a small linear program. For contacts placed symmetrically at ``alpha`` above the
horizontal it has the closed form ``W / 2 cot(atan(mu) - alpha)`` (:func:`symmetric_squeeze`;
``W / (2 mu)`` for horizontal contacts, the classic two-finger hold).
:func:`phase1_squeeze` turns it into the phase-1 command; the round planner uses it in the
phase 1 after one that rolled the object along the palm into a workspace limit
(:func:`.phase_planning.carry_squeeze`).
"""

from __future__ import annotations

import math

import numpy as np

from planner import checks


def _frame(beta: float) -> tuple[np.ndarray, np.ndarray]:
    """Inward normal and counter-clockwise tangent of a contact at world polar angle
    ``beta`` [rad] on a circle."""
    c, s = math.cos(beta), math.sin(beta)
    return np.array([-c, -s]), np.array([-s, c])


def carrying_squeeze(beta_left: float, beta_right: float, mu: float, load: float) -> float:
    """Smallest internal force [N] at which a two-finger grasp of a circle carries ``load``.

    Args:
        beta_left, beta_right: world polar angles of the left and right contacts about the
            object's centre [rad].
        mu: friction coefficient of the cones the controller uses [-] (> 0).
        load: upward force the fingers must apply on the object (its weight plus any
            lift) [N] (>= 0).

    Returns:
        the smallest ``min(f_L . u, -f_R . u)`` [N] (``f_i`` the forces the fingers apply on
        the object, ``u`` the unit vector from the left contact to the right one) over the
        force pairs with ``f_L + f_R = (0, load)``, no moment about the centre (their
        tangential components cancel: both normals pass through it) and each force in its
        cone ``|t . f| <= mu n . f``; ``inf`` when no pair does (the contact line outside a
        cone, or the load not carried by any squeeze).
    """
    checks.positive("mu", mu)
    checks.nonnegative("load", load, "N")
    from scipy.optimize import linprog

    nL, tL = _frame(beta_left)
    nR, tR = _frame(beta_right)
    pL = -nL  # contact points on the unit circle (the radius drops out)
    pR = -nR
    d = pR - pL
    if float(d @ d) < 1e-18:
        return math.inf
    u = d / math.sqrt(float(d @ d))
    # variables: f_L (2), f_R (2); minimize f_L . u
    zero = np.zeros(2)
    a_eq = np.array([[1.0, 0.0, 1.0, 0.0], [0.0, 1.0, 0.0, 1.0], [*tL, *tR]])
    b_eq = np.array([0.0, load, 0.0])
    a_ub = np.array([
        [*(tL - mu * nL), *zero],
        [*(-tL - mu * nL), *zero],
        [*zero, *(tR - mu * nR)],
        [*zero, *(-tR - mu * nR)],
    ])  # fmt: skip
    res = linprog(np.r_[u, zero], A_ub=a_ub, b_ub=np.zeros(4), A_eq=a_eq, b_eq=b_eq,
                  bounds=[(None, None)] * 4, method="highs")  # fmt: skip
    if res.status != 0:
        return math.inf
    a = float(res.fun)
    # f_L . u - (-f_R . u) = (f_L + f_R) . u = load u_y: the other finger's share
    return max(min(a, a - load * float(u[1])), 0.0)


def symmetric_squeeze(alpha: float, mu: float, load: float) -> float:
    """Closed form of :func:`carrying_squeeze` for contacts at ``pi - alpha`` and ``alpha``
    (``alpha`` [rad] above the horizontal on both sides): each finger carries ``load / 2``
    [N]; its cone ``|T| <= mu N`` with ``N = F cos(alpha) - V sin(alpha)``, ``T = F
    sin(alpha) + V cos(alpha)`` (``F`` the squeeze, ``V = load / 2``) gives ``F >= V
    cot(atan(mu) - alpha)``; ``inf`` for ``alpha >= atan(mu)``."""
    phi = math.atan(mu)
    if alpha >= phi:
        return math.inf
    return max(0.5 * load / math.tan(phi - alpha), 0.0)


def phase1_squeeze(beta, settings, lift: float) -> float:
    """The phase-1 internal force [N]: the commanded ``settings.internal_force``, raised
    where the planned grasp (``beta`` (N+1, 2) world contact angles of the plan's knots
    [rad]) needs more to carry the object's weight (``settings.object_mass`` times
    ``settings.gravity``) and its lift (``lift`` [m] against the object impedance's
    vertical stiffness) inside the controller's cones (``mu (1 - friction_margin)``), times
    ``1 + settings.carry_margin``; capped at ``settings.max_squeeze``."""
    s = settings
    mu = s.planning_mu
    load = s.object_mass * s.gravity + s.object_kp[1] * lift
    need = max(carrying_squeeze(float(bl), float(br), mu, load) for bl, br in np.asarray(beta))
    want = (1.0 + s.carry_margin) * need
    return float(min(max(s.internal_force, want), max(s.max_squeeze, s.internal_force)))


__all__ = ["carrying_squeeze", "phase1_squeeze", "symmetric_squeeze"]
