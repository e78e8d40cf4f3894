"""Scenario kind ``filter_study``: rate noise-type smoothing filters as App. B.4 does — the
false positives plus false negatives of the App. B.2 detection scheme — over a grid of
filters x windows x sigmas, on simulated data shaped like App. B's (a 0.65 mm wire across an
inclined plane: three curvature features, position noise ~1e-4 m).

Keys (besides name/kind/description/seed/output):

- ``tip_radius`` [m]; ``profile``: the open profile traced (the ``trace`` kind's block);
  ``spacing`` [m] between samples; ``speed`` [m/s]; ``noise_sigma`` [m];
- ``repeats``: noise realisations per setting;
- ``filters``, ``windows`` [samples], ``sigmas`` [samples] (Gaussian),
  ``dual_point_iterations``;
- ``decimate`` (App. B.2 step 2), ``curvature_sigma`` [samples] (step 5),
  ``tolerance`` [m] (match distance along the path; default r_f/2).

Metrics state what they compare: ``<filter>_best_errors`` is a filter's fewest errors per
trace over the grid; ``<filter>_thesis_region_errors`` its fewest inside the settings App. B.4
recommends, and ``<filter>_thesis_region_within_half_error`` whether those are within 0.5
errors per trace of its best (the thesis' region is as good as any for that filter);
``gaussian_beats_wiener`` whether the Gaussian filter's best is at most the Wiener filter's
(App. B.4 ranks the Gaussian first).
"""

from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from pydantic import Field, field_validator, model_validator

from planner.kinds._profiles import ProfileSpec, WireSpec, build_profile
from planner.results import RunResult
from planner.scenario import ScenarioBase

FilterName = Literal["none", "average", "median", "dual_point", "gaussian", "wiener"]


