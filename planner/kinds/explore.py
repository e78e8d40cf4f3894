"""Scenario kind ``explore``: feature-guided exploration of a plate with the 3GM (thesis ch. 4).

Keys (SI units)::

    plate:
      tilt_deg: 0.0              # plate tilt about the WCS y axis [deg] (wire_plate_45: 45)
      features:                  # macro features (planner.sim.spatial.PlateFeature)
        - kind: ridge            # ridge | ravine | step | bump | pit | wire | cusp
          height: 0.002          # [m] (the wire's diameter)
          width: 0.002           # profile width w [m]
          position: [0.0, 0.0]   # crest / centre in the plate frame [m]
          across_deg: 30.0       # direction of the profile coordinate [deg]
          path: null             # polyline skeleton [[u, v], ...] of a finite/bent feature [m]
    region: [[-0.02, 0.02], [-0.02, 0.02]]   # explored box of the plate frame [m]
    strategy: raster             # raster | random_walk | bug2
    identify: flow_chart         # flow_chart (crossings, Fig. 4.7 extended) | raster
    control: open_loop           # normal force: open_loop (eq. 4.12) | closed_loop | qp
    line_spacing: null           # largest raster line spacing [m] (1.5 r_f; >= 0.05 r_f)
    all_contacts: false          # simulate every tip-plate contact (both rims of a groove)
    goal: null                   # bug2 goal [u, v] in the plate frame [m]
    tip_radius: 0.008            # fingertip radius r_f [m]
    normal_force: 0.3            # desired normal force (eq. 4.12) [N]
    speed: 0.03                  # search speed [m/s]
    trace_speed: 0.012           # tracing speed [m/s]
    friction: 0.1                # fingertip-plate friction (graphite, §4.3.3) [-]
    duration: 60.0               # longest simulated time [s] (at most 600)
    quick_duration: 0.6          # simulated time of --quick [s]

Bad input (exit 2): a region or goal the fingertip cannot reach, a normal force beyond the
motors' capacity (App. C.2.1), a bug2 strategy without goal, raster identification without
the raster strategy. Features closer than a fingertip diameter (the §4.2.1 assumption) are
run anyway, with a ``features_too_close`` event.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, ValidationInfo, field_validator, model_validator

from planner.scenario import ScenarioBase, StrictModel


class FeatureSpec(StrictModel):
    """One macro feature of the plate."""

    kind: Literal["ridge", "ravine", "step", "bump", "pit", "wire", "cusp"] = Field(
        ..., description="feature type"
    )
    height: float = Field(..., gt=0, le=0.02, description="height / depth / wire diameter [m]")
    width: float = Field(0.002, gt=0, le=0.05, description="profile width w [m]")
    position: tuple[float, float] = Field((0.0, 0.0), description="centre / crest point [m]")
    across_deg: float = Field(0.0, ge=-360, le=360, description="profile direction [deg]")
    rounding: float | None = Field(None, gt=0, description="cusp/wire rounding [m]")
    path: list[tuple[float, float]] | None = Field(
        None, min_length=1, description="polyline skeleton of a finite or bent feature [m]"
    )

    @model_validator(mode="after")
    def _path(self):
        if self.path is not None and self.kind == "step":
            raise ValueError("a step has no skeleton path; use position and across_deg")
        # the feature's own checks here, each located at the key its message starts with
        # (plate.features[i].rounding); raised later, inside the reach check, they were
        # blamed on region
        _invalid_as_value_error(self.build)
        return self

    def build(self):
        from planner.sim.spatial.plate import PlateFeature

        return PlateFeature(
            self.kind,
            self.height,
            self.width,
            self.position,
            math.radians(self.across_deg),
            self.rounding,
            path=None if self.path is None else tuple(self.path),
        )


class PlateSpec(StrictModel):
    """The plate: its features and tilt."""

    features: list[FeatureSpec] = Field(default_factory=list, description="macro features")
    tilt_deg: float = Field(0.0, ge=-60, le=60, description="tilt about the WCS y axis [deg]")

    def build(self, name: str = "plate"):
        from planner.sim.spatial.plate import Plate

        return Plate(tuple(f.build() for f in self.features), name=name)


def _check(plate_spec, tip_radius, region, goal, normal_force) -> None:
    """Reach and force checks of the explorer (raise InvalidParameter)."""
    from planner.exploration.surface.explorer import build_world
    from planner.exploration.surface.placement import region_box
    from planner.exploration.surface.result import ExplorationSettings

    cfg = ExplorationSettings(
        strategy="bug2" if goal is not None else "raster",
        tip_radius=tip_radius,
        normal_force=normal_force,
        goal=goal,
    )
    build_world(plate_spec.build(), cfg, region_box(region), math.radians(plate_spec.tilt_deg), 0)


class Config(ScenarioBase):
    """Search a plate, identify, trace and map its features with the 3GM (ch. 4)."""

    kind: Literal["explore"]
    plate: PlateSpec
    tip_radius: float = Field(0.008, gt=0.002, le=0.02, description="fingertip radius r_f [m]")
    normal_force: float = Field(0.3, gt=0, le=20, description="desired normal force [N]")
    region: tuple[tuple[float, float], tuple[float, float]] = Field(
        ((-0.02, 0.02), (-0.02, 0.02)), description="explored box [[u0, u1], [v0, v1]] [m]"
    )
    goal: tuple[float, float] | None = Field(None, description="bug2 goal [m]")
    strategy: Literal["raster", "random_walk", "bug2"] = Field("raster", description="search")
    identify: Literal["flow_chart", "raster"] = Field(
        "flow_chart",
        description="type identification: crossings of the extended Fig. 4.7 (stop at each "
        "detection) or pattern matching of the whole raster's curvature regions (§4.4.1)",
    )
    control: Literal["open_loop", "closed_loop", "qp"] = Field(
        "open_loop",
        description="normal-force variant of the hybrid law (open loop eq. 4.12, PI on the "
        "sensed normal force, torque-limit QP)",
    )
    line_spacing: float | None = Field(
        None,
        gt=0,
        le=0.1,
        description="largest raster line spacing [m] (default 1.5 r_f, at least 0.05 r_f)",
    )
    all_contacts: bool = Field(
        False,
        description="simulate every point where the tip touches the plate (a groove narrower "
        "than the tip on both rims); false: one contact, which can sink into the far rim",
    )
    speed: float = Field(0.03, gt=0, le=0.1, description="search speed [m/s]")
    trace_speed: float = Field(0.012, gt=0, le=0.1, description="tracing speed [m/s]")
    friction: float = Field(0.1, ge=0, le=2, description="fingertip-plate friction [-]")
    duration: float = Field(
        60.0, gt=0, description="longest simulated time [s] (at most 600: every step is kept)"
    )
    quick_duration: float = Field(0.6, gt=0, le=60, description="simulated time of --quick [s]")

    @field_validator("line_spacing")
    @classmethod
    def _line_spacing(cls, v, info: ValidationInfo):
        from planner.exploration.surface.result import check_line_spacing

        if v is not None and "tip_radius" in info.data:
            _invalid_as_value_error(check_line_spacing, v, info.data["tip_radius"])
        return v

    @field_validator("duration")
    @classmethod
    def _duration(cls, v):
        from planner.exploration.surface.result import check_duration

        _invalid_as_value_error(check_duration, v)
        return v

    @field_validator("region")
    @classmethod
    def _region(cls, v, info: ValidationInfo):
        (u0, u1), (v0, v1) = v
        if not (u0 < u1 and v0 < v1):
            raise ValueError("expected [[u0, u1], [v0, v1]] with u0 < u1 and v0 < v1 [m]")
        if "plate" in info.data and "tip_radius" in info.data:
            _reach(info.data["plate"], info.data["tip_radius"], v, None, 0.3)
        return v

    @field_validator("goal")
    @classmethod
    def _goal(cls, v, info: ValidationInfo):
        if v is not None and {"plate", "tip_radius", "region"} <= set(info.data):
            _reach(info.data["plate"], info.data["tip_radius"], info.data["region"], v, 0.3)
        return v

    @model_validator(mode="after")
    def _force_and_goal(self):
        if self.strategy == "bug2" and self.goal is None:
            # a rule across keys: its message starts with a key of the file, which locates it
            raise ValueError("strategy: bug2 needs a goal [u, v] [m] (add the key goal)")
        if self.identify == "raster" and self.strategy != "raster":
            raise ValueError(
                f"identify: raster pattern-matches the raster's lines and needs strategy "
                f"raster, got strategy {self.strategy}"
            )
        _reach(self.plate, self.tip_radius, self.region, None, self.normal_force)
        return self


def _invalid_as_value_error(check, *args) -> None:
    """Run a library check; its InvalidParameter as the ValueError a field validator
    raises (the message starts with the key; the framework drops the repeated key)."""
    from planner.errors import InvalidParameter

    try:
        check(*args)
    except InvalidParameter as exc:
        raise ValueError(str(exc)) from None


def _reach(plate, tip_radius, region, goal, normal_force) -> None:
    """Reach and force checks as a ValueError. Its message starts with the key it is about
    (``region: ...``): in a model-level rule that locates it; in that key's own field
    validator the framework drops the repeated key (:func:`planner.scenario.validate`)."""
    from planner.errors import InvalidParameter

    try:
        _check(plate, tip_radius, region, goal, normal_force)
    except InvalidParameter as exc:
        raise ValueError(str(exc)) from None


def run(config: Config, ctx):
    """Explore the plate; metrics, arrays, events and figures of the run."""
    from planner.kinds._explore_report import report

    return report(config, ctx)
