"""The runner of the ``skeleton`` scenario kind (its ``Config`` is in
``planner/kinds/skeleton.py``)."""

from __future__ import annotations

import json

import numpy as np
from scipy.spatial import cKDTree

from planner.errors import HapexError, InfeasibleProblem
from planner.results import Event, RunResult
from planner.skeleton.datafile import load_boundaries
from planner.skeleton.export import to_arrays, to_geojson
from planner.skeleton.feature import feature_skeleton, pseudo_skeleton
from planner.skeleton.global_map import global_skeleton
from planner.skeleton.mat import regeneration_error
from planner.skeleton.navigation import region_report, safest_path
from planner.skeleton.synthetic import make_feature

MAX_DVMA_PLOTS = 4


def _hausdorff(a: np.ndarray, b: np.ndarray) -> float:
    return float(max(cKDTree(b).query(a)[0].max(), cKDTree(a).query(b)[0].max()))


def _inputs(config, ctx):
    """(names, samples, traced, truths, spacings) from synthetic features or the data file."""
    if config.data_file is not None:
        from pathlib import Path

        path = Path(config.data_file)
        if not path.is_absolute():
            path = Path(ctx.base_dir) / path
        names, samples = load_boundaries(path)
        n = len(names)
        return names, samples, ["around"] * n, [None] * n, [config.data_spacing] * n
    names, samples, traced, truths, spacings = [], [], [], [], []
    for f in config.features:
        spacing = f.spacing * (2.0 if ctx.quick else 1.0)
        sf = make_feature(
            f.name,
            f.shape,
            center=f.center,
            angle_deg=f.angle_deg,
            length=f.length,
            width=f.width,
            radius=f.radius,
            sweep_deg=f.sweep_deg,
            turn_deg=f.turn_deg,
            arms=f.arms,
            height=f.height,
            spacing=spacing,
            noise=f.noise,
            traced=f.traced,
            rng=ctx.rng,
        )
        names.append(f.name)
        samples.append(sf.samples)
        traced.append(f.traced)
        truths.append(sf.truth)
        spacings.append(spacing)
    return names, samples, traced, truths, spacings


def run_skeleton(config, ctx) -> RunResult:
    """Run a validated ``skeleton`` scenario (see ``planner/kinds/skeleton.py``)."""
    names, samples, traced, truths, spacings = _inputs(config, ctx)
    p = config.pruning
    settings = {
        k: getattr(p, k)
        for k in (
            "max_edge_length",
            "min_generator_distance",
            "min_branch_length",
            "min_angle_deg",
            "keep_largest",
            "branching",
        )
    }
    metrics: dict = {"n_features": len(names)}
    arrays: dict = {}
    events: list[Event] = []
    skeletons = []
    failed = []
    with ctx.timer("feature_skeletons"):
        for name, pts, how, truth, spacing in zip(
            names, samples, traced, truths, spacings, strict=True
        ):
            arrays[f"boundary_{name}"] = pts
            try:
                if how == "along":
                    sk = pseudo_skeleton(pts, spacing)
                else:
                    sk = feature_skeleton(pts, spacing, noise=p.noise, **settings)
            except HapexError as exc:
                failed.append(name)
                events.append(Event("skeleton_failed", f"{name}: {exc}"))
                skeletons.append(None)
                continue
            skeletons.append(sk)
            m = {
                "n_samples": len(pts),
                "n_points": len(sk.points),
                "n_edges": len(sk.edges),
                "length_m": sk.length,
                "branch_points": len(sk.branch_points),
                "end_points": len(sk.end_points),
                "has_loop": sk.has_loop,
                "spacing_m": sk.spacing,
                "noise_m": sk.noise,
            }
            if how == "around" and len(sk.edges):
                err = regeneration_error(sk)
                m["regeneration_area_ratio"] = err.area_ratio
                m["regeneration_hausdorff_m"] = err.hausdorff
                m["mean_radius_m"] = float(np.mean(sk.radii))
            if truth is not None and len(sk.points):
                m["hausdorff_to_truth_m"] = _hausdorff(sk.points, truth)
            if len(sk.points) == 0:
                failed.append(name)
            metrics.update({f"{name}.{k}": v for k, v in m.items()})
            ctx.log(f"{name}: {len(sk.edges)} skeleton edges, length {sk.length:.4g} m")
    good = [s for s in skeletons if s is not None]
    for name, sk in zip(names, skeletons, strict=True):
        if sk is not None:
            arrays[f"skeleton_{name}_points"] = np.asarray(sk.points)
            arrays[f"skeleton_{name}_edges"] = np.asarray(sk.edges)
            arrays[f"skeleton_{name}_radii"] = np.asarray(sk.radii)
    gs = None
    path = None
    if len(names) >= 2:
        g = config.global_map
        with ctx.timer("global_skeleton"):
            gs = global_skeleton(
                samples,
                generators=g.generators,
                margin=g.margin,
                **(settings | {"noise": p.noise} if g.generators == "skeleton" else {}),
            )
            metrics["clearance_m"] = gs.clearance
            metrics["global_length_m"] = gs.length
            metrics["region_area_total_m2"] = float(gs.region_areas.sum())
            metrics["domain_area_m2"] = float(gs.domain.area)
            for name, area in zip(names, gs.region_areas, strict=True):
                metrics[f"{name}.region_area_m2"] = float(area)
            rep = region_report(gs, g.tip_radius)
            metrics["regions_needing_exploration"] = [
                names[r.feature] for r in rep if r.needs_exploration
            ]
            for r in rep:
                metrics[f"{names[r.feature]}.largest_gap_m"] = r.largest_gap
            narrow = [
                [names[i], names[j]]
                for i in range(len(names))
                for j in range(i + 1, len(names))
                if not gs.can_pass(i, j, g.tip_radius)
            ]
            metrics["impassable_pairs"] = narrow
            arrays.update(to_arrays((), gs))
            if g.start is not None:
                try:
                    nav = safest_path(gs, np.array(g.start), np.array(g.goal), g.tip_radius)
                    path = nav.points
                    metrics["path_length_m"] = nav.length
                    metrics["path_min_clearance_m"] = nav.min_clearance
                    arrays["path"] = nav.points
                except InfeasibleProblem as exc:
                    events.append(Event("no_path", str(exc)))
                    metrics["path_length_m"] = None
    files = {
        "skeletons.geojson": json.dumps(
            to_geojson(
                [s for s in skeletons if s is not None],
                gs,
                None if len(good) != len(names) else names,
            ),
            allow_nan=False,
        )
    }
    figures = {}
    if ctx.plots:
        from planner.skeleton.plots import plot_dvma_pruning, plot_feature_map

        with ctx.timer("plots"):
            shown = 0
            for name, pts, how, sk in zip(names, samples, traced, skeletons, strict=True):
                limit = 1 if ctx.quick else MAX_DVMA_PLOTS
                if sk is None or how != "around" or shown >= limit:
                    continue
                figures[f"dvma_{name}"] = plot_dvma_pruning(
                    pts, sk, f"{name}: DVMA before and after pruning"
                )
                shown += 1
            if gs is not None:
                figures["feature_map"] = plot_feature_map(
                    gs, good, path, names, f"Global skeleton and regions of {len(names)} features"
                )
    status, reason = "ok", ""
    if failed:
        status, reason = "failed", f"no skeleton for feature(s) {failed}"
    return RunResult(
        status=status,
        reason=reason,
        metrics=metrics,
        arrays=arrays,
        events=events,
        figures=figures,
        files=files,
    )


__all__ = ["run_skeleton"]
