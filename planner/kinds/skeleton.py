"""Scenario kind ``skeleton``: feature skeletons, global skeleton and feature map (thesis
§4.4.3, §4.5.3, Figs. 4.11-4.15).

Boundary samples come from synthetic features (``features``) or a data file
(``data_file``, CSV/NPZ with ``feature_id, x, y`` [m]). Each feature gets its pruned DVMA
skeleton (or, when traced along, its pseudo-skeleton); with two or more features the global
skeleton partitions the surface into regions.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from planner.scenario import ScenarioBase, StrictModel


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


class PruningSpec(StrictModel):
    """Feature skeleton pruning (``null`` = derived from spacing and noise)."""

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


def run(config: Config, ctx):
    """Build the skeletons and the feature map; see the module docstring."""
    from planner.skeleton.runner import run_skeleton

    return run_skeleton(config, ctx)
