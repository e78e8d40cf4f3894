"""Argument checks of :func:`planner.exploration.explore_object` (its public boundary).

Every bad argument raises :class:`planner.errors.InvalidParameter` with one message that
names it, before anything is built or simulated. Whether the object fits the hand is
checked later, by :func:`.setup.build_world` (it needs the grasp search).
"""

from __future__ import annotations

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from planner.exploration.planar.settings import GaitSettings
from planner.geometry.profiles import Profile

#: the fingertips the executor runs, (left, right): the thesis' hand (the flat pad with the
#: 8x8 tactile array and the 2.5 cm soft round tip, ``robots.planar_hand.params``), or a
#: round left tip too (no tactile array: sensed like the right one, no pad strokes). The
#: right finger is always round: phase 2 slides it along the object, which a pad's edges
#: would catch.
EXECUTOR_TIPS = (("flat", "round"), ("round", "round"))


def _closed_profile(name: str, value: object, what: str) -> None:
    if getattr(value, "closed", False) is not True:
        hint, got = "", checks.shown(value)
        if _vertex_array(value):
            hint = " (for (N, 2) vertices [m] use planner.geometry.polygon(points))"
        elif isinstance(value, Profile):
            n = len(value.pieces)
            got = f"an open Profile {value.name!r} of {n} piece{'s' * (n != 1)}"
        raise InvalidParameter(
            f"{name}: expected a closed planar Profile ({what}), got {got}{hint}"
        )


def _vertex_array(value: object) -> bool:
    """Whether ``value`` looks like an (N, 2) array of vertices (a likely mistake for a
    Profile)."""
    try:
        shape = np.shape(value)
    except ValueError:  # ragged nested sequences
        return False
    return len(shape) == 2 and shape[1] == 2 and not hasattr(value, "pieces")


def check_tips(left: str, right: str, nominal) -> None:
    """Whether the executor runs a hand whose fingertips are ``left`` and ``right``
    (``"flat"`` / ``"round"``, :data:`EXECUTOR_TIPS`) with the planner's model ``nominal``
    (a closed Profile, or None for a circle of the object's area): a round left tip runs
    with a round model only (the posed-outline planner is written for the flat pad).

    Raises:
        InvalidParameter: naming ``hand`` (tips the executor does not run) or ``nominal``.
    """
    if (left, right) not in EXECUTOR_TIPS:
        raise InvalidParameter(
            f"hand: expected a round right fingertip and a flat or round left one (the "
            f"executor's planners, sensing and controllers are written for them), got a "
            f"{left} left and a {right} right fingertip"
        )
    from planner.exploration.planar.shape_tracking import is_round

    if left == "round" and nominal is not None and not is_round(nominal):
        raise InvalidParameter(
            "nominal: a hand with a round left tip runs with a round nominal model only "
            "(the posed-outline planner is written for the flat pad), got a non-round "
            "profile; pass None for a circle of the object's area"
        )


def check_arguments(
    profile,
    hand,
    mu,
    nominal,
    *,
    seed,
    duration,
    settings,
    max_rotation,
    use_prior,
    on_progress,
) -> tuple[float, int, float | None, float]:
    """Validate the arguments of ``explore_object``.

    Returns:
        ``(mu, seed, duration, max_rotation)`` converted: mu [-] (finite, > 0); seed (an int
        >= 0); duration [s] (at least one simulator step, ``inf`` allowed, or None);
        max_rotation [rad] (> 0, ``inf`` allowed).

    Raises:
        InvalidParameter: the first bad argument, named.
    """
    _closed_profile("profile", profile, "the object outline")
    if nominal is not None:
        _closed_profile("nominal", nominal, "the planner's model, or None")
    mu = checks.positive("mu", mu)
    seed = checks.integer("seed", seed, minimum=0)
    if duration is not None:
        duration = checks.positive("duration", duration, "s", allow_inf=True)
    max_rotation = checks.positive("max_rotation", max_rotation, "rad", allow_inf=True)
    if settings is not None and not isinstance(settings, GaitSettings):
        raise InvalidParameter(f"settings: expected a GaitSettings or None, got {settings!r}")
    dt = (settings or GaitSettings()).dt
    if duration is not None and duration < dt:
        raise InvalidParameter(
            f"duration: expected at least one simulator step ({dt:g} s) or None, got {duration!r}"
        )
    if hand is not None:
        from robots.planar_hand import PlanarHand

        if not isinstance(hand, PlanarHand):
            raise InvalidParameter(f"hand: expected a robots.planar_hand.PlanarHand or None, "
                                   f"got {type(hand).__name__}")  # fmt: skip
        check_tips(hand.params.left.tip, hand.params.right.tip, nominal)
    if not isinstance(use_prior, bool):
        raise InvalidParameter(f"use_prior: expected True or False, got {use_prior!r}")
    if on_progress is not None and not callable(on_progress):
        raise InvalidParameter(f"on_progress: expected a callable(t) or None, got {on_progress!r}")
    return mu, seed, duration, max_rotation


__all__ = ["EXECUTOR_TIPS", "check_arguments", "check_tips"]
