"""Scenario kind ``trace``: a spherical fingertip over a 2-D profile (§3.2.1, §3.4.1, Fig. 3.9).

The fingertip-centre path (traced curve) is simulated exactly, sampled at equal arclength,
corrupted with Gaussian noise, smoothed, and turned back into an estimate of the object
surface (eq. 3.11). Metrics compare the estimate with the true profile over the part of it the
fingertip can touch.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from pydantic import Field, model_validator

from planner.kinds._profiles import ProfileSpec, build_profile
from planner.results import Event, RunResult
from planner.scenario import ScenarioBase, StrictModel

# The simulator samples the traced curve 4x finer than the measurement, and the curve
# construction takes at most 2 M samples (planner.geometry.curves.MAX_SAMPLES): 500 000.
MAX_SAMPLES = 500_000


class Sampling(StrictModel):
    """Where the fingertip centre is sampled: give ``spacing``, or ``samples``, or
    ``speed`` with ``rate``."""

    spacing: float | None = Field(None, gt=0, description="along the traced curve [m]")
    samples: int | None = Field(
        None, ge=2, le=MAX_SAMPLES, description="number of samples over the trace"
    )
    speed: float | None = Field(None, gt=0, description="finger speed [m/s]")
    rate: float | None = Field(None, gt=0, description="sample rate [Hz]")

    @model_validator(mode="after")
    def _one_way(self):
        ways = [
            self.spacing is not None,
            self.samples is not None,
            self.speed is not None or self.rate is not None,
        ]
        if sum(ways) > 1:
            raise ValueError("give only one of spacing, samples, or speed+rate")
        if ways[2] and (self.speed is None or self.rate is None):
            raise ValueError("speed and rate go together")
        return self


class Noise(StrictModel):
    """Gaussian measurement noise (standard deviations)."""

    center_sigma: float = Field(0.0, ge=0, le=0.01, description="fingertip centre, per axis [m]")
    contact_sigma: float = Field(0.0, ge=0, le=0.01, description="contact point, per axis [m]")
    normal_sigma_deg: float = Field(0.0, ge=0, le=90, description="contact normal [deg]")


class Smoothing(StrictModel):
    """Gaussian smoothing of the measured centres against sample index (App. B)."""

    # the filter's kernel spans 8 sigma + 1 samples: 1e9 asked numpy for 60 GB
    sigma_samples: float = Field(
        8.0, ge=0, le=1000, description="Gaussian sigma [samples]; 0: none"
    )


class Config(ScenarioBase):
    """A fingertip tracing a 2-D profile: traced, estimated curves and their errors."""

    kind: Literal["trace"]
    profile: ProfileSpec
    tip_radius: float = Field(..., gt=0, description="fingertip radius r_f [m]")
    sampling: Sampling = Field(default_factory=Sampling)
    noise: Noise = Field(default_factory=Noise)
    smoothing: Smoothing = Field(default_factory=Smoothing)

    @model_validator(mode="after")
    def _buildable(self):
        from planner.errors import HapexError

        try:
            profile = build_profile(self.profile)
        except HapexError as exc:
            raise ValueError(f"profile: {exc}") from None
        s = self.sampling
        spacing = (
            s.spacing
            if s.spacing is not None
            else (s.speed / s.rate if s.speed is not None and s.rate is not None else None)
        )
        if spacing is not None and spacing > profile.length / 2:
            raise ValueError(
                f"sampling: a spacing of {spacing:g} m gives fewer than 3 samples "
                f"over a profile {profile.length:g} m long"
            )
        if spacing is not None and profile.length / spacing > MAX_SAMPLES:
            raise ValueError(
                f"sampling: a spacing of {spacing:g} m gives more than {MAX_SAMPLES} samples "
                f"over a profile {profile.length:g} m long; expected a spacing >= "
                f"{profile.length / MAX_SAMPLES:g} m"
            )
        return self


def _spacing(cfg: Config, traced_length: float) -> float:
    s = cfg.sampling
    if s.spacing is not None:
        return s.spacing
    if s.samples is not None:
        return traced_length / (s.samples - 1)
    if s.speed is not None:
        return s.speed / s.rate
    return cfg.tip_radius / 100.0


def end_cap_samples(sigma_samples: float) -> int:
    """Samples at each end of an open trace whose estimate is not trusted (the end caps).

    The Gaussian smoothing (``scipy.ndimage.gaussian_filter1d``, ``mode="nearest"``) reaches
    ``int(4 sigma + 0.5)`` samples to each side; within that many samples of an end it
    averages copies of the last sample, which bends the smoothed path and sweeps the estimate
    along an arc of radius r_f about the trace's end (5 mm off on ``wire_on_incline``).
    """
    return int(4.0 * sigma_samples + 0.5) if sigma_samples > 0 else 0


def in_end_caps(source: np.ndarray, n: int, cap: int) -> np.ndarray:
    """Which estimated points come from the first or last ``cap`` of ``n`` centres."""
    src = np.asarray(source)
    return (src >= 0) & ((src < cap) | (src >= n - cap))


def _detect(meas, tip_radius: float) -> list:
    """Curvature features detected in the noisy data (``planner.detection``, its default
    algorithm: the curvature of the fingertip-centre path), for the metrics and the figure."""
    from planner.detection import detect_features

    return list(detect_features(meas.centers, tip_radius, normals=meas.normals))


def _rms(err: np.ndarray) -> float:
    return float(np.sqrt(np.mean(err**2))) if len(err) else 0.0


@dataclass(frozen=True)
class _Curves:
    """The noise-free curves of the profile for the fingertip."""

    profile: object
    parallel: object
    traced: object
    estimated: object


def _exact_curves(cfg: Config, ctx) -> _Curves:
    from planner.geometry import curves

    r = cfg.tip_radius
    profile = build_profile(cfg.profile)
    with ctx.timer("curves"):
        parallel = curves.parallel_curve(profile, r)
        traced = curves.traced_curve(profile, r)
        estimated = curves.estimated_curve(traced, r)
    return _Curves(profile, parallel, traced, estimated)


def _measure(cfg: Config, ctx, c: _Curves):
    """Sample the traced curve with noise (``FingertipTrace``); the spacing used [m]."""
    from planner.geometry.measurement import simulate_trace

    total = float(c.traced.s[-1])
    spacing = _spacing(cfg, total)
    if total / spacing + 1 < 2:  # the Config rules this out; kept as a guard (bad input)
        from planner.errors import InputIssue, ScenarioError

        raise ScenarioError(
            [
                InputIssue(
                    "(scenario)",
                    0,
                    "sampling",
                    f"gives {total / spacing + 1:.1f} samples over a {total:.4g} m trace; "
                    "need at least 2",
                )
            ]
        )
    if ctx.quick:
        spacing = max(spacing, total / 2000)
    with ctx.timer("measurement"):
        meas = simulate_trace(
            c.profile,
            cfg.tip_radius,
            spacing=spacing,
            center_sigma=cfg.noise.center_sigma,
            contact_sigma=cfg.noise.contact_sigma,
            normal_sigma=np.deg2rad(cfg.noise.normal_sigma_deg),
            speed=cfg.sampling.speed,
            rng=ctx.rng,
        )
    return meas, spacing


def _estimate(cfg: Config, ctx, c: _Curves, meas) -> dict:
    """Smooth the measured centres, estimate the surface (eq. 3.11) and its errors [m]."""
    from scipy.ndimage import gaussian_filter1d

    from planner.geometry import curves

    r, profile = cfg.tip_radius, c.profile
    with ctx.timer("estimation"):
        sig = cfg.smoothing.sigma_samples
        smooth = (
            gaussian_filter1d(meas.centers, sig, axis=0, mode="nearest")
            if sig > 0
            else meas.centers
        )
        est_meas = curves.estimated_curve(smooth, r, closed=profile.closed)
        exact = c.estimated.points[~c.estimated.unobservable]
        err_exact = curves.distance_to_profile(exact, profile)
        cap = end_cap_samples(sig) if not profile.closed else 0
        in_cap = in_end_caps(est_meas.source, len(meas.t), cap)
        obs_m = ~est_meas.unobservable
        err_meas = curves.distance_to_profile(est_meas.points[obs_m & ~in_cap], profile)
        err_caps = curves.distance_to_profile(est_meas.points[obs_m & in_cap], profile)
    return {
        "smooth": smooth,
        "estimated": est_meas,
        "metrics": {
            "rms_error_exact_m": _rms(err_exact),
            "end_cap_samples": cap,
            "rms_error_without_end_caps_m": _rms(err_meas),
            "max_error_without_end_caps_m": float(err_meas.max()) if len(err_meas) else 0.0,
            "max_error_end_caps_m": float(err_caps.max()) if len(err_caps) else 0.0,
        },
    }


def _metrics(c: _Curves, meas, spacing: float, est: dict, features, detected) -> dict:
    traced = c.traced
    err_traced = np.linalg.norm(meas.centers - meas.true_centers, axis=1)
    return {
        "samples": len(meas.t),
        "spacing_m": spacing,
        "duration_s": float(meas.t[-1]),
        "profile_length_m": c.profile.length,
        "traced_length_m": float(traced.s[-1]),
        "interference_points": traced.interference_points.tolist(),
        "interference_count": len(traced.interference_points),
        "caustic_count": len(c.parallel.caustic_points),
        "unobservable_length_m": traced.unobservable_length,
        "estimated_unobservable_length_m": c.estimated.unobservable_length,
        **est["metrics"],
        "center_noise_rms_m": float(np.sqrt(np.mean(err_traced**2))),
        "curvature_features": [
            {"sign": f.sign, "start_m": f.start, "end_m": f.end, "position": list(f.position)}
            for f in features
        ],
        "detected_features": [
            {"sign": int(f.sign), "position": np.asarray(f.position, float).tolist()}
            for f in detected
        ],
    }


def _arrays(c: _Curves, meas, est: dict, smp) -> dict:
    return {
        "profile_points": smp.points,
        "profile_curvature": smp.curvature,
        "parallel_points": c.parallel.points,
        "caustic_points": c.parallel.caustic_points,
        "traced_points": c.traced.points,
        "interference_points": c.traced.interference_points,
        "estimated_points": c.estimated.points,
        "estimated_unobservable": c.estimated.unobservable,
        "t": meas.t,
        "centers": meas.centers,
        "true_centers": meas.true_centers,
        "contacts": meas.contacts,
        "normals": meas.normals,
        "centers_smoothed": est["smooth"],
        "estimated_measured_points": est["estimated"].points,
    }


def _figures(cfg: Config, c: _Curves, meas, est: dict, smp, features, detected) -> dict:
    from planner.geometry.plots import curves_figure, trace_figure

    trace = trace_figure(
        f"{cfg.name}: {cfg.description}" if cfg.description else cfg.name,
        smp.points,
        meas.centers,
        est["smooth"],
        est["estimated"].points,
        cfg.tip_radius,
        c.profile.closed,
        meas.true_centers[len(meas.t) // 3],
        detected=[(f.sign, np.asarray(f.position, float)) for f in detected],
        truth=[(f.sign, np.asarray(f.position, float)) for f in features],
    )
    curves = curves_figure(cfg.name, smp.points, c.parallel, c.traced, c.estimated)
    return {"trace": trace, "curves": curves}


def run(cfg: Config, ctx) -> RunResult:
    """Simulate, measure, estimate, detect; metrics, arrays and figures of one trace."""
    c = _exact_curves(cfg, ctx)
    meas, spacing = _measure(cfg, ctx, c)
    est = _estimate(cfg, ctx, c, meas)
    features = c.profile.curvature_features(cfg.tip_radius)
    with ctx.timer("detection"):
        detected = _detect(meas, cfg.tip_radius)
    events = [
        Event(
            "interference",
            f"interference point at {p.round(6).tolist()} m",
            data={"point": p.tolist()},
        )
        for p in c.traced.interference_points
    ]
    smp = c.profile.sample(c.profile.length / 4000.0)
    return RunResult(
        status="ok",
        metrics=_metrics(c, meas, spacing, est, features, detected),
        arrays=_arrays(c, meas, est, smp),
        events=events,
        figures=_figures(cfg, c, meas, est, smp, features, detected) if ctx.plots else {},
    )
