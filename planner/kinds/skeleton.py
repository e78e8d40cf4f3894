"""Scenario kind ``skeleton``: feature skeletons, global skeleton and feature map (thesis
§4.4.3, §4.5.3, Figs. 4.11-4.15).

Boundary samples come from synthetic features (``features``) or a data file
(``data_file``, CSV/NPZ with ``feature_id, x, y`` [m]). Each feature gets its pruned DVMA
skeleton (or, when traced along, its pseudo-skeleton); with two or more features the global
skeleton partitions the surface into regions.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import Field, model_validator

from planner.results import Event, RunResult
from planner.scenario import ScenarioBase, StrictModel

MAX_DVMA_PLOTS = 4


class FeatureSpec(StrictModel):
    """One synthetic feature."""

    name: str = Field(..., pattern=r"^[A-Za-z0-9_.-]+$", description="feature name")
    shape: Literal[
        "straight", "curved", "sharp_turn", "branching", "ring", "rectangle", "ellipse"
    ] = Field(..., description="feature shape")
    center: tuple[float, float] = Field((0.0, 0.0), description="reference point [m]")
    angle_deg: float = Field(0.0, description="rotation of the feature [deg]")
    length: float = Field(0.03, gt=0, description="ridge/arm length, rectangle width [m]")
    width: float = Field(0.006, gt=0, description="ridge width; ellipse minor diameter [m]")
    radius: float = Field(
        0.02,
        gt=0,
        description="arc radius (curved), mid radius (ring), ellipse semi-major axis [m]",
    )
    sweep_deg: float = Field(120.0, gt=0, le=300, description="arc sweep (curved) [deg]")
    turn_deg: float = Field(150.0, gt=0, lt=180, description="heading change at a sharp turn [deg]")
    arms: int = Field(3, ge=3, le=8, description="arms of a branching ridge")
    height: float = Field(0.01, gt=0, description="rectangle height [m]")
    spacing: float = Field(0.0005, gt=0, description="boundary sample spacing [m]")
    noise: float = Field(0.0, ge=0, description="sample noise standard deviation [m]")
    traced: Literal["around", "along"] = Field(
        "around", description="traced around (boundary) or along (cusp/step: pseudo-skeleton)"
    )

    @model_validator(mode="after")
    def _consistent(self):
        if self.traced == "along" and self.shape == "branching":
            raise ValueError(
                "traced 'along' needs a single centre line; trace a branching ridge around"
            )
        if self.shape == "ring" and not self.width < 2 * self.radius:
            raise ValueError(f"a ring needs width < 2 * radius = {2 * self.radius:g} m")
        if self.shape == "ellipse" and not self.width / 2 <= self.radius:
            raise ValueError(
                f"an ellipse needs width / 2 <= radius (semi-minor <= semi-major axis), got "
                f"{self.width / 2:g} > {self.radius:g} m"
            )
        return self


class PruningSpec(StrictModel):
    """Feature skeleton pruning (``null`` = derived from spacing and noise); see
    :class:`planner.skeleton.SkeletonSettings`."""

    max_edge_length: float | None = Field(None, ge=0, description="longest Voronoi edge [m]")
    min_generator_distance: float | None = Field(
        None, ge=0, description="closest generating samples of a kept edge [m]"
    )
    min_branch_length: float | None = Field(
        None, ge=0, description="shortest terminal arc kept [m]"
    )
    min_angle_deg: float = Field(
        45.0, ge=0, lt=180, description="smallest angle subtended by the generators [deg]"
    )
    keep_largest: bool = Field(True, description="keep the connected skeleton with most edges")
    branching: bool = Field(True, description="False: keep only the main path")
    noise: float | None = Field(None, ge=0, description="boundary noise [m] (null: estimated)")

    def settings(self):
        """The :class:`planner.skeleton.SkeletonSettings` of this block."""
        from planner.skeleton import SkeletonSettings

        return SkeletonSettings(
            max_edge_length=self.max_edge_length,
            min_generator_distance=self.min_generator_distance,
            min_branch_length=self.min_branch_length,
            min_angle_deg=self.min_angle_deg,
            keep_largest=self.keep_largest,
            branching=self.branching,
        )


class GlobalSpec(StrictModel):
    """Global skeleton and feature map."""

    generators: Literal["boundary", "skeleton"] = Field(
        "boundary", description="Voronoi generators: boundary samples or skeleton points"
    )
    margin: float | None = Field(None, ge=0, description="domain margin [m] (null: 10 %)")
    tip_radius: float = Field(0.005, gt=0, description="fingertip radius r_f [m]")
    start: tuple[float, float] | None = Field(None, description="navigation start [m]")
    goal: tuple[float, float] | None = Field(None, description="navigation goal [m]")

    @model_validator(mode="after")
    def _both_or_none(self):
        if (self.start is None) != (self.goal is None):
            raise ValueError("give both start and goal, or neither")
        return self


class Config(ScenarioBase):
    """Feature skeletons (DVMA), the global skeleton and the feature map of §4.4-4.5."""

    kind: Literal["skeleton"]
    features: list[FeatureSpec] = Field(default_factory=list, description="synthetic features")
    data_file: str | None = Field(None, description="CSV/NPZ with feature_id, x, y [m]")
    data_spacing: float | None = Field(None, gt=0, description="sample spacing of data_file [m]")
    pruning: PruningSpec = Field(default_factory=PruningSpec)
    global_map: GlobalSpec = Field(default_factory=GlobalSpec)

    @model_validator(mode="after")
    def _one_source(self):
        if bool(self.features) == (self.data_file is not None):
            raise ValueError("give either features (synthetic) or data_file, not both/neither")
        names = [f.name for f in self.features]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ValueError(f"feature names must be unique; repeated: {dup}")
        return self


def _hausdorff(a: np.ndarray, b: np.ndarray) -> float:
    from scipy.spatial import cKDTree

    return float(max(cKDTree(b).query(a)[0].max(), cKDTree(a).query(b)[0].max()))


def _inputs(config: Config, ctx) -> list[dict]:
    """One record per feature: name, samples (M, 2) [m], traced, truth, spacing [m]."""
    if config.data_file is not None:
        from planner.skeleton.datafile import load_boundaries

        path = Path(config.data_file)
        if not path.is_absolute():
            path = Path(ctx.base_dir) / path
        names, samples = load_boundaries(path)
        return [
            {
                "name": n,
                "samples": s,
                "traced": "around",
                "truth": None,
                "spacing": config.data_spacing,
            }
            for n, s in zip(names, samples, strict=True)
        ]
    from planner.skeleton.synthetic import make_feature

    out = []
    for f in config.features:
        spacing = f.spacing * (2.0 if ctx.quick else 1.0)
        keys = (
            "center",
            "angle_deg",
            "length",
            "width",
            "radius",
            "sweep_deg",
            "turn_deg",
            "arms",
            "height",
            "noise",
            "traced",
        )
        sf = make_feature(
            f.name, f.shape, spacing=spacing, rng=ctx.rng, **{k: getattr(f, k) for k in keys}
        )
        out.append(
            {
                "name": f.name,
                "samples": sf.samples,
                "traced": f.traced,
                "truth": sf.truth,
                "spacing": spacing,
            }
        )
    return out


def _feature_metrics(feat: dict, sk) -> dict:
    from planner.skeleton.mat import regeneration_error

    m = {
        "n_samples": len(feat["samples"]),
        "n_points": len(sk.points),
        "n_edges": len(sk.edges),
        "length_m": sk.length,
        "branch_points": len(sk.branch_points),
        "end_points": len(sk.end_points),
        "has_loop": sk.has_loop,
        "spacing_m": sk.spacing,
        "noise_m": sk.noise,
    }
    if feat["traced"] == "around" and len(sk.edges):
        err = regeneration_error(sk)
        m["regeneration_area_ratio"] = err.area_ratio
        m["regeneration_hausdorff_m"] = err.hausdorff
        m["mean_radius_m"] = float(np.mean(sk.radii))
    if feat["truth"] is not None and len(sk.points):
        m["hausdorff_to_truth_m"] = _hausdorff(sk.points, feat["truth"])
    return m


def _feature_skeletons(config: Config, ctx, feats: list[dict], out: dict) -> tuple[list, list]:
    """Each feature's skeleton (``None`` where it failed) and the names that failed."""
    from planner.errors import HapexError
    from planner.skeleton import feature_skeleton, pseudo_skeleton

    p = config.pruning
    settings = p.settings()
    skeletons, failed = [], []
    for feat in feats:
        name, pts = feat["name"], feat["samples"]
        out["arrays"][f"boundary_{name}"] = pts
        try:
            if feat["traced"] == "along":
                sk = pseudo_skeleton(pts, feat["spacing"])
            else:
                sk = feature_skeleton(pts, feat["spacing"], noise=p.noise, settings=settings)
        except HapexError as exc:
            failed.append(name)
            out["events"].append(Event("skeleton_failed", f"{name}: {exc}"))
            skeletons.append(None)
            continue
        skeletons.append(sk)
        if len(sk.points) == 0:
            failed.append(name)
        out["metrics"].update({f"{name}.{k}": v for k, v in _feature_metrics(feat, sk).items()})
        out["arrays"][f"skeleton_{name}_points"] = np.asarray(sk.points)
        out["arrays"][f"skeleton_{name}_edges"] = np.asarray(sk.edges)
        out["arrays"][f"skeleton_{name}_radii"] = np.asarray(sk.radii)
        ctx.log(f"{name}: {len(sk.edges)} skeleton edges, length {sk.length:.4g} m")
    return skeletons, failed


