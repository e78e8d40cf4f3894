"""The ``detect`` scenario: its keys and every rule their values must satisfy.

Keys (besides name/kind/description/seed/output):

- ``tip_radius`` [m]: fingertip radius r_f.
- ``simulation``: a fingertip tracing an open ``profile`` (the block of the ``trace`` kind:
  ``{type: wire, diameter: 0.00065, angle_deg: 45}`` ...) with Gaussian sensor noise; see
  :class:`Simulation`. Or
- ``data_file``: a CSV/NPZ trace (format in :mod:`planner.detection.datafile`), relative to
  the scenario file. Exactly one of the two.
- ``algorithms``: which algorithms of Fig. 3.8 to run (default all four; 1 needs contacts,
  2 needs normals or contacts).
- ``material_side``: ``auto`` (from normals/contacts, else from the path), ``left`` or
  ``right`` of the direction of travel.
- ``smoothing_scale`` [m]: Gaussian smoothing along the path (default: from the data's noise).
- ``tolerance`` [m]: matching distance for scoring (default r_f/2).
- ``multiscale_radii`` [m]: virtual fingertip radii r_i >= r_f for re-detection (§3.2.2).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, field_validator, model_validator

from planner.kinds._profiles import ProfileSpec, build_profile
from planner.scenario import ScenarioBase, StrictModel

#: fewest samples per tip radius of travel (planner.detection.MIN_SAMPLES_PER_RADIUS)
SAMPLES_PER_RADIUS = 5


class Simulation(StrictModel):
    """A fingertip tracing an open profile of the catalogue from end to end, with Gaussian
    sensor noise; ground truth from the profile's exact curvature features."""

    profile: ProfileSpec = Field(
        ...,
        description="open 2-D profile to trace (plane, step, ridge, ravine, bump, pit, wire, "
        "cusp, polyline, open spline)",
    )
    spacing: float = Field(
        2e-5, gt=0, le=0.01, description="arclength between samples of the centre path [m]"
    )
    speed: float = Field(0.03, gt=0, le=10.0, description="fingertip speed [m/s]")
    center_sigma: float = Field(
        1e-4, ge=0, le=0.01, description="fingertip-centre noise, 1 sigma per axis [m]"
    )
    contact_sigma: float = Field(
        2.5e-4, ge=0, le=0.01, description="contact-point noise, 1 sigma per axis [m]"
    )
    normal_sigma_deg: float = Field(
        1.0, ge=0, le=30, description="contact-normal noise, 1 sigma [deg]"
    )

    @field_validator("profile")
    @classmethod
    def _open_profile(cls, spec):
        from planner.errors import HapexError

        try:
            closed = build_profile(spec).closed
        except HapexError as exc:
            raise ValueError(str(exc)) from None
        if closed:
            raise ValueError(
                f"a closed profile ({spec.type!r}) cannot be traced from end to end; use an "
                "open one: plane, step, ridge, ravine, bump, pit, wire, cusp, polyline, "
                "spline (closed: false)"
            )
        return spec


class Config(ScenarioBase):
    """Detect features in a fingertip trace."""

    kind: Literal["detect"]
    tip_radius: float = Field(..., gt=0, le=1.0, description="fingertip radius r_f [m]")
    simulation: Simulation | None = Field(None, description="simulate the trace")
    data_file: str | None = Field(
        None, min_length=1, description="CSV/NPZ trace, relative to the scenario"
    )
    algorithms: tuple[Literal[1, 2, 3, 4], ...] = Field(
        (1, 2, 3, 4), min_length=1, description="algorithms of thesis Fig. 3.8 to run"
    )
    material_side: Literal["auto", "left", "right"] = Field(
        "auto", description="side of travel where the object lies (auto: from the data)"
    )
    smoothing_scale: float | None = Field(
        None, gt=0, le=1.0, description="Gaussian smoothing scale [m] (default: from noise)"
    )
    tolerance: float | None = Field(
        None, gt=0, le=1.0, description="scoring match distance [m] (default r_f/2)"
    )
    multiscale_radii: tuple[float, ...] = Field(
        (), description="virtual fingertip radii r_i >= tip_radius for re-detection [m]"
    )

    @model_validator(mode="after")
    def _consistent(self) -> Config:
        r = self.tip_radius
        if (self.simulation is None) == (self.data_file is None):
            raise ValueError("give exactly one of 'simulation' and 'data_file'")
        bad = [x for x in self.multiscale_radii if not r <= x <= 1.0]
        if bad:
            raise ValueError(
                f"multiscale_radii {bad} must each be in [tip_radius, 1] = [{r:g}, 1] [m] "
                "(§3.2.2: only r_i >= r_f can be simulated)"
            )
        if self.smoothing_scale is not None and self.smoothing_scale > r:
            raise ValueError(
                f"smoothing_scale {self.smoothing_scale:g} m must be <= tip_radius {r:g} m "
                "(the default is about r_f/10)"
            )
        sim = self.simulation
        if sim is not None and sim.spacing > r / SAMPLES_PER_RADIUS:
            raise ValueError(
                f"simulation.spacing {sim.spacing:g} m must be <= tip_radius / "
                f"{SAMPLES_PER_RADIUS} = {r / SAMPLES_PER_RADIUS:g} m (at least "
                f"{SAMPLES_PER_RADIUS} samples per tip radius)"
            )
        return self


__all__ = ["Config", "Simulation"]
