"""``explore_surface``: feature-guided exploration of a fixed plate with the 3GM (thesis ch. 4).

The plate (:class:`planner.sim.spatial.Plate`) is placed under the finger
(:mod:`~planner.exploration.surface.placement`), the world is built with the finger resting
0.5 mm above the first search point, and :class:`~planner.exploration.surface.runtime.
ExplorerController` runs :func:`~planner.exploration.surface.program.exploration_program` at
1 kHz under the hybrid law of §4.3. Afterwards every traced feature gets its skeleton and the
features their global skeleton and region report (§4.4.3, §4.5.3).
"""

from __future__ import annotations

import time
from dataclasses import fields

import numpy as np

from planner import checks
from planner.control.hybrid_law import HybridSettings, check_force_feasible
from planner.errors import InvalidParameter
from planner.exploration.surface.modelling import feature_model, global_model
from planner.exploration.surface.placement import (
    check_reachable,
    plate_pose,
    region_box,
    to_world,
)
from planner.exploration.surface.plates import plate_height
from planner.exploration.surface.program import (
    ProgramState,
    exploration_program,
    traced_sides,
)
from planner.exploration.surface.raster_program import raster_program
from planner.exploration.surface.result import (
    ExplorationResult,
    ExplorationSettings,
    ExploredFeature,
    check_duration,
)
from planner.exploration.surface.runtime import PHASES, ExplorerController
from planner.exploration.surface.spacing import spacing_warnings
from planner.exploration.surface.strategies import segments
from planner.sim import SimEvent

__all__ = ["explore_surface"]

GAP = 5e-4  # [m] the fingertip starts this far above the plate


def _corners(region: np.ndarray) -> np.ndarray:
    (u0, u1), (v0, v1) = region
    return np.array([[u0, v0], [u1, v0], [u1, v1], [u0, v1], [(u0 + u1) / 2, (v0 + v1) / 2]])


def _start_height(H, point, r: float, slack: float = 0.5 * GAP) -> float:
    """Height [m] of the fingertip centre over ``point`` for a clearance of at least ``GAP -
    slack`` once ``GAP`` is added: ``H + r``, unless the ball of radius ``r`` resting on ``H``
    above ``point`` (the grey dilation, :func:`~planner.exploration.surface.kinematic.
    ball_trace`: on a slope or next to a crest it rests on the highest point under it) is
    higher by more than ``slack``; then that resting height, so the finger never starts in
    penetration."""
    from planner.exploration.surface.kinematic import ball_trace

    flat = float(H(point[0], point[1])) + r
    rest = float(ball_trace(H, np.asarray(point, float)[None, :2], r, grid=r / 80).centers[0, 2])
    return rest if rest > flat + slack else flat


def build_world(plate, cfg: ExplorationSettings, region, tilt: float, seed: int, sensors=None):
    """World, finger and plate pose for an exploration; validates reach, goal and force."""
    from planner.sim import SpatialWorld
    from robots.three_gm import ThreeGM

    gm = ThreeGM()
    H = plate_height(plate)
    r = cfg.tip_radius
    mid = region.mean(axis=1)
    T = plate_pose(gm, region, tilt, float(H(mid[0], mid[1])), r + GAP)
    corners = _corners(region)
    check_reachable(gm, T, corners, H(corners[:, 0], corners[:, 1]), r, "region")
    if cfg.goal is not None:
        g = np.array([cfg.goal])
        check_reachable(gm, T, g, H(g[:, 0], g[:, 1]), r, "goal")
    _, first = segments(cfg, region, np.random.default_rng(seed))
    x0 = to_world(T, [first[0], first[1], _start_height(H, first, r) + GAP])
    theta = gm.inverse_kinematics(x0)
    for p in corners:
        x = to_world(T, [p[0], p[1], float(H(p[0], p[1])) + r])
        check_force_feasible(gm, gm.inverse_kinematics(x, theta), cfg.normal_force)
    world = SpatialWorld(dt=1e-3, seed=seed, sensors=sensors, all_contacts=cfg.all_contacts)
    world.add_surface(plate, friction=cfg.friction, name="plate", pose=T)
    world.add_finger(gm, theta, tip_radius=r)
    return world, gm, T


