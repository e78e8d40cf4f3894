"""Scenario kind ``detect``: curvature and macro features from a fingertip trace, simulated
(with ground truth and scoring) or read from a user's CSV/NPZ log (thesis §3.3-3.4).

Keys (besides name/kind/description/seed/output):

- ``tip_radius`` [m]: fingertip radius r_f.
- ``simulation``: a fingertip tracing a feature on an inclined plane (``shape`` and its
  sizes) or any open profile of the catalogue (``profile``, the block of the ``trace`` kind);
  see ``Simulation``. Or
- ``data_file``: a CSV/NPZ trace (format in :mod:`planner.detection.datafile`), relative to
  the scenario file. Exactly one of the two.
- ``algorithms``: which algorithms of Fig. 3.8 to run (default all four; 1 needs contacts,
  2 needs normals or contacts).
- ``smoothing_scale`` [m]: Gaussian smoothing along the path (default: from the data's noise).
- ``tolerance`` [m]: matching distance for scoring (default r_f/2).
- ``multiscale_radii`` [m]: virtual fingertip radii r_i >= r_f for re-detection (§3.2.2).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, field_validator, model_validator

from planner.kinds._profiles import ProfileSpec, build_profile
from planner.scenario import ScenarioBase, StrictModel

#: keys of the feature-on-a-plane surface, replaced by ``profile`` when that is given
SHAPE_KEYS = ("shape", "size_mm", "width_mm", "angle_deg", "length")


class Simulation(StrictModel):
    """A fingertip tracing a surface with Gaussian sensor noise: a feature on an inclined
    plane (``shape`` and its sizes), or an open ``profile`` of the catalogue (the ``trace``
    kind's block; ground truth from its exact curvature features)."""

    profile: ProfileSpec | None = Field(
        None, description="open 2-D profile to trace instead of shape/size_mm/.../length"
    )

    shape: Literal["plane", "wire", "step", "ridge", "ravine", "pit"] = Field(
        "wire", description="feature on the plane"
    )
    size_mm: float = Field(
        0.65,
        ge=-50,
        le=50,
        description=(
            "wire diameter, step height (negative: step down), ridge height, ravine or pit "
            "depth [mm]"
        ),
    )
    width_mm: float = Field(4.0, gt=0, le=100, description="ridge/ravine width, pit diameter [mm]")
    angle_deg: float = Field(45.0, ge=-90, le=90, description="inclination of the plane [deg]")
    length: float = Field(
        0.03, gt=0, le=1.0, description="length of plane on each side of the feature [m]"
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

        if spec is None:
            return spec
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

    @model_validator(mode="after")
    def _profile_or_shape(self) -> Simulation:
        both = [k for k in SHAPE_KEYS if k in self.model_fields_set]
        if self.profile is not None and both:
            keys = ", ".join(f"'{k}'" for k in both)
            raise ValueError(
                f"give either 'profile' or the shape keys, not both: 'profile' was given "
                f"with {keys} (the profile block sets the whole surface)"
            )
        return self


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
    def _one_source(self) -> Config:
        if (self.simulation is None) == (self.data_file is None):
            raise ValueError("give exactly one of 'simulation' and 'data_file'")
        bad = [r for r in self.multiscale_radii if not r >= self.tip_radius]
        if bad:
            raise ValueError(
                f"multiscale_radii {bad} must each be >= tip_radius {self.tip_radius} [m] (§3.2.2)"
            )
        if self.simulation is not None and self.simulation.profile is None:
            s = self.simulation
            if s.shape == "pit" and not 0 < s.size_mm <= s.width_mm / 2:
                raise ValueError("simulation: a pit needs 0 < size_mm <= width_mm / 2")
            if s.shape in ("wire", "ridge", "ravine") and not s.size_mm > 0:
                raise ValueError(f"simulation: size_mm must be > 0 for a {s.shape}")
        return self


def run(config: Config, ctx):
    """Run the ``detect`` scenario (see the module docstring)."""
    from planner.detection.kind_detect import run_detect

    return run_detect(config, ctx)
