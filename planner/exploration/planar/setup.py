"""The start of an exploration: the map-space prior, the start grasp and the world."""

from __future__ import annotations

import math

import numpy as np

from planner.errors import HapexError, InvalidParameter
from planner.exploration.planar.heuristics import (
    best_margin_ik,
    left_ik,
    start_grasp_candidates,
)
from planner.exploration.planar.objects import rest_height
from planner.exploration.planar.prior_track import world_angle


def gait_prior(nominal, radius: float, hand, mu: float):
    """``planner.grasp.plan_gait`` on the planner's model (default the nominal circle of
    ``radius`` [m]) with the friction ``mu`` [-] the planner assumes (``GaitSettings.mu``).

    Returns:
        ``(gait, error)``: the map-space gait (feasible or not) and "", or None and the
        message of the :class:`~planner.errors.HapexError` ``plan_gait`` raised (the run goes
        on without a prior and its first ``prior`` event says why).
    """
    from planner.geometry import shapes
    from planner.grasp import plan_gait

    model = nominal if nominal is not None else shapes.circle(radius)
    try:
        return plan_gait(model, hand, mu, resolution=72), ""
    except HapexError as exc:
        return None, str(exc)


def _place(hand, profile, origin, beta, q_ref):
    """Joint angles putting both fingertips on the TRUE outline at world polar angles
    ``beta`` about the object origin (the hand closing on the object), or None."""
    pts, nrm = profile.point_at_polar_angle(np.asarray(beta, float))
    p = pts + origin
    r = hand.params.right.tip_radius
    qL = left_ik(hand, p[0], math.atan2(nrm[0, 1], nrm[0, 0]), float(q_ref[:3].sum()))
    if qL is None:
        return None
    apex = math.atan2(nrm[1, 1], nrm[1, 0]) + 0.5 * math.pi  # contact at the tip's apex
    qR = best_margin_ik(hand, "right", p[1] + r * nrm[1], around=apex)
    if qR is None:
        return None
    return np.r_[qL, qR]


def prior_world_grasp(prior) -> tuple[float, float]:
    """World polar angles ``(beta_left, beta_right)`` [rad] of the first phase-1 grasp of a
    map-space gait. ``plan_gait`` gives object-frame contact angles at pose index
    ``pose_start``, where the object has turned by ``-pose_start 2 pi / resolution`` (they
    were used as world angles before, which put the prior's grasp 20 deg off)."""
    ph = prior.phases[0]
    left = world_angle(ph.start["left"], ph.pose_start, prior.resolution) % (2 * math.pi)
    right = world_angle(ph.start["right"], ph.pose_start, prior.resolution)
    return float(left), math.remainder(right, 2 * math.pi)


#: a start grasp whose fingertips penetrate the palm or the object deeper than this is
#: rejected [m] (with wider joint ranges the best-margin grasp can fold the pad into the palm)
START_PENETRATION = 5e-4


def _collides(hand, profile, q, pose, mu, settings) -> bool:
    """Whether the start configuration ``q`` puts a fingertip into the palm or the object
    (anything behind a flat pad counts as inside it: that is where its finger is)."""
    from planner.sim import PlanarWorld

    world = PlanarWorld(dt=settings.dt)
    world.add_hand(hand, q, pad_depth=math.inf)
    world.add_body(profile, pose, settings.object_mass, friction=mu, name="object")
    return any(
        gap < -START_PENETRATION
        for (a, b, gap) in world.penetrations()
        if {a, b} != {"hand.palm", "object"}
    )


def check_fits(profile, mu: float, hand=None, radius: float | None = None, settings=None) -> str:
    """Why the object cannot be grasped at the start ("" when it can): the bad-input test
    of scenario validation (exit 2). ``settings``: the run's ``GaitSettings`` (default
    ``GaitSettings(mu=mu)``; its ``planning_mu`` bounds the start grasp's cones)."""
    from planner.exploration.planar.objects import mean_radius
    from planner.exploration.planar.settings import GaitSettings
    from robots.planar_hand import PlanarHand

    hand = hand or PlanarHand(friction=mu)
    s = settings or GaitSettings(mu=mu)
    R = radius or mean_radius(profile)
    try:
        build_world(profile, hand, mu, R, None, s, 0, dry=True)
    except InvalidParameter as exc:
        return str(exc).removeprefix("profile: ")
    return ""


def build_world(
    profile, hand, mu: float, radius: float, prior, settings, seed: int, dry: bool = False
):
    """The planar world with the object resting on the palm and the fingers on it.

    Args:
        profile: the true object outline (object frame) [m]; hand: the ``PlanarHand``.
        mu: the world's true friction coefficient [-] (the simulated object's).
        radius: the planner's nominal radius [m]; prior: ``plan_gait``'s gait or None.
        settings: ``GaitSettings``: the start grasp is searched within the planner's
            cones, ``settings.planning_mu`` (the planner does not know the true ``mu``).
        seed: sensor-noise seed; dry: only search the start grasp (``world`` is None).

    Returns:
        ``(world, start)`` with ``start = {"beta": (2,), "q": (6,), "rest": (3,)}``.

    Raises:
        InvalidParameter: no start grasp of the object exists (it does not fit the hand).
    """
    from planner.sim import PlanarWorld

    h = rest_height(profile)
    origin = np.array([0.0, h])
    first = None
    if prior is not None and prior.feasible and prior.phases:
        first = prior_world_grasp(prior)
    found = None
    # the planner's friction (settings.mu, reserve kept), not the world's true ``mu``
    mu_plan = settings.planning_mu
    cands = start_grasp_candidates(hand, (0.0, radius), radius, mu_plan, first, settings.nlp_margin)
    for bl, br, q_nom, _ in cands:
        q = _place(hand, profile, origin, (bl, br), q_nom)
        if q is not None and not _collides(hand, profile, q, (0.0, h, 0.0), mu, settings):
            found = (bl, br, q)
            break
    if found is None:
        capped = f" capped at {settings.mu_cap:g}" if settings.mu > settings.mu_cap else ""
        raise InvalidParameter(
            "profile: the object does not fit the hand: no stable two-finger grasp of it "
            "resting on the palm is within the fingers' joint limits (friction cones of "
            f"mu {mu_plan:.3g}: the planner's mu {settings.mu:g}{capped} with its "
            f"{settings.friction_margin:.0%} reserve)"
        )
    bl, br, q = found
    if dry:
        return None, {"beta": (bl, br), "q": q, "rest": np.array([0.0, h, 0.0])}
    world = PlanarWorld(dt=settings.dt, gravity=(0.0, -settings.gravity), seed=seed)
    world.add_hand(hand, q)
    world.add_body(profile, (0.0, h, 0.0), settings.object_mass, friction=mu, name="object")
    return world, {"beta": (bl, br), "q": q, "rest": np.array([0.0, h, 0.0])}


__all__ = ["build_world", "gait_prior", "prior_world_grasp"]
