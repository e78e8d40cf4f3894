"""Result types of the grasp-gait search (§2.2.1, Fig. 2.3) and their assembly from a loop
of phase-1 entries found by :mod:`planner.grasp.gait`."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from planner.grasp.gait_tables import GaitProblem

PHASE_NAMES = {
    1: "left-right (rotate object)",
    2: "left-palm (right relocates)",
    3: "right-palm (left relocates)",
}


@dataclass(frozen=True)
class GaitPhase:
    """One phase of a gait.

    Attributes:
        phase: 1, 2 or 3 (Fig. 2.3).
        holding: the two contacts holding the object, e.g. ``("left", "palm")``.
        moving: the finger that relocates (phases 2, 3) or None (phase 1).
        pose_start, pose_end: object-rotation indices at start/end (rotation ``-Δ k``
            for a clockwise gait).
        rotation: object rotation during the phase [rad] (negative: clockwise).
        start, end: contact angles ``{"left", "right", "palm"}`` in the object frame at the
            start/end of the phase [rad] (NaN for a free finger).
        min_epsilon: smallest ε of the holding grasp during the phase.
        transition: ``"forward"`` or ``"skip"`` (transition 4) into the next phase.
    """

    phase: int
    holding: tuple[str, str]
    moving: str | None
    pose_start: int
    pose_end: int
    rotation: float
    start: dict[str, float]
    end: dict[str, float]
    min_epsilon: float
    transition: str

    def to_json(self) -> dict:
        """JSON-ready dict (angles in degrees, suffixed ``_deg``)."""

        def deg(d: dict[str, float]) -> dict[str, float | None]:
            return {
                k: (round(float(np.rad2deg(v)), 3) if np.isfinite(v) else None)
                for k, v in d.items()
            }

        return {
            "phase": self.phase,
            "name": PHASE_NAMES[self.phase],
            "holding": list(self.holding),
            "moving": self.moving,
            "pose_start": self.pose_start,
            "pose_end": self.pose_end,
            "rotation_deg": round(float(np.rad2deg(self.rotation)), 3),
            "start_deg": deg(self.start),
            "end_deg": deg(self.end),
            "min_epsilon": round(float(self.min_epsilon), 6),
            "transition": self.transition,
        }


@dataclass(frozen=True)
class Gait:
    """Result of :func:`plan_gait`.

    Attributes:
        feasible: a cyclic gait rotating the object by whole turns was found.
        reason: why not (empty when feasible): the constraint that blocked the search.
        phases: the phases of one period of the cyclic gait, in order.
        rotation_per_cycle: mean object rotation per phase-1 → phase-1 cycle [rad]
            (negative for clockwise).
        turns: full object turns of one period (>= 1 when feasible).
        min_epsilon: smallest ε of any holding grasp along the gait.
        coverage: fraction of the outline (contact-angle cells) touched by the fingers.
        resolution: contact-angle grid size n used by the search.
        path: (M, 3) map-space path ``(pose index, left index, right index)`` (-1: free).
    """

    feasible: bool
    reason: str
    phases: tuple[GaitPhase, ...] = ()
    rotation_per_cycle: float = 0.0
    turns: int = 0
    min_epsilon: float = 0.0
    coverage: float = 0.0
    resolution: int = 0
    path: np.ndarray = field(default_factory=lambda: np.zeros((0, 3), dtype=int))

    @property
    def cycles(self) -> int:
        """Number of phase-1 → phase-1 cycles in one period."""
        return sum(1 for p in self.phases if p.phase == 1)

    def to_json(self) -> dict:
        """JSON-ready summary (``gait.json``)."""
        return {
            "feasible": self.feasible,
            "reason": self.reason,
            "rotation_per_cycle_deg": round(float(np.rad2deg(self.rotation_per_cycle)), 4),
            "turns": self.turns,
            "cycles": self.cycles,
            "min_epsilon": round(float(self.min_epsilon), 6),
            "coverage": round(float(self.coverage), 6),
            "resolution": self.resolution,
            "phases": [p.to_json() for p in self.phases],
        }


def component_run(r: np.ndarray, j: int) -> np.ndarray:
    """Indices of the circular run of True in ``r`` containing ``j`` (sorted by offset)."""
    n = r.size
    if not r[j]:
        return np.zeros(0, dtype=int)
    if r.all():
        return np.arange(n)
    fwd = 0
    while r[(j + fwd + 1) % n]:
        fwd += 1
    back = 0
    while r[(j - back - 1) % n]:
        back += 1
    return np.mod(np.arange(j - back, j + fwd + 1), n)


def _arc_path(j: int, j2: int, n: int, comp: np.ndarray) -> np.ndarray:
    """Cells swept moving from ``j`` to ``j2`` inside the component ``comp``."""
    if comp.size == n:  # whole circle: the shorter way
        d = (j2 - j) % n
        return np.mod(j + (np.arange(d + 1) if d <= n - d else -np.arange(n - d + 1)), n)
    pos = {int(c): t for t, c in enumerate(comp)}
    a, b = sorted((pos[j], pos[j2]))
    return comp[a : b + 1]


def _arc_fraction(cells: set[int], n: int) -> float:
    return len(cells) / n


class _GaitRecord:
    """Phases, swept cells, map-space path and ε of a gait being assembled from its loop."""

    def __init__(self, prob: GaitProblem) -> None:
        self.prob, self.n, self.s = prob, prob.theta.size, prob.sign
        self.phases: list[GaitPhase] = []
        self.covered: set[int] = set()
        self.path: list[tuple[int, int, int]] = []
        self.eps: list[float] = []

    def contacts(self, k: int, left: int, right: int) -> dict[str, float]:
        th = self.prob.theta
        return {
            "left": th[left],
            "right": th[right],
            "palm": float(self.prob.tables.placement.palm_theta[k]),
        }

    def phase1(self, k: int, i: int, j: int, t: int, forward: bool) -> None:
        """Phase 1: left and right roll the object ``t`` steps from pose ``k``."""
        n, s = self.n, self.s
        di = np.mod(i + s * np.arange(t + 1), n)
        dj = np.mod(j + s * np.arange(t + 1), n)
        self.covered.update(di.tolist())
        self.covered.update(dj.tolist())
        self.path += [((k + a) % n, int(di[a]), int(dj[a])) for a in range(t + 1)]
        e1 = float(self.prob.eps_lr[di, dj].min())
        self.eps.append(e1)
        k2 = (k + t) % n
        self.phases.append(
            GaitPhase(
                1,
                ("left", "right"),
                None,
                k,
                k2,
                -s * (2 * np.pi / n) * t,
                self.contacts(k, i, j),
                self.contacts(k2, int(di[-1]), int(dj[-1])),
                e1,
                "forward" if forward else "skip",
            )
        )

    def relocation(self, phase: int, k: int, hold: int, start: int, end: int, fwd: bool) -> None:
        """Phase 2 (left + palm hold at ``hold``, right moves) or 3 (right + palm, left moves)."""
        mover = "right" if phase == 2 else "left"
        comp = component_run(self.prob.reach[mover][k], start)
        self.covered.update(_arc_path(start, end, self.n, comp).tolist())
        e = float((self.prob.eps_lp if phase == 2 else self.prob.eps_rp)[k, hold])
        self.eps.append(e)
        if phase == 2:
            self.path += [(k, hold, -1), (k, hold, end)]
            ends = self.contacts(k, hold, start), self.contacts(k, hold, end)
            holding = ("left", "palm")
        else:
            self.path += [(k, -1, hold), (k, end, hold)]
            ends = self.contacts(k, start, hold), self.contacts(k, end, hold)
            holding = ("right", "palm")
        self.phases.append(
            GaitPhase(phase, holding, mover, k, k, 0.0, *ends, e, "forward" if fwd else "skip")
        )


def build_gait(prob: GaitProblem, loop) -> Gait:
    """The :class:`Gait` of a search loop: records ``(k, i, j, t, route, (i3, j3, _))``.

    Route ``A``: phases 1, 2, 3; ``B``: 1, 2 then 1 (transition 4); ``C``: 1, 3 then 1.
    """
    rec = _GaitRecord(prob)
    n, s = rec.n, rec.s
    for k, i, j, t, route, (i3, j3, _) in loop:
        k2, i2, j2 = (k + t) % n, (i + s * t) % n, (j + s * t) % n
        rec.phase1(k, i, j, t, route in "AB")
        if route in "AB":  # phase 2: left + palm hold, right relocates
            rec.relocation(2, k2, i2, j2, j3, route == "A")
            if route == "A":
                rec.relocation(3, k2, j3, i2, i3, True)
        else:  # route C: phase 3 directly
            rec.relocation(3, k2, j2, i2, i3, True)
    total = sum(r[3] for r in loop)
    return Gait(
        True,
        "",
        tuple(rec.phases),
        rotation_per_cycle=-s * (2 * np.pi / n) * total / len(loop),
        turns=int(total // n),
        min_epsilon=float(min(rec.eps)),
        coverage=_arc_fraction(rec.covered, n),
        resolution=n,
        path=np.array(rec.path, dtype=int),
    )


__all__ = ["PHASE_NAMES", "Gait", "GaitPhase", "build_gait", "component_run"]
