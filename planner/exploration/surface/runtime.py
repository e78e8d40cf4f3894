"""The explorer as a controller callable: hybrid law + recorder + a motion program.

:class:`ExplorerController` is what :meth:`planner.sim.SpatialWorld.run` calls at 1 kHz. Each
call it reads the previous step's estimates (contact point, filtered normal, fingertip centre
- all from sensor readings, mapped into the plate frame), advances the motion *program* (a
generator that yields the desired velocity in the plate frame, see
:mod:`planner.exploration.surface.motions`), commands it to the hybrid law of §4.3 and records
the step into preallocated arrays. ``stop`` ends the run when the program is finished.

The per-step work after the program - averaging the 5 kHz OWTS samples, the hybrid law, the
plate-frame estimates and the recorder row - is one compiled call (:func:`explorer_step`);
``kernel=False`` runs the same step through :class:`~planner.control.hybrid_law.
HybridController` and numpy (the reference the tests compare it with).

Lost contact: every phase but ``approach`` and ``idle`` slides on the plate under the normal
force. When the OWTS reports no contact for longer than :data:`CONTACT_LOST_TIME` in such a
phase, the finger has left the plate and not come back: the program is stopped and the run
ends "failed" (a :class:`~planner.errors.ContactLost` reason and a ``failed`` event). Brief
losses - the ball stepping off a wire on a 45 deg plate loses contact for about 0.12 s - go on.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.control import hybrid_kernel as hk
from planner.control.hybrid_law import (
    HybridController,
    HybridSettings,
    owts_voltages,
    tip_force,
)
from planner.errors import ContactLost, HapexError
from planner.jit import njit
from planner.sim import SimEvent

__all__ = ["PHASES", "Estimate", "ExplorerController", "Recorder", "explorer_step"]

#: phase codes of the recorded samples
PHASES = ("approach", "search", "move", "across", "along", "trace", "reapproach", "idle")
PHASE = {name: i for i, name in enumerate(PHASES)}
OWTS_ON = 1e-3  # [V] total light of a 5 kHz sample counted as in contact (owts_voltages)
#: longest time without contact [s] in a phase that slides on the plate before the run fails
CONTACT_LOST_TIME = 0.5
_FREE = (PHASE["approach"], PHASE["idle"])  # phases that do not expect contact


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


@njit(cache=True)
def owts_mean(samples, threshold, volts):
    """Mean (4,) of the rows of ``samples`` (k, 4) whose total exceeds ``threshold`` [V]
    (zeros when none): :func:`~planner.control.hybrid_law.owts_voltages` compiled."""
    cnt = 0
    a0 = a1 = a2 = a3 = 0.0
    for i in range(samples.shape[0]):
        s = samples[i, 0] + samples[i, 1] + samples[i, 2] + samples[i, 3]
        if s > threshold:
            if cnt == 0:
                a0, a1, a2, a3 = samples[i, 0], samples[i, 1], samples[i, 2], samples[i, 3]
            else:
                a0 += samples[i, 0]
                a1 += samples[i, 1]
                a2 += samples[i, 2]
                a3 += samples[i, 3]
            cnt += 1
    if cnt == 0:
        volts[:] = 0.0
    else:
        volts[0], volts[1], volts[2], volts[3] = a0 / cnt, a1 / cnt, a2 / cnt, a3 / cnt


@njit(cache=True)
def _plate(R, o, x, i0, dst, k):
    """``dst[k] = Rᵀ (x[i0:i0+3] - o)``: a WCS point into the plate frame."""
    d0, d1, d2 = x[i0] - o[0], x[i0 + 1] - o[1], x[i0 + 2] - o[2]
    for i in range(3):
        dst[k, i] = R[0, i] * d0 + R[1, i] * d1 + R[2, i] * d2


@njit(cache=True)
def explorer_step(q, qd, samples, avg, volts, vel, R, o, law, rec, k, t, phase, feature):
    """One explorer step after the program: OWTS mean, hybrid law, estimates, recorder row.

    Args:
        q, qd: (3,) encoder angles [rad] and rates [rad/s].
        samples: (m, 4) OWTS voltages of the 5 kHz samples since the last step [V].
        avg: average ``samples`` into ``volts`` (False: ``volts`` holds the voltages).
        volts: (4,) voltages the law reads [V].
        vel: (3,) desired velocity in the plate frame [m/s] (z ignored).
        R, o: plate rotation (3, 3) and origin (3,) in the WCS.
        law: ``(state, target, par, out, force, fstate, fpar, closed)``: the arrays of
            :func:`~planner.control.hybrid_kernel.hybrid_step_closed_loop` and whether to
            close the normal-force loop (False: :func:`~planner.control.hybrid_kernel.
            hybrid_step`, the open-loop law).
        rec: tuple of the recorder's arrays (t, centre, contact, normal, in_contact, phase,
            feature, normal_force, saturated); row ``k`` is written.
        t: time [s]; phase, feature: codes of the row.
    """
    if avg:
        owts_mean(samples, OWTS_ON, volts)
    state, target, par, out, force, fstate, fpar, closed = law
    for i in range(3):
        target[i] = R[i, 0] * vel[0] + R[i, 1] * vel[1]
    if closed:
        hk.hybrid_step_closed_loop(q, qd, volts, force, state, fstate, target, par, fpar, out)
    else:
        hk.hybrid_step(q, qd, volts, state, target, par, out)
    r_t, r_centre, r_contact, r_normal, r_on, r_phase, r_feat, r_fn, r_sat = rec
    r_t[k] = t
    _plate(R, o, out, 6, r_centre, k)
    _plate(R, o, out, 3, r_contact, k)
    n0, n1, n2 = state[0], state[1], state[2]
    for i in range(3):
        r_normal[k, i] = -(R[0, i] * n0 + R[1, i] * n1 + R[2, i] * n2)
    r_on[k] = out[12] != 0.0
    r_phase[k] = phase
    r_feat[k] = feature
    r_fn[k] = out[18]
    r_sat[k] = out[13] != 0.0


class ExplorerController:
    """Hybrid force/velocity control driven by a motion program (see the module doc).

    Args:
        finger: the :class:`robots.three_gm.ThreeGM`.
        settings: :class:`~planner.control.hybrid_law.HybridSettings`.
        pose: 4x4 ``T_WS`` of the plate (plate frame -> WCS).
        capacity: number of steps to preallocate.
        kernel: run the step compiled (:func:`explorer_step`); False: through
            :class:`~planner.control.hybrid_law.HybridController` and numpy (same numbers).
    """

    def __init__(
        self,
        finger,
        settings: HybridSettings,
        pose: np.ndarray,
        capacity: int,
        kernel: bool = True,
    ) -> None:
        self.ctl = HybridController(finger, settings)
        self.R = np.ascontiguousarray(np.asarray(pose, float)[:3, :3])
        self.o = np.asarray(pose, float)[:3, 3].copy()
        self.rec = Recorder(capacity)
        self.events: list[SimEvent] = []
        self.phase = PHASE["approach"]
        self.feature = -1
        self.est = Estimate(0.0, 0, np.zeros(3), np.zeros(3), np.array([0, 0, 1.0]), False)
        self.program = None
        self.finished: str | None = None
        self.failed: str | None = None
        self._lost: tuple[float, np.ndarray] | None = None  # (time [s], (2,) uv [m]) off since
        self.kernel = bool(kernel)
        self._v = np.zeros(3)
        self._sat = False
        r = self.rec
        self._rows = (
            r.t, r.centre, r.contact, r.normal, r.in_contact, r.phase, r.feature,
            r.normal_force, r.saturated,
        )  # fmt: skip
        self._none = np.zeros((0, 4))
        c = self.ctl
        self._closed = c.mode == "closed_loop"
        self._law = (c.state, c.target, c.par, c.out, c._force, c.fstate, c.fpar, self._closed)

    def event(self, etype: str, message: str, **data) -> None:
        """Record an explorer event of type ``etype`` at the current time."""
        self.events.append(SimEvent(self.est.t, etype, message, data))

    def warm_up(self) -> None:
        """Load the compiled step (numba cache) before the run, on scratch copies."""
        c = self.ctl
        scratch = Recorder(1)
        rows = (
            scratch.t, scratch.centre, scratch.contact, scratch.normal, scratch.in_contact,
            scratch.phase, scratch.feature, scratch.normal_force, scratch.saturated,
        )  # fmt: skip
        th = c.finger.center_theta.astype(float)
        for closed in (False, True):
            law = (
                c.state.copy(), np.zeros(3), c.par.copy(), np.zeros(hk.NOUT), np.zeros(3),
                np.zeros(hk.NFSTATE), c.fpar, closed,
            )  # fmt: skip
            explorer_step(
                th, np.zeros(3), self._none, True, np.zeros(4), np.zeros(3), self.R, self.o,
                law, rows, 0, 0.0, 0, -1,
            )  # fmt: skip

    def _advance(self) -> None:
        """Next velocity of the program into ``self._v`` (zero once it has finished)."""
        if self.finished is not None or self.program is None:
            self._v[:2] = 0.0
            return
        try:
            self._watch_contact()
            self._v[:2] = next(self.program)
        except StopIteration:
            self._v[:2] = 0.0
            self.finished = "exploration complete"
        except HapexError as exc:  # a task failure (no contact, ...): stop, status failed
            self._v[:2] = 0.0
            self.failed = f"{type(exc).__name__}: {exc}"
            self.finished = self.failed
            self.event("failed", self.failed)

    def _watch_contact(self) -> None:
        """Raise ContactLost when the last :data:`CONTACT_LOST_TIME` [s] of a phase that
        slides on the plate had no contact (see the module doc)."""
        e = self.est
        if e.in_contact or self.phase in _FREE:
            self._lost = None
        elif self._lost is None:
            self._lost = (e.t, e.uv.copy())
        elif e.t - self._lost[0] > CONTACT_LOST_TIME:
            t0, (u, v) = self._lost
            raise ContactLost(
                f"no contact for more than {CONTACT_LOST_TIME:g} s while in phase "
                f"{PHASES[self.phase]}: the fingertip left the plate at t = {t0:.3f} s, "
                f"({u * 1e3:.1f}, {v * 1e3:.1f}) mm, and did not come back"
            )

    def __call__(self, t: float, obs) -> np.ndarray:
        self._advance()
        c, rec = self.ctl, self.rec
        k = rec.n
        if not self.kernel or k >= len(rec.t):
            return self._reference_call(t, obs)
        q, qd = obs.q, obs.qd
        c.anchor(q)
        o = getattr(obs, "owts", None)
        a = getattr(o, "voltages", o)
        avg = isinstance(a, np.ndarray) and a.ndim == 2 and a.dtype == np.float64
        if not avg:
            owts_voltages(obs, c._volts)
        if self._closed:
            tip_force(obs, c._force)
        explorer_step(
            q, qd, a if avg else self._none, avg, c._volts, self._v, self.R, self.o,
            self._law, self._rows, k, t, self.phase, self.feature,
        )  # fmt: skip
        if c.qp is not None and c.qp.apply(c.out, c.state[:3]):
            rec.normal_force[k] = c.out[18]
        rec.n = k + 1
        sat = c.out[13] != 0.0
        if sat:
            c.saturated_steps += 1
            if not self._sat:
                self.event("torque_saturated", "hybrid law limited by the motor torques")
        self._sat = sat
        e = self.est
        e.t, e.k = t, e.k + 1
        e.centre, e.contact, e.normal = rec.centre[k], rec.contact[k], rec.normal[k]
        e.in_contact = bool(rec.in_contact[k])
        return c.out[:3].copy()

    def _reference_call(self, t: float, obs) -> np.ndarray:
        """The same step through :class:`HybridController` and numpy (``kernel=False``)."""
        np.dot(self.R, self._v, out=self.ctl.target)  # desired velocity in the WCS
        tau = self.ctl(t, obs)
        if self.ctl.saturated and not self._sat:
            self.event("torque_saturated", "hybrid law limited by the motor torques")
        self._sat = self.ctl.saturated
        out = self.ctl.out
        Rt = self.R.T
        e = self.est
        e.t, e.k = t, e.k + 1
        e.centre = Rt @ (out[6:9] - self.o)
        e.contact = Rt @ (out[3:6] - self.o)
        e.normal = -(Rt @ self.ctl.state[:3])
        e.in_contact = bool(out[12])
        self.rec.add(self.est, self.phase, self.feature, float(out[18]), self._sat)
        return tau

    def stop(self, t: float, world) -> str | None:
        """The run loop's stop callback: the program's end."""
        return self.finished
