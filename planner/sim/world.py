"""The base class both worlds share: logging, the run loop, events (issue 15, item 4).

A world subclass provides the physics and these members:

* ``dt`` [s], ``time`` [s]; ``body_names`` (logged free bodies); ``pose_size`` (3 planar,
  7 spatial), ``velocity_size`` (3 / 6), ``contact_dim`` (2 / 3), ``n_joints``;
* ``torque_limits``: (n_joints,) [N m] or None;
* ``step(tau)``, ``observe(oracle=False)``, ``pose(h)``, ``velocity(h)``, ``contacts()``,
  ``joint_state() -> (q, qd)``;
* ``state_vector()`` (every position and velocity, for the NaN guard) and
  ``velocity_vector()`` (for the runaway guard);
* world events are appended to ``self._events`` during ``step`` (drained by the loop).

It inherits :meth:`run` (:func:`planner.sim.loop.run`), :meth:`record` (one log row),
:meth:`active_pairs` (a subclass may override both with faster versions) and
:meth:`drain_events`.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from planner.errors import InvalidParameter
from planner.sim.events import SimEvent
from planner.sim.log import SimLog
from planner.sim.loop import run as _run

__all__ = ["WorldBase", "check_joint_limits", "joint_torques"]

#: how far a joint angle may lie outside its limits at a world's start [rad] (round-off of
#: an inverse kinematics that stops on a limit; as ``within_limits`` of the robots)
LIMIT_TOLERANCE = 1e-9


def check_joint_limits(name: str, q: np.ndarray, limits: np.ndarray, joints) -> None:
    """Refuse a start with a joint outside its limits.

    Args:
        name: the argument (``q``, ``theta``).
        q: (n,) joint angles [rad].
        limits: (n, 2) lower/upper limits [rad].
        joints: (n,) joint names, for the message.

    Raises:
        InvalidParameter: naming the first joint outside, its angle and its limits.
    """
    lo, hi = limits[:, 0], limits[:, 1]
    out = (q < lo - LIMIT_TOLERANCE) | (q > hi + LIMIT_TOLERANCE)
    if out.any():
        k = int(np.argmax(out))
        raise InvalidParameter(
            f"{name}[{k}]: joint {joints[k]} starts at {q[k]:.6g} rad, outside its limits "
            f"[{lo[k]:.6g}, {hi[k]:.6g}] rad ({int(out.sum())} joint(s) outside)"
        )


def joint_torques(tau: object, n: int, what: str) -> np.ndarray:
    """``tau`` as the (n,) float array of joint torques [N m] a world's ``step`` takes.

    Raises:
        InvalidParameter: ``tau`` is not ``n`` finite numbers (``what`` names them after
            the count, e.g. "motor torques": "expected 3 motor torques [N m]"); a wrong
            length would otherwise be broadcast or read past its end by the compiled step,
            and a NaN would become the state.
    """
    t = tau if isinstance(tau, np.ndarray) and tau.dtype == np.float64 else None
    if t is None:
        try:
            t = np.asarray(tau, float)
        except (TypeError, ValueError):
            raise InvalidParameter(
                f"tau: expected {n} {what} [N m], got {type(tau).__name__}"
            ) from None
    if t.shape != (n,):
        raise InvalidParameter(f"tau: expected {n} {what} [N m], got shape {t.shape}")
    # the sum of Python floats is the cheap test (0.2 us): NaN and inf propagate, and a
    # sum that overflows without them is looked into, so huge finite torques pass
    vals = t.tolist()
    if not math.isfinite(sum(vals)):
        bad = [(i, v) for i, v in enumerate(vals) if not math.isfinite(v)]
        if bad:
            raise InvalidParameter(
                f"tau: joint torques must be finite, got {bad[0][1]} at index {bad[0][0]}"
            )
    return t


class WorldBase:
    """Shared machinery of :class:`PlanarWorld` and :class:`SpatialWorld`."""

    _events: list[SimEvent]

    def drain_events(self) -> list[SimEvent]:
        """The world events since the last call (and forget them)."""
        out, self._events = self._events, []
        return out

    def active_pairs(self) -> set[tuple[str, str]]:
        """Body-name pairs carrying a normal force after the last step (a subclass may
        override it with a version that builds no contact records)."""
        return {c.bodies for c in self.contacts() if c.normal_force > 0.0}

    def record(self, log: SimLog, k: int, tau: np.ndarray) -> None:
        """Write the current state into row ``k`` of ``log``."""
        log.t[k] = self.time
        for name in log.poses:
            log.poses[name][k] = self.pose(name)
            log.velocities[name][k] = self.velocity(name)
        if self.n_joints:
            q, qd = self.joint_state()
            log.q[k], log.qd[k], log.tau[k] = q, qd, tau
        log.write_contacts(k, self.contacts())

    def run(
        self,
        duration: float,
        controller: Callable | None = None,
        control_rate: float = 1000.0,
        progress: bool = False,
        oracle: bool = False,
        stop: Callable | None = None,
        max_contacts: int = 8,
        loop: str = "auto",
    ) -> SimLog:
        """Simulate for ``duration`` [s]; see :func:`planner.sim.loop.run`."""
        return _run(
            self, duration, controller, control_rate, progress, oracle, stop, max_contacts, loop
        )