class Config(ScenarioBase):
    """Compare smoothing filters on simulated fingertip data (App. B.4)."""

    kind: Literal["filter_study"]
    tip_radius: float = Field(0.01, gt=0, le=1.0, description="fingertip radius r_f [m]")
    profile: ProfileSpec = Field(
        default_factory=lambda: WireSpec(type="wire", diameter=0.00065, angle_deg=45, length=0.04),
        description="open profile traced (App. B: a 0.65 mm wire across a 45 deg plane)",
    )
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
    windows: tuple[Annotated[int, Field(ge=1, le=10_000)], ...] = Field(
        (5, 10, 15, 20, 25, 30, 35, 40, 50), min_length=1, description="windows [samples]"
    )
    sigmas: tuple[Annotated[float, Field(gt=0, le=10_000)], ...] = Field(
        (2, 3, 5, 8, 10, 15), min_length=1, description="Gaussian sigmas [samples]"
    )
    dual_point_iterations: tuple[Annotated[int, Field(ge=1, le=20)], ...] = Field(
        (1, 2, 3, 4), min_length=1, description="dual-point corner-cutting passes"
    )
    decimate: int = Field(1, ge=1, le=100, description="App. B.2 step 2: keep every n-th")
    curvature_sigma: float = Field(
        2.0, ge=0, le=50, description="App. B.2 step 5: curvature smoothing [samples]"
    )
    tolerance: float | None = Field(
        None, gt=0, le=1.0, description="match distance along the path [m]"
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
            raise ValueError(f"a closed profile ({spec.type!r}) cannot be traced end to end")
        return spec

    @model_validator(mode="after")
    def _sampling(self) -> Config:
        r = self.tip_radius
        if self.spacing > r / 5:
            raise ValueError(
                f"spacing {self.spacing:g} m must be <= tip_radius / 5 = {r / 5:g} m "
                "(at least 5 samples per tip radius)"
            )
        if "gaussian" in self.filters and not self.sigmas:
            raise ValueError("sigmas: the gaussian filter needs at least one sigma")
        return self


#: the best settings App. B.4 reports
THESIS_GAUSSIAN = {"windows": (25, 40), "sigmas": (5, 10)}
THESIS_WIENER = {"windows": (35, 40)}


def _table(scores) -> str:
    rows = ["filter,window,sigma,fp,fn,errors"]
    for s in scores:
        sg = "" if s.setting.sigma is None else f"{s.setting.sigma:g}"
        rows.append(
            f"{s.setting.method},{s.setting.window},{sg},{s.fp:.3f},{s.fn:.3f},{s.errors:.3f}"
        )
    return "\n".join(rows) + "\n"


def _traces(config, ctx, repeats: int) -> list:
    """``repeats`` noisy traces of the profile with the times of their observable truth."""
    from planner.detection.filter_study import StudyTrace
    from planner.geometry.measurement import simulate_trace

    profile = build_profile(config.profile)
    out = []
    for _ in range(repeats):
        tr = simulate_trace(
            profile,
            config.tip_radius,
            spacing=config.spacing,
            speed=config.speed,
            center_sigma=config.noise_sigma,
            rng=ctx.rng,
        )
        out.append(
            StudyTrace(
                tr.t,
                tr.centers,
                tuple(f.sign for f in tr.truth.observable),
                tuple(float(x) for x in tr.t[tr.truth.observable_index]),
            )
        )
    return out


def _per_filter(config, scores, metrics: dict) -> dict:
    """Each filter's best setting over the grid (metrics ``<filter>_best_*``)."""
    per = {}
    for m in config.filters:
        b = min((s for s in scores if s.setting.method == m), key=lambda s: s.errors)
        per[m] = b
        metrics[f"{m}_best_window"] = b.setting.window
        metrics[f"{m}_best_sigma"] = b.setting.sigma
        metrics[f"{m}_best_errors"] = b.errors
    return per


def _thesis_flags(scores, per: dict, metrics: dict) -> None:
    """Compare with App. B.4 (module docstring: what each flag compares)."""
    (w0, w1), (s0, s1) = THESIS_GAUSSIAN["windows"], THESIS_GAUSSIAN["sigmas"]
    regions = {
        "gaussian": lambda s: w0 <= s.setting.window <= w1 and s0 <= s.setting.sigma <= s1,
        "wiener": lambda s: (
            THESIS_WIENER["windows"][0] <= s.setting.window <= THESIS_WIENER["windows"][1]
        ),
    }
    for name, inside in regions.items():
        errs = [s.errors for s in scores if s.setting.method == name and inside(s)]
        if errs:
            metrics[f"{name}_thesis_region_errors"] = min(errs)
            metrics[f"{name}_thesis_region_within_half_error"] = bool(
                min(errs) <= per[name].errors + 0.5
            )
    if "gaussian" in per and "wiener" in per:
        metrics["gaussian_beats_wiener"] = bool(per["gaussian"].errors <= per["wiener"].errors)


def run(config: Config, ctx) -> RunResult:
    """Simulate the traces, rate every filter setting, report the best ones."""
    from planner.detection.filter_study import grid, rate_filters

    r = float(config.tip_radius)
    windows, sigmas, repeats = config.windows, config.sigmas, config.repeats
    if ctx.quick:
        windows = tuple(w for w in windows if w in (10, 25, 40)) or windows[:2]
        sigmas = tuple(s for s in sigmas if s in (3, 8)) or sigmas[:1]
        repeats = 1
    with ctx.timer("simulate"):
        traces = _traces(config, ctx, repeats)
    settings = grid(config.filters, windows, sigmas, config.dual_point_iterations)
    tol_t = (config.tolerance or r / 2) / config.speed
    with ctx.timer("rate"):
        scores = rate_filters(
            traces,
            settings,
            r,
            tol_t,
            decimate=config.decimate,
            curvature_sigma=config.curvature_sigma,
        )
    best = min(scores, key=lambda s: s.errors)
    metrics: dict = {
        "n_settings": len(scores),
        "repeats": repeats,
        "n_samples": int(traces[0].t.size),
        "n_true_features": len(traces[0].truth_signs),
        "best_filter": best.setting.method,
        "best_window": best.setting.window,
        "best_sigma": best.setting.sigma,
        "best_errors": best.errors,
    }
    _thesis_flags(scores, _per_filter(config, scores, metrics), metrics)
    arrays = {
        "errors": np.array([s.errors for s in scores]),
        "fp": np.array([s.fp for s in scores]),
        "fn": np.array([s.fn for s in scores]),
        "window": np.array([s.setting.window for s in scores]),
        "sigma": np.array([np.nan if s.setting.sigma is None else s.setting.sigma for s in scores]),
    }
    figures = {}
    if ctx.plots:
        with ctx.timer("plots"):
            from planner.detection.plots import filter_errors_figure

            figures["filter_errors"] = filter_errors_figure(config.filters, scores, windows, sigmas)
    return RunResult(
        status="ok",
        metrics=metrics,
        arrays=arrays,
        figures=figures,
        files={"filter_study.csv": _table(scores)},
    )


__all__ = ["Config", "run"]
