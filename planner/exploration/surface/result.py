"""Settings and results of :func:`planner.exploration.surface.explore_surface`."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from planner import checks

__all__ = [
    "MAX_DURATION",
    "MIN_LINE_SPACING",
    "STRATEGIES",
    "ExplorationResult",
    "ExplorationSettings",
    "ExploredFeature",
    "check_duration",
    "check_line_spacing",
]

STRATEGIES = ("raster", "random_walk", "bug2")
#: smallest raster line spacing [r_f]: 0.4 mm for the 8 mm fingertip, under three times the
#: tracer's lateral accuracy (0.15 mm); closer lines cover nothing their neighbours do not,
#: and a spacing of 1e-12 m asked numpy for 3e10 lines (MemoryError)
MIN_LINE_SPACING = 0.05
#: longest simulated run [s]: the explorer's recorder and the simulator's log keep every
#: 1 kHz control step (about 1.1 kB each, allocated up front): 0.66 GB for 600 s
MAX_DURATION = 600.0
#: bytes kept per control step (recorder + log), for the messages
_STEP_BYTES = 1.1e3


def check_line_spacing(spacing: object, tip_radius: float) -> float:
    """``spacing`` [m] as a float >= :data:`MIN_LINE_SPACING` ``tip_radius`` (raise
    InvalidParameter naming ``line_spacing`` otherwise)."""
    from planner.errors import InvalidParameter

    s = checks.positive("line_spacing", spacing, "m")
    least = MIN_LINE_SPACING * tip_radius
    if s < least:
        raise InvalidParameter(
            f"line_spacing: expected >= {MIN_LINE_SPACING:g} r_f = {least * 1e3:.2f} mm "
            f"(closer raster lines cover nothing their neighbours do not), got {s!r} m"
        )
    return s


def check_duration(duration: object) -> float:
    """``duration`` [s] as a float in (0, :data:`MAX_DURATION`] (raise InvalidParameter
    naming ``duration`` otherwise)."""
    from planner.errors import InvalidParameter

    d = checks.positive("duration", duration, "s")
    if d > MAX_DURATION:
        raise InvalidParameter(
            f"duration: expected at most {MAX_DURATION:g} s (the recorder and the log keep "
            f"every 1 kHz control step, about {_STEP_BYTES / 1e3:.1f} kB each, allocated up "
            f"front: {MAX_DURATION * 1e3 * _STEP_BYTES / 1e9:.2f} GB at that bound), got "
            f"{d!r} s"
        )
    return d


@dataclass(frozen=True)
class ExplorationSettings:
    """How the finger explores (validated at construction).

    Attributes:
        strategy: feature search, one of :data:`STRATEGIES` (§4.2, §4.5.1).
        tip_radius: fingertip radius r_f [m].
        normal_force: desired normal force f_des of eq. 4.12 [N].
        speed: sliding speed while searching [m/s].
        trace_speed: sliding speed while tracing a boundary [m/s].
        line_spacing: largest distance between raster lines [m] (default 1.5 r_f; at least
            :data:`MIN_LINE_SPACING` r_f).
        boundary_rise: the traced outline is where the fingertip centre is this much above
            (below, for pits and ravines) the plate level [m] (see
            :mod:`~planner.exploration.surface.tracing`).
        detect_every: online detection period [s] (algorithm 3 over a sliding window).
        window: length of the sliding detection window along the path [m] (default 6 r_f).
        friction: Coulomb coefficient of the fingertip on the plate (graphite: low) [-].
        kp, kv: PD gains parallel to the surface (eq. 4.10) [N/m], [N s/m].
        trace_time: longest time spent tracing one feature [s].
        info_weight, cost_weight: weights of the continue-or-move-on decision parameter of
            §4.5.2 (expected new boundary per second minus the cost of tracing) [-].
        identify: ``"flow_chart"`` (crossings of Fig. 4.7 extended) or ``"raster"``
            (pattern matching of the raster's curvature regions, strategy raster only).
        goal: (2,) goal point of the ``bug2`` strategy in the plate frame [m].
        all_contacts: simulate every point where the tip touches the plate (a groove
            narrower than the tip on both rims; :class:`~planner.sim.spatial.SpatialWorld`).
            False (default): one contact, which can sink into a groove's far rim.
    """

    strategy: str = "raster"
    tip_radius: float = 0.008
    normal_force: float = 0.3
    speed: float = 0.02
    trace_speed: float = 0.012
    line_spacing: float | None = None
    boundary_rise: float = 2.5e-4
    detect_every: float = 0.02
    window: float | None = None
    friction: float = 0.1
    kp: float = 300.0
    kv: float = 16.0
    trace_time: float = 12.0
    info_weight: float = 1.0
    cost_weight: float = 0.2
    identify: str = "flow_chart"
    goal: tuple[float, float] | None = None
    all_contacts: bool = False

    def __post_init__(self) -> None:
        checks.boolean("all_contacts", self.all_contacts)
        checks.choice("strategy", self.strategy, STRATEGIES)
        r = checks.positive("tip_radius", self.tip_radius, "m")
        checks.positive("normal_force", self.normal_force, "N")
        checks.in_range("speed", self.speed, 1e-4, 0.2, "m/s")
        checks.in_range("trace_speed", self.trace_speed, 1e-4, 0.2, "m/s")
        if self.line_spacing is None:
            object.__setattr__(self, "line_spacing", 1.5 * r)
        check_line_spacing(self.line_spacing, r)
        checks.in_range("boundary_rise", self.boundary_rise, 1e-5, 5e-3, "m")
        checks.positive("detect_every", self.detect_every, "s")
        if self.window is None:
            object.__setattr__(self, "window", 6.0 * r)
        checks.positive("window", self.window, "m")
        checks.nonnegative("friction", self.friction)
        checks.positive("kp", self.kp, "N/m")
        checks.nonnegative("kv", self.kv, "N s/m")
        checks.positive("trace_time", self.trace_time, "s")
        checks.nonnegative("info_weight", self.info_weight)
        checks.nonnegative("cost_weight", self.cost_weight)
        checks.choice("identify", self.identify, ("flow_chart", "raster"))
        if self.identify == "raster" and self.strategy != "raster":
            from planner.errors import InvalidParameter

            raise InvalidParameter(
                f"identify: 'raster' pattern-matches the lines of the raster search; needs "
                f"strategy='raster', got strategy={self.strategy!r}"
            )
        if self.goal is not None:
            g = checks.vector("goal", self.goal, 2, "m")
            object.__setattr__(self, "goal", (float(g[0]), float(g[1])))
        if self.strategy == "bug2" and self.goal is None:
            from planner.errors import InvalidParameter

            raise InvalidParameter("goal: the bug2 strategy needs a goal point (2,) [m]")


@dataclass(frozen=True)
class ExploredFeature:
    """One feature found, identified, traced and modelled.

    Attributes:
        kind: identified type (bump, pit, ridge, ravine, step, cusp, or unknown).
        confidence: posterior probability of ``kind`` [-]; ``scores`` of every kind.
        boundary: (N, 2) traced boundary samples in the plate frame [m]: fingertip centres on
            the outline level (re-approach samples dropped).
        closed: whether the trace closed its loop.
        ends_reached: ends of an open feature reached along its length, where its traced
            outline leaves the region (0, 1 or 2). A ridge or ravine is traced on both sides,
            and both sides' outlines run between the same two ends: this is the most ends
            one side reached, not the sum over sides.
        skeleton: the feature skeleton (:class:`planner.skeleton.Skeleton`) or None.
        centre: (2,) where the identification crossings peak (a bump's or pit's top or
            bottom; on a line feature where the search met it) [m]; detected_at: time of the
            detection [s].
        latency: online detection latency (peak crossed -> detection) [s].
        evidence: the cues read by the flow chart.
        rise: height of the traced outline above (below) the plate level [m]: the boundary
            tracer keeps the fingertip centre there (30 % of the feature's relief, at least
            ``boundary_rise``).
    """

    kind: str
    confidence: float
    scores: dict[str, float]
    boundary: np.ndarray
    closed: bool
    ends_reached: int
    skeleton: Any
    centre: np.ndarray
    detected_at: float
    latency: float
    evidence: tuple[str, ...] = ()
    rise: float = 2.5e-4


@dataclass(frozen=True)
class ExplorationResult:
    """What :func:`explore_surface` returns.

    Attributes:
        status: ``"ok"`` or ``"failed"``; reason: why it stopped / failed.
        features: the :class:`ExploredFeature` list, in the order found.
        global_skeleton: :class:`planner.skeleton.GlobalSkeleton` or None (fewer than 2).
        regions: the §4.5.3 region report (list of :class:`planner.skeleton.RegionInfo`).
        path: (M, 3) fingertip centres in the plate frame [m] (every control step).
        contacts: (M, 3) estimated contact points in the plate frame [m].
        normals: (M, 3) filtered outward surface normals in the plate frame [-].
        t: (M,) time [s]; phase: (M,) phase codes (see ``phases``).
        phases: names of the phase codes.
        events: simulator and explorer events (:class:`planner.sim.SimEvent`).
        log: the simulator's :class:`planner.sim.SimLog`.
        decision: (M,) continue-or-move-on parameter of §4.5.2 while tracing (nan otherwise).
        wall_time: wall-clock duration of the run [s].
        cpu_time: CPU time of this process over the run [s] (what the machine's load does not
            inflate; nan when not measured).
        settings: the :class:`ExplorationSettings` used.
        pose: 4x4 ``T_WS`` of the plate in the WCS.
    """

    status: str
    reason: str
    features: tuple[ExploredFeature, ...]
    global_skeleton: Any
    regions: tuple
    path: np.ndarray
    contacts: np.ndarray
    normals: np.ndarray
    t: np.ndarray
    phase: np.ndarray
    phases: tuple[str, ...]
    events: tuple
    log: Any
    decision: np.ndarray
    wall_time: float
    settings: ExplorationSettings
    pose: np.ndarray = field(default_factory=lambda: np.eye(4))
    cpu_time: float = float("nan")

    @property
    def sim_time(self) -> float:
        """Simulated duration [s]."""
        return float(self.t[-1]) if len(self.t) else 0.0

    @property
    def real_time_factor(self) -> float:
        """Simulated over wall-clock time [-]."""
        return self.sim_time / self.wall_time if self.wall_time > 0 else float("inf")

    @property
    def cpu_real_time_factor(self) -> float:
        """Simulated time over the run's CPU time [-] (nan when not measured): the real-time
        factor on an unloaded core."""
        c = self.cpu_time
        return self.sim_time / c if c > 0 else float("nan")
