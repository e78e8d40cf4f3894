"""Scenario kind ``filter_study``: rate noise-type smoothing filters as App. B.4 does — the
false positives plus false negatives of the App. B.2 detection scheme — over a grid of
filters x windows x sigmas, on simulated data shaped like App. B's (a 0.65 mm wire across an
inclined plane: three curvature features, position noise ~1e-4 m).

Keys (besides name/kind/description/seed/output):

- ``tip_radius`` [m]; ``shape``/``size_mm``/``angle_deg``/``length`` as in ``detect``'s
  ``simulation``; ``spacing`` [m] between samples; ``speed`` [m/s]; ``noise_sigma`` [m];
- ``repeats``: noise realisations per setting;
- ``filters``, ``windows`` [samples], ``sigmas`` [samples] (Gaussian),
  ``dual_point_iterations``;
- ``decimate`` (App. B.2 step 2), ``curvature_sigma`` [samples] (step 5),
  ``tolerance`` [m] (match distance along the path; default r_f/2).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from planner.scenario import ScenarioBase

FilterName = Literal["none", "average", "median", "dual_point", "gaussian", "wiener"]


class Config(ScenarioBase):
    """Compare smoothing filters on simulated fingertip data (App. B.4)."""

    kind: Literal["filter_study"]
    tip_radius: float = Field(0.01, gt=0, le=1.0, description="fingertip radius r_f [m]")
    shape: Literal["wire", "step", "ridge", "ravine", "pit"] = Field(
        "wire", description="feature on the plane (App. B: a 0.65 mm wire)"
    )
    size_mm: float = Field(0.65, ge=-50, le=50, description="feature size [mm]")
    width_mm: float = Field(4.0, gt=0, le=100, description="ridge/ravine/pit width [mm]")
    angle_deg: float = Field(45.0, ge=-90, le=90, description="plane inclination [deg]")
    length: float = Field(0.02, gt=0, le=1.0, description="plane on each side [m]")
    spacing: float = Field(
        2e-4, gt=0, le=0.01, description="arclength between samples [m] (0.03 m/s at 150 Hz)"
    )
    speed: float = Field(0.03, gt=0, le=10.0, description="fingertip speed [m/s]")
    noise_sigma: float = Field(
        1e-4, ge=0, le=0.01, description="position noise, 1 sigma per axis [m] (Table B.1)"
    )
    repeats: int = Field(4, ge=1, le=100, description="noise realisations per setting")
    filters: tuple[FilterName, ...] = Field(
        ("none", "average", "median", "dual_point", "gaussian", "wiener"),
        min_length=1,
        description="filters to compare",
    )
    windows: tuple[int, ...] = Field(
        (5, 10, 15, 20, 25, 30, 35, 40, 50), min_length=1, description="windows [samples]"
    )
    sigmas: tuple[float, ...] = Field(
        (2, 3, 5, 8, 10, 15), min_length=1, description="Gaussian sigmas [samples]"
    )
    dual_point_iterations: tuple[int, ...] = Field(
        (1, 2, 3, 4), min_length=1, description="dual-point corner-cutting passes"
    )
    decimate: int = Field(1, ge=1, le=100, description="App. B.2 step 2: keep every n-th")
    curvature_sigma: float = Field(
        2.0, ge=0, le=50, description="App. B.2 step 5: curvature smoothing [samples]"
    )
    tolerance: float | None = Field(
        None, gt=0, le=1.0, description="match distance along the path [m]"
    )


def run(config: Config, ctx):
    """Run the ``filter_study`` scenario (see the module docstring)."""
    from planner.detection.kind_filter_study import run_filter_study

    return run_filter_study(config, ctx)
