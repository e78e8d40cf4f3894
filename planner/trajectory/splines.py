"""Startup segments (§2.2.3): quintic position splines and force ramps.

"When this startup is a change from force to position control of a finger, a 5th order
position spline is used to command smooth positions, velocities and accelerations. The
commanded internal and external forces on the object are initially computed to be
consistent with the commanded tip forces at the end of the previous phase and gradually
ramped to their desired values."

:class:`QuinticSpline` joins two states ``(x, v, a)`` with a 5th-order polynomial per
coordinate over a duration ``T``; :class:`ForceRamp` is the same with zero end rates (a
smooth step from one force to another, C2 at both ends).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks


@dataclass(frozen=True)
class QuinticSpline:
    """A 5th-order polynomial from ``(x0, v0, a0)`` at t = 0 to ``(x1, v1, a1)`` at ``T``.

    Attributes:
        coefficients: (6, d) polynomial coefficients, lowest order first.
        duration: ``T`` [s].
    """

    coefficients: np.ndarray
    duration: float

    @classmethod
    def between(cls, x0, x1, duration: float, v0=None, v1=None, a0=None, a1=None):
        """The spline joining two states (rates default to zero) over ``duration`` [s]."""
        T = checks.positive("duration", duration, "s")
        x0 = np.atleast_1d(np.asarray(x0, float))
        x1 = np.atleast_1d(np.asarray(x1, float))
        if x0.shape != x1.shape:
            raise checks.InvalidParameter(
                f"x1: expected the shape of x0 {x0.shape}, got {x1.shape}"
            )
        z = np.zeros_like(x0)
        v0, v1, a0, a1 = (z if v is None else np.atleast_1d(np.asarray(v, float))
                          for v in (v0, v1, a0, a1))  # fmt: skip
        c0, c1, c2 = x0, v0, a0 / 2.0
        # solve the 3x3 system for c3, c4, c5 (end position, velocity, acceleration)
        M = np.array([[T**3, T**4, T**5], [3 * T**2, 4 * T**3, 5 * T**4],
                      [6 * T, 12 * T**2, 20 * T**3]])  # fmt: skip
        rhs = np.stack([x1 - (c0 + c1 * T + c2 * T**2), v1 - (c1 + 2 * c2 * T), a1 - 2 * c2])
        c345 = np.linalg.solve(M, rhs)
        return cls(np.vstack([c0, c1, c2, c345]), T)

    def __call__(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position, velocity and acceleration at ``t`` [s] (held constant after ``T``)."""
        t = min(max(float(t), 0.0), self.duration)
        c = self.coefficients
        p = c[0] + t * (c[1] + t * (c[2] + t * (c[3] + t * (c[4] + t * c[5]))))
        v = c[1] + t * (2 * c[2] + t * (3 * c[3] + t * (4 * c[4] + t * 5 * c[5])))
        a = 2 * c[2] + t * (6 * c[3] + t * (12 * c[4] + t * 20 * c[5]))
        if t >= self.duration:
            v, a = v * 0.0 + self._end_rate(1), a * 0.0 + self._end_rate(2)
        return p, v, a

    def scalar(self):
        """A plain-Python ``t -> (x, v, a)`` of a 1-D spline (floats; for control loops,
        where numpy on scalars costs ~10x more), equal to :meth:`__call__`."""
        if self.coefficients.shape[1] != 1:
            raise checks.InvalidParameter("scalar: expected a 1-D spline")
        c0, c1, c2, c3, c4, c5 = (float(x) for x in self.coefficients[:, 0])
        T = self.duration
        v_end, a_end = float(self._end_rate(1)[0]), float(self._end_rate(2)[0])

        def at(t: float) -> tuple[float, float, float]:
            t = min(max(float(t), 0.0), T)
            p = c0 + t * (c1 + t * (c2 + t * (c3 + t * (c4 + t * c5))))
            if t >= T:
                return p, v_end, a_end
            v = c1 + t * (2 * c2 + t * (3 * c3 + t * (4 * c4 + t * 5 * c5)))
            a = 2 * c2 + t * (6 * c3 + t * (12 * c4 + t * 20 * c5))
            return p, v, a

        return at

    def _end_rate(self, order: int) -> np.ndarray:
        T, c = self.duration, self.coefficients
        if order == 1:
            return c[1] + 2 * c[2] * T + 3 * c[3] * T**2 + 4 * c[4] * T**3 + 5 * c[5] * T**4
        return 2 * c[2] + 6 * c[3] * T + 12 * c[4] * T**2 + 20 * c[5] * T**3


@dataclass(frozen=True)
class ForceRamp:
    """A smooth (quintic, C2) ramp of a force from ``start`` to ``end`` over ``duration``.

    Attributes:
        start, end: forces [N] (scalars or arrays of equal shape).
        duration: [s].
    """

    start: object
    end: object
    duration: float

    def __post_init__(self) -> None:
        checks.positive("duration", self.duration, "s")

    def __call__(self, t: float):
        """The ramped force at ``t`` [s] (``start`` before 0, ``end`` after ``duration``)."""
        s = min(max(float(t) / self.duration, 0.0), 1.0)
        w = s**3 * (10.0 - 15.0 * s + 6.0 * s * s)
        if isinstance(self.start, (int, float)) and isinstance(self.end, (int, float)):
            return float(self.start) * (1.0 - w) + float(self.end) * w  # scalar: no numpy
        return np.asarray(self.start) * (1.0 - w) + np.asarray(self.end) * w


__all__ = ["ForceRamp", "QuinticSpline"]
