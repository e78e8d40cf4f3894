"""The explorer as a controller callable: hybrid law + recorder + a motion program.

:class:`ExplorerController` is what :meth:`planner.sim.SpatialWorld.run` calls at 1 kHz. Each
call it reads the previous step's estimates (contact point, filtered normal, fingertip centre
- all from sensor readings, mapped into the plate frame), advances the motion *program* (a
generator that yields the desired velocity in the plate frame, see
:mod:`planner.exploration.surface.motions`), commands it to the hybrid law of §4.3 and records
the step into preallocated arrays. ``stop`` ends the run when the program is finished.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.control.hybrid_law import HybridController, HybridSettings
from planner.errors import HapexError
from planner.sim import SimEvent

__all__ = ["PHASES", "Estimate", "ExplorerController", "Recorder"]

#: phase codes of the recorded samples
PHASES = ("approach", "search", "move", "across", "along", "trace", "reapproach", "idle")
PHASE = {name: i for i, name in enumerate(PHASES)}


@dataclass
class Estimate:
    """The explorer's view of the current step (plate frame, from sensor readings).

    Attributes:
        t: time [s]; k: step index.
        centre: (3,) fingertip centre [m]; contact: (3,) contact point (eq. 4.7) [m].
        normal: (3,) filtered outward surface normal [-]; in_contact: OWTS contact flag.
    """

    t: float
    k: int
    centre: np.ndarray
    contact: np.ndarray
    normal: np.ndarray
    in_contact: bool

    @property
    def uv(self) -> np.ndarray:
        """(2,) fingertip centre in the plate plane [m]."""
        return self.centre[:2]

    @property
    def tilt(self) -> float:
        """Sine of the angle between the contact normal and the plate normal [-]."""
        return float(np.hypot(self.normal[0], self.normal[1]))


class Recorder:
    """Preallocated per-step arrays of the exploration (plate frame)."""

    def __init__(self, capacity: int) -> None:
        self.n = 0
        self.t = np.zeros(capacity)
        self.centre = np.zeros((capacity, 3))
        self.contact = np.zeros((capacity, 3))
        self.normal = np.zeros((capacity, 3))
        self.in_contact = np.zeros(capacity, bool)
        self.phase = np.zeros(capacity, np.int8)
        self.feature = np.full(capacity, -1, np.int16)
        self.normal_force = np.zeros(capacity)
        self.decision = np.full(capacity, np.nan)
        self.saturated = np.zeros(capacity, bool)

    def add(self, est: Estimate, phase: int, feature: int, fn: float, sat: bool) -> None:
        k = self.n
        if k >= len(self.t):
            return
        self.t[k] = est.t
        self.centre[k] = est.centre
        self.contact[k] = est.contact
        self.normal[k] = est.normal
        self.in_contact[k] = est.in_contact
        self.phase[k] = phase
        self.feature[k] = feature
        self.normal_force[k] = fn
        self.saturated[k] = sat
        self.n = k + 1


class ExplorerController:
    """Hybrid force/velocity control driven by a motion program (see the module doc).

    Args:
        finger: the :class:`robots.three_gm.ThreeGM`.
        settings: :class:`~planner.control.hybrid_law.HybridSettings`.
        pose: 4x4 ``T_WS`` of the plate (plate frame -> WCS).
        capacity: number of steps to preallocate.
    """

    def __init__(self, finger, settings: HybridSettings, pose: np.ndarray, capacity: int) -> None:
        self.ctl = HybridController(finger, settings)
        self.R = np.asarray(pose, float)[:3, :3].copy()
        self.o = np.asarray(pose, float)[:3, 3].copy()
        self.rec = Recorder(capacity)
        self.events: list[SimEvent] = []
        self.phase = PHASE["approach"]
        self.feature = -1
        self.est = Estimate(0.0, 0, np.zeros(3), np.zeros(3), np.array([0, 0, 1.0]), False)
        self.program = None
        self.finished: str | None = None
        self.failed: str | None = None
        self._v = np.zeros(3)
        self._sat = False

    def event(self, etype: str, message: str, **data) -> None:
        """Record an explorer event of type ``etype`` at the current time."""
        self.events.append(SimEvent(self.est.t, etype, message, data))

    def _update(self, t: float) -> None:
        out = self.ctl.out
        Rt = self.R.T
        e = self.est
        e.t, e.k = t, e.k + 1
        e.centre = Rt @ (out[6:9] - self.o)
        e.contact = Rt @ (out[3:6] - self.o)
        e.normal = -(Rt @ self.ctl.state[:3])
        e.in_contact = bool(out[12])

    def __call__(self, t: float, obs) -> np.ndarray:
        v = np.zeros(2)
        if self.finished is None and self.program is not None:
            try:
                v = next(self.program)
            except StopIteration:
                self.finished = "exploration complete"
            except HapexError as exc:  # a task failure (no contact, ...): stop, status failed
                self.failed = f"{type(exc).__name__}: {exc}"
                self.finished = self.failed
                self.event("failed", self.failed)
        self._v[:2] = v
        np.dot(self.R, self._v, out=self.ctl.target)  # desired velocity in the WCS
        tau = self.ctl(t, obs)
        if self.ctl.saturated and not self._sat:
            self.event("torque_saturated", "hybrid law limited by the motor torques")
        self._sat = self.ctl.saturated
        self._update(t)
        self.rec.add(self.est, self.phase, self.feature, float(self.ctl.out[18]), self._sat)
        return tau

    def stop(self, t: float, world) -> str | None:
        """The run loop's stop callback: the program's end."""
        return self.finished
