"""The run result of the ``gait`` scenario kind (planner/kinds/gait.py): metrics, events,
arrays, figures and the optional GIF of an executed gait, ok or failed."""

from __future__ import annotations

import math


def report(config, ctx, res, profile, duration: float, hand, noise_seed: int | None = None):
    """The :class:`RunResult` of an executed gait, ok or failed: the figures show what ran
    up to the end, ``result.json`` has the reason and the last phase.

    Args:
        config: the validated ``gait`` scenario; ctx: the run context.
        res: the :class:`planner.exploration.planar.ExplorationResult`.
        profile: the true object profile; duration: the simulated time limit [s].
        hand: the ``robots.planar_hand.PlanarHand`` that ran it.
        noise_seed: the ``seed`` the run passed to ``explore_object`` (derived from the
            scenario's seed; ``metrics["noise_seed"]``: the same run from Python).
    """
    import json

    import numpy as np

    from planner.results import RunResult

    ridge = (math.radians(config.object.ridge_angle_deg)
             if config.object.shape == "circle_with_ridge" else None)  # fmt: skip
    theta = _rotation(config, res, profile)
    metrics = _metrics(config, res, profile, ridge, duration, theta)
    if noise_seed is not None:
        metrics["noise_seed"] = int(noise_seed)
    # the left fingertip that ran: null for the flat pad, else the round tip's radius [m]
    metrics["left_tip_radius_m"] = hand.params.left.round_radius or None
    metrics["gravity_m_s2"] = float(config.gravity)  # towards the palm; 0: a horizontal hand
    if ridge is not None:
        metrics.update(_ridge_coverage(config, res, profile, hand))
    arrays = {f"log/{k}": v for k, v in res.log.arrays().items() if k != "pairs"}
    arrays.update({f"trace/{k}": np.asarray(v) for k, v in res.trace.items()})
    events = _events(res)
    figures = _figures(ctx, res, profile, hand, ridge, theta) if ctx.plots else {}
    files = {"phases.json": json.dumps([p.to_json() for p in res.phases], indent=2)}
    if res.prior is not None:  # the map-space gait the executor followed (prior events)
        files["prior_gait.json"] = json.dumps(res.prior.to_json(), indent=2)
    if config.output.animation and ctx.plots:
        gif = _animation(ctx, res, profile, hand, events)
        if gif is not None:
            files["plots/animation.gif"] = gif
    reason = ""
    if res.status == "failed":
        reason = f"{res.reason} (last phase {metrics['last_phase']})"
    return RunResult(status=res.status, reason=reason, metrics=metrics, arrays=arrays,
                     events=events, figures=figures, files=files)  # fmt: skip


def _ridge_coverage(config, res, profile, hand) -> dict:
    """The untouched cells beside the ridge and the coverage outside its shadows
    (:func:`planner.exploration.planar.metrics.ridge_coverage`): the part of each side that
    neither the round right tip nor the pad touching with its middle (or a round left tip)
    can reach (the smaller of the two shadows), and ``ridge_probe_shadow_deg``: what the
    corner probe leaves beside the far wall (:mod:`planner.exploration.planar.corner_probe`, its
    contact :data:`~planner.exploration.planar.corner_probe.PROBE_EDGE` behind the pad's
    end: 2.9 deg on the 10 cm ball)."""
    from planner.exploration.planar.corner_probe import PROBE_EDGE
    from planner.exploration.planar.metrics import (
        coverage_mask,
        pad_shadow,
        ridge_coverage,
        round_tip_shadow,
    )

    o = config.object
    R = o.radius
    left = hand.params.left
    left_shadow = (round_tip_shadow(R, o.ridge_height, left.round_radius) if left.round_radius
                   else pad_shadow(R, o.ridge_height, left.pad_half_width))  # fmt: skip
    shadow = min(round_tip_shadow(R, o.ridge_height, hand.params.right.tip_radius), left_shadow)
    mask = coverage_mask(res.log, "object", profile)
    out = ridge_coverage(mask, math.radians(o.ridge_angle_deg), o.ridge_width / (2 * R), shadow)
    found = {f"ridge_{k}" if not k.startswith("coverage") else k: v for k, v in out.items()}
    found["ridge_probe_shadow_deg"] = math.degrees(pad_shadow(R, o.ridge_height, PROBE_EDGE))
    return found