def _navigation(g, gs, out: dict):
    """The safest path from ``g.start`` to ``g.goal`` (points, or ``None``)."""
    from planner.errors import InfeasibleProblem
    from planner.skeleton import safest_path

    try:
        nav = safest_path(gs, np.array(g.start), np.array(g.goal), g.tip_radius)
    except InfeasibleProblem as exc:
        out["events"].append(Event("no_path", str(exc)))
        out["metrics"]["path_length_m"] = None
        return None
    out["metrics"]["path_length_m"] = nav.length
    out["metrics"]["path_min_clearance_m"] = nav.min_clearance
    out["arrays"]["path"] = nav.points
    return nav.points


def _global_map(config: Config, names: list[str], samples: list, out: dict):
    """Global skeleton, regions, clearances, navigation (metrics and arrays into ``out``)."""
    from planner.skeleton import global_skeleton, region_report, to_arrays

    g, p, m = config.global_map, config.pruning, out["metrics"]
    gs = global_skeleton(
        samples, generators=g.generators, margin=g.margin, settings=p.settings(), noise=p.noise
    )
    m["clearance_m"] = gs.clearance
    m["global_length_m"] = gs.length
    m["region_area_total_m2"] = float(gs.region_areas.sum())
    m["domain_area_m2"] = float(gs.domain.area)
    for name, area in zip(names, gs.region_areas, strict=True):
        m[f"{name}.region_area_m2"] = float(area)
    rep = region_report(gs, g.tip_radius)
    m["regions_needing_exploration"] = [names[r.feature] for r in rep if r.needs_exploration]
    for r in rep:
        m[f"{names[r.feature]}.largest_gap_m"] = r.largest_gap
    n = len(names)
    m["impassable_pairs"] = [
        [names[i], names[j]]
        for i in range(n)
        for j in range(i + 1, n)
        if not gs.can_pass(i, j, g.tip_radius)
    ]
    out["arrays"].update(to_arrays((), gs))
    path = _navigation(g, gs, out) if g.start is not None else None
    return gs, path


