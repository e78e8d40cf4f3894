"""The ``explore`` scenario kind's run: exploration, metrics, arrays, events, figures."""

from __future__ import annotations

import math

import numpy as np

from planner.exploration.surface.spacing import spacing_warnings  # re-export: outside code

__all__ = ["report", "spacing_warnings"]


def report(config, ctx):
    """Run the exploration of an ``explore`` scenario and package its results."""
    from planner.exploration.surface.explorer import explore_surface
    from planner.exploration.surface.metrics import exploration_metrics
    from planner.results import Event, RunResult

    plate = config.plate.build(config.name)
    region = np.array(config.region, float)
    duration = min(config.duration, config.quick_duration) if ctx.quick else config.duration
    with ctx.timer("explore"):
        res = explore_surface(
            plate,
            strategy=config.strategy,
            region=region,
            tip_radius=config.tip_radius,
            normal_force=config.normal_force,
            speed=config.speed,
            seed=config.seed,
            duration=duration,
            tilt=math.radians(config.plate.tilt_deg),
            goal=config.goal,
            trace_speed=config.trace_speed,
            friction=config.friction,
            identify=config.identify,
            control=config.control,
            all_contacts=config.all_contacts,
            **({} if config.line_spacing is None else {"line_spacing": config.line_spacing}),
        )
    with ctx.timer("metrics"):
        metrics = exploration_metrics(res, plate, region, config.tip_radius, config.normal_force)
    metrics["quick"] = bool(ctx.quick)
    for f_i, f in enumerate(res.features):
        metrics[f"feature{f_i}_kind"] = f.kind
        metrics[f"feature{f_i}_confidence"] = round(float(f.confidence), 4)
        metrics[f"feature{f_i}_closed"] = bool(f.closed)
    # features_too_close comes with the library's events (spacing_warnings, t = 0)
    events = [Event(e.kind, e.message, t=float(e.t), data=_plain(e.data)) for e in res.events]
    for e in events:
        if e.kind == "features_too_close":
            ctx.log(f"warning: {e.message}")
    figures = _figures(res, plate, region, config, ctx) if ctx.plots else {}
    return RunResult(
        status=res.status,
        reason="" if res.status == "ok" else res.reason,
        metrics=metrics,
        arrays=_arrays(res),
        events=events,
        figures=figures,
    )


def _plain(data) -> dict:
    out = {}
    for k, v in dict(data or {}).items():
        if isinstance(v, np.ndarray):
            v = v.tolist()
        elif isinstance(v, np.generic):
            v = v.item()
        out[str(k)] = v
    return out


def _arrays(res) -> dict:
    arrays = {
        "t": res.t,
        "path": res.path,
        "contacts": res.contacts,
        "normals": res.normals,
        "phase": res.phase.astype(np.int16),
        "decision": res.decision,
        "pose": res.pose,
    }
    if res.log is not None and res.log.normal_force.size:
        arrays["sim_t"] = res.log.t
        arrays["normal_force"] = res.log.normal_force.sum(axis=1)
        arrays["q"] = res.log.q
    b = [
        np.column_stack([np.full(len(f.boundary), i), f.boundary])
        for i, f in enumerate(res.features)
    ]
    arrays["boundaries"] = np.vstack(b) if b else np.zeros((0, 3))
    s = [
        np.column_stack([np.full(len(f.skeleton.points), i), f.skeleton.points])
        for i, f in enumerate(res.features)
        if f.skeleton is not None
    ]
    arrays["skeleton_points"] = np.vstack(s) if s else np.zeros((0, 3))
    if res.global_skeleton is not None:
        arrays["global_skeleton_points"] = res.global_skeleton.points
        arrays["global_skeleton_edges"] = res.global_skeleton.edges
    return arrays


def _figures(res, plate, region, config, ctx) -> dict:
    import matplotlib.pyplot as plt

    from planner.exploration.surface.plates import truth_features
    from planner.exploration.surface.plots import finger_view, time_series, top_view
    from robots.three_gm import ThreeGM

    with ctx.timer("plots"):
        truth = truth_features(plate, region, res.settings.tip_radius, res.settings.boundary_rise)
        figs = {
            "top_view": top_view(res, plate, region, truth, f"{config.name}: top view"),
            "time_series": time_series(res, config.normal_force, f"{config.name}: time series"),
            "finger_3d": finger_view(res, plate, region, ThreeGM(), f"{config.name}: 3GM"),
        }
    del plt
    return figs