def _rotation(config, res, profile):
    """(N,) sensed object rotation [rad] of every trace row (rolling on the holding pad in
    phase 2 and on the palm in phase 3 included:
    :func:`planner.exploration.planar.metrics.object_rotation`), with the planner's radius
    (the nominal shape's, else the object's)."""
    from planner.exploration.planar.metrics import object_rotation
    from planner.exploration.planar.objects import mean_radius

    if not len(res.trace.get("t", ())):
        return None
    nominal = config.nominal.profile() if config.nominal is not None else profile
    return object_rotation(res.trace, mean_radius(nominal))


def _metrics(config, res, profile, ridge, duration: float, theta) -> dict:
    """The listed metrics (``summary_metrics``) plus the features against the truth, the
    last phase and the timing spreads."""
    import numpy as np

    from planner.exploration.planar.metrics import summary_metrics
    from planner.exploration.planar.pad_trace import VIRTUAL_RADIUS
    from planner.exploration.planar.plots import fig214_measures

    m = summary_metrics(res, ridge, config.explore_force, config.internal_force)
    m["simulated_s"] = float(res.log.t[-1]) if len(res.log.t) else 0.0
    m["duration_limit_s"] = duration
    m["last_phase"] = res.phases[-1].kind if res.phases else 0
    truth = [math.degrees(math.atan2(f.position[1], f.position[0]))
             for f in profile.curvature_features(VIRTUAL_RADIUS)]  # fmt: skip
    m["true_features"] = len(truth)
    m["true_feature_angles_deg"] = [round(a, 2) for a in truth[:50]]
    m["features_within_5deg"] = sum(
        1 for f in res.features if np.isfinite(f.error) and abs(math.degrees(f.error)) <= 5.0
    )
    steps = np.asarray(res.timings.get("control_step_us", []), float)
    nlp = np.asarray(res.timings.get("nlp_solve_ms", []), float)
    m["controller_call_p95_us"] = float(np.percentile(steps, 95)) if steps.size else None
    m["nlp_solve_max_ms"] = float(np.max(nlp)) if nlp.size else None
    m["nlp_solves"] = int(nlp.size)
    m["prior_feasible"] = bool(res.prior.feasible) if res.prior is not None else None
    m["prior_deviations"] = sum(1 for e in res.events if e.get("kind") == "prior")
    m.update(fig214_measures(res, ridge, theta=theta))
    return m


def _events(res) -> list:
    """The simulator's, the gait's and one per phase, in time order."""
    from planner.results import Event

    events = [Event(e.kind, e.message, t=e.t, data=dict(e.data)) for e in res.log.events]
    for e in res.events:
        data = {k: v for k, v in e.items() if k not in ("kind", "message", "t")}
        events.append(Event(str(e["kind"]), str(e.get("message", "")), t=float(e["t"]),
                            data=data))  # fmt: skip
    for k, ph in enumerate(res.phases):
        four = " (transition 4)" if ph.skip else ""
        events.append(Event("phase", f"phase {ph.phase}{four}: {ph.event}", t=ph.end,
                            data={"index": k, **ph.to_json()}))  # fmt: skip
    events.sort(key=lambda e: e.t if e.t is not None else 0.0)
    return events


def _figures(ctx, res, profile, hand, ridge, theta) -> dict:
    from planner.exploration.planar import plots

    with ctx.timer("plots"):
        return {
            "timeline": plots.plot_timeline(res),
            "contacts": plots.plot_contacts(res),
            "forces": plots.plot_forces(res, ridge, theta=theta),
            "snapshots": plots.plot_snapshots(res, profile, hand),
        }


def _animation(ctx, res, profile, hand, events: list) -> bytes | None:
    """GIF bytes of the run, or ``None`` (with an event saying why) when it cannot be made
    (Pillow missing, nothing logged): the run's results stay valid without it."""
    from planner.exploration.planar.plots import animation_gif
    from planner.results import Event

    try:
        with ctx.timer("animation"):
            return animation_gif(res, profile, hand, frames=24 if ctx.quick else 80)
    except (ImportError, ValueError, OSError) as exc:
        events.append(Event("animation", f"no animation: {exc}"))
        return None


__all__ = ["report"]
