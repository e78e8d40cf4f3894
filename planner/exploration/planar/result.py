"""Result types of :func:`planner.exploration.explore_object` (frozen)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from planner.errors import InvalidParameter

#: names of the phase kinds (Fig. 2.3); kind 4 is a phase 1 entered by transition 4 (phase 3
#: skipped: the object is rotated again with two fingers)
PHASE_KINDS = {
    1: "rotate (left-right)",
    2: "right explores",
    3: "left explores",
    4: "rotate again (transition 4)",
}


@dataclass(frozen=True)
class PhaseRecord:
    """One executed phase.

    Attributes:
        kind: 1, 2 or 3 (Fig. 2.3), or 4: a phase 1 entered through transition 4 (phase 3
            was skipped and the object is rotated again with two fingers). :attr:`phase`
            is the phase the fingers run (1 for kind 4).
        skip: entered through transition 4 (``kind == 4``; a record built with ``kind=1,
            skip=True`` gets kind 4).
        start, end: world time at its start and end [s].
        rotation: true object rotation during it [rad] (negative: clockwise).
        planned_rotation: what its plan expected [rad] (phase 1; 0 otherwise).
        event: what ended it ("path finished", "workspace limit", "grasp stability lost",
            "contact lost", "no plan: ...", "object dropped", ...).
        epsilon: smallest sensed epsilon of the grasp during the phase (NaN if not a grasp).
        nlp_time_s: solve time of its NLP [s] (phase 1), else 0.
        nlp_cpu_s, nlp_iterations: its CPU time [s] and IPOPT iterations.
        backstroke: a phase-3 back-stroke (the pad returns onto the far side of a feature
            it slid over in the phase 3 before).
    """

    kind: int
    skip: bool
    start: float
    end: float
    rotation: float
    planned_rotation: float
    event: str
    epsilon: float = float("nan")
    nlp_time_s: float = 0.0
    backstroke: bool = False
    nlp_cpu_s: float = 0.0
    nlp_iterations: int = 0

    def __post_init__(self) -> None:
        if self.kind not in PHASE_KINDS:
            raise InvalidParameter(f"PhaseRecord.kind must be 1, 2, 3 or 4, got {self.kind!r}")
        if self.skip and self.kind == 1:
            object.__setattr__(self, "kind", 4)
        if self.kind == 4:
            object.__setattr__(self, "skip", True)
        elif self.skip:
            raise InvalidParameter(
                f"only a phase 1 is entered by transition 4, got kind {self.kind}"
            )

    @property
    def phase(self) -> int:
        """The phase the fingers run (1, 2 or 3): kind 4 is a phase 1."""
        return 1 if self.kind == 4 else self.kind

    @property
    def start_time(self) -> float:
        """:attr:`start` [s] (the issue's "start time")."""
        return self.start

    @property
    def end_time(self) -> float:
        """:attr:`end` [s] (the issue's "end time")."""
        return self.end

    @property
    def duration(self) -> float:
        """``end - start`` [s]."""
        return self.end - self.start

    @property
    def end_event(self) -> str:
        """:attr:`event`: what ended the phase (the issue's "end event")."""
        return self.event

    def to_json(self) -> dict:
        return {
            "kind": self.kind, "phase": self.phase, "name": PHASE_KINDS[self.kind],
            "skip": self.skip,
            "start_s": round(self.start, 4), "end_s": round(self.end, 4),
            "rotation_deg": round(float(np.rad2deg(self.rotation)), 3),
            "planned_rotation_deg": round(float(np.rad2deg(self.planned_rotation)), 3),
            "event": self.event,
            "epsilon": None if not np.isfinite(self.epsilon) else round(self.epsilon, 5),
            "nlp_time_ms": round(1e3 * self.nlp_time_s, 3), "backstroke": self.backstroke,
            "nlp_cpu_ms": round(1e3 * self.nlp_cpu_s, 3), "nlp_iterations": self.nlp_iterations,
        }  # fmt: skip


@dataclass(frozen=True)
class DetectedFeature:
    """A feature found in the exploring pad's trace.

    Attributes:
        angle: polar angle on the object (object frame) [rad].
        kind: ``"convex"`` or ``"concave"`` (curvature features, ch. 3's detector on the
            pad's trace) or ``"ridge"`` or ``"groove"`` (macro features, :mod:`.macro`).
        truth_angle: angle of the nearest true feature [rad] (NaN if none).
        error: wrapped ``angle - truth_angle`` [rad].
    """

    angle: float
    kind: str
    truth_angle: float = float("nan")
    error: float = float("nan")


@dataclass(frozen=True)
class ExplorationResult:
    """Result of :func:`planner.exploration.explore_object`.

    Attributes:
        status: ``"ok"`` or ``"failed"``; reason: why it ended (always set).
        phases: the executed :class:`PhaseRecord` in order.
        rotation: total true object rotation [rad] (negative: clockwise), from the
            simulator's log: on a failed run it includes what the object turned after
            control was lost (a long ellipse flung in a simulator fault turned 28 deg in
            48 ms), so read it with ``status``.
        coverage: fraction of the outline (1-degree cells of polar angle) touched by an
            exploring fingertip, 0-1 (issue 11's definition): the right finger's contacts
            in phases 2, the left finger's in phases 3
            (``metrics.coverage_mask(log, "object", profile, phases=phases)``).
        contact_coverage: the same fraction touched by any fingertip in any phase (phase-1
            rolling and the holder sense the outline too), 0-1; at least ``coverage``.
        min_epsilon: smallest sensed epsilon of any phase-1 grasp.
        features: :class:`DetectedFeature` found by the exploring pad.
        log: the :class:`planner.sim.SimLog` of the whole run.
        trace: dict of the controller's sensed time series (see ``explore_object``).
        prior: the map-space gait of ``plan_gait`` on the nominal shape (or None).
        timings: wall times ``{"nlp_build_s", "nlp_solve_ms": [...], "control_step_us":
            [...], "wall_s"}`` and ``"control_steps_compiled"`` (how many of the control
            steps ran in the compiled phase loop, where a step's time includes its
            simulator step).
        events: the gait's own events (deviations from the prior, transitions, end).
    """

    status: str
    reason: str
    phases: tuple[PhaseRecord, ...]
    rotation: float
    coverage: float
    contact_coverage: float
    min_epsilon: float
    features: tuple[DetectedFeature, ...]
    log: object
    trace: dict = field(default_factory=dict, repr=False)
    prior: object = field(default=None, repr=False)
    timings: dict = field(default_factory=dict)
    events: tuple[dict, ...] = ()

    @property
    def transitions4(self) -> int:
        """How many phases were entered through transition 4."""
        return sum(1 for p in self.phases if p.skip)


__all__ = ["PHASE_KINDS", "DetectedFeature", "ExplorationResult", "PhaseRecord"]
