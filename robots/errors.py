"""Errors specific to the robot models (all derive from :class:`planner.errors.HapexError`)."""

from __future__ import annotations

from planner.errors import InfeasibleProblem


class UnreachableTarget(InfeasibleProblem):
    """An inverse-kinematics target lies outside the reachable set within the joint limits.

    Derives from :class:`~planner.errors.InfeasibleProblem` (an IK problem without solution),
    so callers catching either class see it.
    """


__all__ = ["UnreachableTarget"]
