"""Trajectories of the ch. 2 gait: the phase-1 rolling-contact NLP (eqs. 2.3-2.4), quintic
position splines and force ramps for the startup segments (§2.2.3)."""

from planner.trajectory.rolling_nlp import RollingNLP, RollingPlan
from planner.trajectory.splines import ForceRamp, QuinticSpline

__all__ = ["ForceRamp", "QuinticSpline", "RollingNLP", "RollingPlan"]
