"""Per-phase diagnosis of an executed gait: what the planner sensed against the truth.

:func:`phase_rows` turns an :class:`~.result.ExplorationResult` into one
:class:`PhaseRow` per phase: the true and the sensed rotation, the object-centre estimate's
error at the phase start, and how hard each contact leans on its friction cone (the median
and largest ``|tangential| / normal`` of the simulator's contact forces). On the 12 x 10 cm
ellipse these rows located the stall (``scenarios/ellipse_gait.yaml``): the right holder
of phase 3 at ``|T| / N`` 0.95-0.97 while the object rolled back 5-9 deg, the centre
estimate 5-8 mm off.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: contacts carrying less than this are ignored in the cone ratios [N]
MIN_NORMAL = 0.05
#: the simulator's contact pairs of the hand with the object, by finger
PAIRS = {"left": "hand.left|object", "right": "hand.right|object", "palm": "hand.palm|object"}


@dataclass(frozen=True)
class PhaseRow:
    """One phase, measured.

    Attributes:
        index, kind, skip, event: the phase (its :class:`~.result.PhaseRecord`).
        start, end: world time [s].
        rotation: true rotation of the object during the phase [rad].
        sensed_rotation: the executor's rotation estimate over the phase [rad] (its value at
            the next phase's first control step minus this one's; NaN for the last phase).
        planned_rotation: the phase-1 plan's rotation [rad] (0 for phases 2/3).
        centre_error: distance of the sensed object centre from the true object origin at
            the phase's first control step [m] (the origin is the centre of symmetric
            objects; on a circle, the estimate's error).
        cone: ``{finger: (median, max) |T| / N}`` over the phase's steps where that
            contact carries >= :data:`MIN_NORMAL` (fingers ``left``, ``right``, ``palm``;
            absent when it carried nothing).
        normal: ``{finger: median normal force [N]}`` over the same steps.
    """

    index: int
    kind: int
    skip: bool
    event: str
    start: float
    end: float
    rotation: float
    sensed_rotation: float
    planned_rotation: float
    centre_error: float
    cone: dict
    normal: dict

    def line(self) -> str:
        """A one-line summary (degrees, mm, N)."""
        cones = " ".join(
            f"{k} N={self.normal[k]:.2f} T/N={v[0]:.2f}/{v[1]:.2f}" for k, v in self.cone.items()
        )
        return (
            f"{self.index:3d} k{self.kind}{'s' if self.skip else ' '} "
            f"t={self.start:6.2f}-{self.end:6.2f} true={math.degrees(self.rotation):7.2f} "
            f"sensed={math.degrees(self.sensed_rotation):7.2f} "
            f"plan={math.degrees(self.planned_rotation):6.1f} "
            f"centre_err={1e3 * self.centre_error:5.1f}mm {cones} [{self.event}]"
        )


def _first_rows(trace_t: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """Index of each phase's first control step (the first trace time >= its start)."""
    return np.minimum(np.searchsorted(trace_t, starts - 1e-9), len(trace_t) - 1)


def _cones(log, t0: float, t1: float) -> tuple[dict, dict]:
    """Median/max ``|T| / N`` and median N of each finger's contact in ``[t0, t1)`` [s]."""
    rows = (log.t >= t0) & (log.t < t1)
    cone, normal = {}, {}
    for finger, name in PAIRS.items():
        if name not in log.pairs:
            continue
        mask = (log.contact_pair == log.pairs.index(name)) & rows[:, None]
        fn = log.normal_force[mask]
        ft = np.abs(np.asarray(log.tangential_force)[mask])
        on = fn >= MIN_NORMAL
        if not on.any():
            continue
        ratio = ft[on] / fn[on]
        cone[finger] = (float(np.median(ratio)), float(np.max(ratio)))
        normal[finger] = float(np.median(fn[on]))
    return cone, normal


def phase_rows(result) -> list[PhaseRow]:
    """The :class:`PhaseRow` of every phase of ``result`` (an ``ExplorationResult`` with
    its log and controller trace)."""
    tr, log = result.trace, result.log
    phases = result.phases
    if not phases or len(tr["t"]) == 0:
        return []
    first = _first_rows(np.asarray(tr["t"]), np.array([p.start for p in phases]))
    theta = np.asarray(tr["theta"])
    pose = log.poses["object"]
    out = []
    for i, p in enumerate(phases):
        k = int(first[i])
        sensed = float(theta[first[i + 1]] - theta[k]) if i + 1 < len(phases) else math.nan
        tk = float(tr["t"][k])
        true_c = (np.interp(tk, log.t, pose[:, 0]), np.interp(tk, log.t, pose[:, 1]))
        err = math.hypot(float(tr["cx"][k]) - true_c[0], float(tr["cy"][k]) - true_c[1])
        cone, normal = _cones(log, p.start, p.end)
        out.append(PhaseRow(
            index=i, kind=p.phase, skip=p.skip, event=p.event, start=p.start, end=p.end,
            rotation=p.rotation, sensed_rotation=sensed, planned_rotation=p.planned_rotation,
            centre_error=err, cone=cone, normal=normal,
        ))  # fmt: skip
    return out


__all__ = ["MIN_NORMAL", "PAIRS", "PhaseRow", "phase_rows"]