def _figures(ctx, feats: list[dict], skeletons: list, gs, path) -> dict:
    from planner.skeleton.plots import dvma_figure, feature_map_figure

    figures = {}
    limit = 1 if ctx.quick else MAX_DVMA_PLOTS
    for feat, sk in zip(feats, skeletons, strict=True):
        if sk is None or feat["traced"] != "around" or len(figures) >= limit:
            continue
        name = feat["name"]
        figures[f"dvma_{name}"] = dvma_figure(
            feat["samples"], sk, f"{name}: DVMA before and after pruning"
        )
    if gs is not None:
        names = [f["name"] for f in feats]
        good = [s for s in skeletons if s is not None]
        figures["feature_map"] = feature_map_figure(
            gs, good, path, names, f"Global skeleton and regions of {len(names)} features"
        )
    return figures


def run(config: Config, ctx) -> RunResult:
    """Build the skeletons and the feature map; see the module docstring."""
    from planner.skeleton import to_geojson

    feats = _inputs(config, ctx)
    names = [f["name"] for f in feats]
    out: dict = {"metrics": {"n_features": len(names)}, "arrays": {}, "events": []}
    with ctx.timer("feature_skeletons"):
        skeletons, failed = _feature_skeletons(config, ctx, feats, out)
    gs = path = None
    if len(names) >= 2:
        with ctx.timer("global_skeleton"):
            gs, path = _global_map(config, names, [f["samples"] for f in feats], out)
    good = [s for s in skeletons if s is not None]
    geojson = to_geojson(good, gs, None if len(good) != len(names) else names)
    figures = {}
    if ctx.plots:
        with ctx.timer("plots"):
            figures = _figures(ctx, feats, skeletons, gs, path)
    status, reason = "ok", ""
    if failed:
        status, reason = "failed", f"no skeleton for feature(s) {failed}"
    return RunResult(
        status=status,
        reason=reason,
        metrics=out["metrics"],
        arrays=out["arrays"],
        events=out["events"],
        figures=figures,
        files={"skeletons.geojson": json.dumps(geojson, allow_nan=False)},
    )


__all__ = ["Config", "run"]
