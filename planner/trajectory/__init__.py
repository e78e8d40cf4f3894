"""Trajectories of the ch. 2 gait: the phase-1 rolling-contact NLPs (eqs. 2.3-2.4; on a
circle, and on a polygonal outline with the contacts' modes fixed), quintic
position splines and force ramps for the startup segments (§2.2.3)."""

from planner.trajectory.outline_nlp import OutlineNLP
from planner.trajectory.rolling_nlp import RollingNLP, RollingPlan
from planner.trajectory.splines import ForceRamp, QuinticSpline

__all__ = ["ForceRamp", "OutlineNLP", "QuinticSpline", "RollingNLP", "RollingPlan"]
