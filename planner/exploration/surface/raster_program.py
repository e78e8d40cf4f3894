"""The exploration procedure with raster pattern matching (thesis §4.4.1, the alternative).

"Rather than using an explicit flow chart for identification, the finger can also move over
the surface (perhaps in a raster-scanning fashion) and record all the curvature feature regions
detected. These regions can then be pattern-matched against the possible feature types."

:func:`raster_program` is the motion program of ``explore_surface(..., identify="raster")``:
scan every raster line without stopping (no online detection), match the curvature-feature
clusters of all lines (:func:`~planner.exploration.surface.raster_match.raster_identify`),
then trace each matched feature (§4.4.2) exactly as the flow-chart program does
(:func:`~planner.exploration.surface.program.trace_feature`), largest cluster first; a cluster
inside the area of a feature already traced is the same feature.
"""

from __future__ import annotations

import numpy as np

from planner.exploration.surface.motions import approach, sweep
from planner.exploration.surface.program import (
    FeatureRecord,
    outline_rise,
    relabel,
    remember,
    trace_feature,
)
from planner.exploration.surface.raster_match import raster_identify
from planner.exploration.surface.runtime import PHASE
from planner.exploration.surface.strategies import segments

__all__ = ["raster_program", "trace_geometry"]


def trace_geometry(feature, tip_radius: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Where to start tracing a raster match: ``(centre (2,), across (2,), half)``.

    ``half`` [m] is half the cluster's extent across the feature plus ``r_f / 2``: its
    curvature features reach the feet of the feature (the outline), and the tracer starts
    ``half + r_f / 4`` from the centre and slides inwards to the outline.
    """
    c = feature.centre
    across = feature.axis()
    half = 0.5 * float(np.ptp((feature.points - c) @ across)) + 0.5 * tip_radius
    return c, across, half


def raster_program(ex, cfg, region: np.ndarray, rng, state):
    """The generator driving the explorer with ``identify="raster"`` (see the module doc);
    same contract as :func:`~planner.exploration.surface.program.exploration_program`."""
    r = cfg.tip_radius
    yield from approach(ex)
    gen, _ = segments(cfg, region, rng)
    ranges = []
    for a, b in gen:
        k0, k1, _ = yield from sweep(ex, a, b, cfg.speed, "search")
        if k1 - k0 > 20:
            ranges.append((k0, k1))
    found = raster_identify([ex.rec.centre[k0:k1] for k0, k1 in ranges], r)
    t_found = ex.est.t
    for rf in found:
        c, across, half = trace_geometry(rf, r)
        if state.is_known(c) or rf.decision.kind == "unknown":
            continue
        ex.feature = len(state.features)
        dec = rf.decision
        ex.event("feature_detected", f"raster cluster of {len(rf.points)} curvature features")
        ex.event("feature_identified", f"{dec.kind} ({dec.confidence:.2f})", kind=dec.kind)
        rec_f = FeatureRecord(dec, c, across, detected_at=t_found, latency=float("nan"))
        rec_f.rise = outline_rise(dec.kind, rf.relief, cfg.boundary_rise)
        rec_f.reasons.append(f"raster match: elongation {rf.elongation:.1f}, lines {rf.lines}")
        yield from trace_feature(ex, cfg, rec_f, region, half)
        relabel(ex, rec_f)
        state.features.append(rec_f)
        remember(ex, state, rec_f, r)
        ex.feature = -1
    ex.phase = PHASE["idle"]