def explore_surface(
    surface,
    *,
    strategy: str = "raster",
    region=None,
    tip_radius: float = 0.008,
    normal_force: float = 0.3,
    speed: float = 0.02,
    seed: int = 0,
    duration: float | None = None,
    tilt: float = 0.0,
    goal=None,
    sensors=None,
    control: str = "open_loop",
    **options,
) -> ExplorationResult:
    """Explore ``surface`` with the 3GM: search, identify, trace, model (thesis ch. 4).

    Args:
        surface: a :class:`planner.sim.spatial.plate.Plate` (plate frame: ``z`` up).
        strategy: ``"raster"``, ``"random_walk"`` or ``"bug2"`` (needs ``goal``).
        region: ((u0, u1), (v0, v1)) explored box of the plate frame [m] (default 40 mm
            square about the origin).
        tip_radius: fingertip radius r_f [m].
        normal_force: desired normal force [N] (eq. 4.12).
        speed: search speed [m/s].
        seed: seed of the simulator's sensor noise and of the random walk (an integer >= 0).
        duration: longest simulated time [s] (default 120 s, at most
            :data:`~planner.exploration.surface.result.MAX_DURATION`: every control step is
            recorded).
        tilt: tilt of the plate about the WCS y axis [rad].
        goal: (2,) bug-2 goal in the plate frame [m].
        sensors: :class:`planner.sim.SensorSettings` (default: the world's).
        control: normal-force variant of the hybrid law: ``"open_loop"`` (eq. 4.12),
            ``"closed_loop"`` (PI on the sensed normal force) or ``"qp"`` (torque limits by a
            QP that keeps the normal force), see :mod:`planner.control.hybrid_variants`.
        **options: further :class:`ExplorationSettings` fields (``trace_speed``,
            ``line_spacing``, ``boundary_rise``, ``friction``, ``kp``, ``kv``, ...).

    Returns:
        :class:`ExplorationResult` (status "failed" with a reason when the run could not go on).
        Features closer than a fingertip diameter (the §4.2.1 assumption) are explored
        anyway; each such pair adds a ``features_too_close`` event at t = 0 s
        (:func:`~planner.exploration.surface.spacing.spacing_warnings`).

    Raises:
        InvalidParameter: bad arguments (an unknown option, a ``seed`` that is not an integer
            >= 0, ``sensors`` that are not a SensorSettings, ...), a region or goal out of
            reach, a force beyond the torque limits.
    """
    seed = checks.integer("seed", seed, 0)
    _check_options(options)
    _check_sensors(sensors)
    cfg = ExplorationSettings(
        strategy=strategy,
        tip_radius=tip_radius,
        normal_force=normal_force,
        speed=speed,
        goal=None if goal is None else tuple(goal),
        **options,
    )
    hs = HybridSettings(
        kp=cfg.kp,
        kv=cfg.kv,
        normal_force=cfg.normal_force,
        tip_radius=tip_radius,
        control=control,
    )
    reg = region_box(((-0.02, 0.02), (-0.02, 0.02)) if region is None else region)
    dur = 120.0 if duration is None else check_duration(duration)
    if not hasattr(surface, "features"):
        raise InvalidParameter(
            f"surface: expected a planner.sim.spatial.Plate, got {type(surface).__name__}"
        )
    world, gm, T = build_world(surface, cfg, reg, tilt, seed, sensors)
    close = [
        SimEvent(0.0, "features_too_close", m)
        for m in spacing_warnings(surface, reg, cfg.tip_radius)
    ]
    ex = ExplorerController(gm, hs, T, int(dur * 1000) + 2)
    state = ProgramState()
    program = raster_program if cfg.identify == "raster" else exploration_program
    ex.program = program(ex, cfg, reg, np.random.default_rng(seed), state)
    _warm_up(ex, lambda: build_world(surface, cfg, reg, tilt, seed, sensors)[0])
    t0, c0 = time.perf_counter(), time.process_time()
    log = world.run(dur, controller=ex, stop=ex.stop)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    return _result(ex, state, log, cfg, T, wall, cpu, close)


def _check_options(options: dict) -> None:
    """Raise InvalidParameter naming any ``**options`` key that is not an
    :class:`ExplorationSettings` field (or is one of ``explore_surface``'s own arguments)."""
    own = {"strategy", "tip_radius", "normal_force", "speed", "goal"}
    valid = sorted(f.name for f in fields(ExplorationSettings) if f.name not in own)
    for name in options:
        if name not in valid:
            raise InvalidParameter(
                f"{name}: not an option of explore_surface; expected one of {valid}"
            )


def _check_sensors(sensors) -> None:
    """Raise InvalidParameter unless ``sensors`` is None or a SensorSettings."""
    from planner.sim import SensorSettings

    if sensors is not None and not isinstance(sensors, SensorSettings):
        raise InvalidParameter(
            f"sensors: expected None or a planner.sim.SensorSettings, got "
            f"{type(sensors).__name__} {sensors!r}"
        )


def _warm_up(ex, scratch_world) -> None:
    """Import what the program imports on first use and load the compiled code (the explorer's
    step; the simulator's kernels through 2 ms of a scratch copy of the world), so that the
    measured wall time - the real-time factor - is the control loop's, not the process's
    start-up (numba cache loads, ~1 s once per process)."""
    import scipy.spatial  # noqa: F401 - the decision parameter's nearest neighbours
    import shapely  # noqa: F401 - known areas

    import planner.detection  # noqa: F401 - online detection (algorithm 3)

    ex.warm_up()
    scratch_world().run(0.002)


def _result(ex, state, log, cfg, T, wall, cpu=float("nan"), warnings=()) -> ExplorationResult:
    rec = ex.rec
    n = rec.n
    feats = []
    for f in state.features:
        sides, boundary = traced_sides(rec, f)
        dec = f.decision  # refined by the traced outline (program.relabel)
        feats.append(
            ExploredFeature(
                kind=dec.kind,
                confidence=dec.confidence,
                scores=dict(dec.scores),
                boundary=boundary,
                closed=bool(f.closed),
                ends_reached=int(f.ends),
                skeleton=feature_model(dec.kind, sides, f.closed),
                centre=np.asarray(f.centre, float),
                detected_at=float(f.detected_at),
                latency=float(f.latency),
                evidence=tuple(dec.path) + tuple(f.reasons),
                rise=float(f.rise),
            )
        )
    gs, regions = global_model([f.boundary for f in feats], cfg.tip_radius)
    status = "failed" if ex.failed else log.status
    reason = ex.failed or log.reason or ex.finished or "duration reached"
    events = tuple(sorted([*warnings, *log.events, *ex.events], key=lambda e: e.t))
    return ExplorationResult(
        status=status,
        reason=reason,
        features=tuple(feats),
        global_skeleton=gs,
        regions=regions,
        path=rec.centre[:n].copy(),
        contacts=rec.contact[:n].copy(),
        normals=rec.normal[:n].copy(),
        t=rec.t[:n].copy(),
        phase=rec.phase[:n].copy(),
        phases=PHASES,
        events=events,
        log=log,
        decision=rec.decision[:n].copy(),
        wall_time=wall,
        cpu_time=cpu,
        settings=cfg,
        pose=T,
    )
