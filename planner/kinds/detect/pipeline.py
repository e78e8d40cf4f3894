"""The run of the ``detect`` scenario kind: load or simulate the trace, detect with each
algorithm, score against the observable truth, noise analysis, multiscale re-detection,
figures."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from planner.detection import (
    CurvatureFeature,
    FingertipTrace,
    curvature_signal,
    detect_multiscale,
    macro_features,
    noise_analysis,
    read_trace_file,
    score_features,
    simulate_trace,
)
from planner.detection.algorithms import check_sampling, features_from_signal
from planner.errors import HapexError, InputIssue, InvalidParameter, ScenarioError
from planner.geometry.features import sign_text
from planner.kinds._profiles import build_profile
from planner.results import Event, RunResult

SCORES = ("tp", "fp", "fn", "precision", "recall", "f1", "localization")


def _load(config, ctx) -> FingertipTrace:
    """The simulated trace, or the data file's (bad data -> ScenarioError, exit 2)."""
    sim = config.simulation
    if sim is not None:
        return simulate_trace(
            build_profile(sim.profile),
            config.tip_radius,
            spacing=sim.spacing,
            speed=sim.speed,
            center_sigma=sim.center_sigma,
            contact_sigma=sim.contact_sigma,
            normal_sigma=np.deg2rad(sim.normal_sigma_deg),
            rng=ctx.rng,
        )
    path = Path(config.data_file)
    if not path.is_absolute():
        path = Path(ctx.base_dir) / path
    data = read_trace_file(path)
    try:
        check_sampling(data.centers, config.tip_radius)
    except InvalidParameter as exc:
        raise ScenarioError([InputIssue(str(path), 0, "data_file", str(exc))]) from None
    return data


def _noise_table(t, centers, signals, feats, r) -> dict:
    """App. B.1 noise analysis (Table B.1) of each coordinate of the fingertip centres over
    the longest stretch at least r_f away from every detected feature."""
    alg = 3 if 3 in signals else next(iter(signals))
    sig = signals[alg]
    s_raw = np.interp(np.arange(len(t)), sig.index, sig.s)
    free = np.ones(len(t), dtype=bool)
    for f in (f for fs in feats.values() for f in fs):
        free &= ~((s_raw >= f.start - r) & (s_raw <= f.end + r))
    edges = np.flatnonzero(np.diff(np.concatenate([[0], free.astype(np.int8), [0]])))
    runs = list(zip(edges[::2], edges[1::2], strict=True))
    if not runs:
        return {}
    i0, i1 = max(runs, key=lambda ab: ab[1] - ab[0])
    if i1 - i0 < 40:
        return {}
    out: dict = {"noise_stretch_samples": int(i1 - i0)}
    for k, name in enumerate("xyz"[: centers.shape[1]]):
        try:
            na = noise_analysis(t[i0:i1], centers[i0:i1, k])
        except HapexError:
            continue
        out.update(
            {
                f"noise_{name}_mean_m": na.mean,
                f"noise_{name}_sigma_m": na.sigma,
                f"noise_{name}_chi2": na.chi2,
                f"noise_{name}_critical": na.critical,
                f"noise_{name}_normal": na.normal,
            }
        )
    return out


def _feature_report(fs: list[CurvatureFeature], macros) -> dict:
    return {
        "features": [
            {
                "sign": f.sign,
                "start": f.start,
                "end": f.end,
                "peak": f.peak,
                "position": np.asarray(f.position).tolist(),
                "peak_curvature": f.peak_curvature,
            }
            for f in fs
        ],
        "macro_features": [
            {
                "kind": m.kind,
                "signs": m.signs,
                "start": m.start,
                "end": m.end,
                "position": m.position.tolist(),
            }
            for m in macros
        ],
    }


def _skip_reason(alg: int, trace: FingertipTrace) -> str | None:
    if alg == 1 and trace.contacts is None:
        return "algorithm 1 needs contact points"
    if alg == 2 and trace.normals is None and trace.contacts is None:
        return "algorithm 2 needs normals or contacts"
    return None


def _detect_all(config, trace: FingertipTrace, out: dict) -> tuple[dict, dict, dict]:
    """Run each algorithm; fill ``out`` (metrics, arrays, events, report); return
    ``(signals, features, scores)`` by algorithm."""
    r = float(config.tip_radius)
    truth = None if trace.truth is None else trace.truth.observable
    tol = config.tolerance or r / 2
    signals, feats, scores = {}, {}, {}
    m, arrays = out["metrics"], out["arrays"]
    for alg in config.algorithms:
        reason = _skip_reason(alg, trace)
        if reason:
            out["events"].append(Event("skipped", reason))
            continue
        sig = curvature_signal(
            trace.centers,
            r,
            alg,
            normals=trace.normals,
            contacts=trace.contacts,
            smoothing_scale=config.smoothing_scale,
            material_side=config.material_side,
        )
        fs = features_from_signal(sig, sig.scale, r)
        macros = macro_features(fs, r)
        signals[alg], feats[alg] = sig, fs
        key = f"alg{alg}"
        m[f"{key}_n_features"] = len(fs)
        m[f"{key}_signs"] = sign_text([f.sign for f in fs])
        m[f"{key}_macro"] = [x.kind for x in macros]
        m[f"{key}_smoothing_scale_m"] = sig.scale
        arrays[f"{key}_s"] = sig.s
        arrays[f"{key}_curvature"] = sig.curvature
        arrays[f"{key}_features"] = np.array(
            [[f.sign, f.start, f.end, f.peak, f.peak_curvature] for f in fs]
        ).reshape(-1, 5)
        arrays[f"{key}_positions"] = np.array([f.position for f in fs]).reshape(
            -1, trace.centers.shape[1]
        )
        if truth is not None:
            sc = scores[alg] = score_features(fs, truth, tol)
            for name in SCORES:
                m[f"{key}_{name}" + ("_m" if name == "localization" else "")] = getattr(sc, name)
        out["report"][key] = _feature_report(fs, macros)
    return signals, feats, scores


def _best(scores: dict, truth, out: dict) -> None:
    best = max(
        scores, key=lambda a: (scores[a].f1, -np.nan_to_num(scores[a].localization, nan=np.inf))
    )
    out["metrics"]["best_algorithm"] = int(best)
    out["metrics"]["truth_signs"] = sign_text([f.sign for f in truth])
    out["arrays"]["truth_positions"] = np.array([f.position for f in truth]).reshape(-1, 2)
    out["arrays"]["truth_signs"] = np.array([f.sign for f in truth])


def _multiscale(config, trace: FingertipTrace, metrics: dict) -> tuple[dict, dict]:
    r = float(config.tip_radius)
    ms = detect_multiscale(
        trace.centers,
        r,
        config.multiscale_radii,
        smoothing_scale=config.smoothing_scale,
        material_side=config.material_side,
    )
    kinds = {}
    for ri, fs in ms.items():
        kinds[ri] = [m.kind for m in macro_features(fs, ri)]
        metrics[f"multiscale_{ri * 1e3:g}mm_signs"] = sign_text([f.sign for f in fs])
        metrics[f"multiscale_{ri * 1e3:g}mm_macro"] = kinds[ri]
    return ms, kinds


def _figures(config, trace, signals, feats, multiscale) -> dict:
    from planner.detection.plots import multiscale_figure, signal_figure, trace_figure

    r = float(config.tip_radius)
    truth = None if trace.truth is None else trace.truth.observable
    profile = None
    if trace.truth is not None:
        prof = trace.truth.profile
        profile = prof.sample(prof.length / 4000).points
    figures = {
        "trace": trace_figure(
            trace.centers,
            {a: s.surface for a, s in signals.items()},
            feats,
            r,
            profile=profile,
            truth=truth,
            title=f"{config.name}: features"
            + (" (truth: black dots)" if truth is not None else " (no ground truth)"),
        ),
        "curvature": signal_figure(signals, feats, title=f"{config.name}: curvature signals"),
    }
    if multiscale is not None:
        ms, kinds = multiscale
        alg = 3 if 3 in feats else next(iter(feats))
        figures["multiscale"] = multiscale_figure(
            {r: feats[alg], **ms},
            {r: [m.kind for m in macro_features(feats[alg], r)], **kinds},
            title=f"{config.name}: features by fingertip radius (r_f = {r * 1e3:g} mm: "
            f"algorithm {alg}; larger: virtual fingertips, §3.2.2)",
        )
    return figures


def run(config, ctx) -> RunResult:
    """Detect features with each requested algorithm; score them when the truth is known."""
    r = float(config.tip_radius)
    with ctx.timer("load"):
        trace = _load(config, ctx)
    out: dict = {
        "metrics": {
            "n_samples": int(len(trace.t)),
            "tip_radius": r,
            "tolerance": config.tolerance or r / 2,
            "duration_s": float(trace.t[-1] - trace.t[0]),
        },
        "arrays": {"t": trace.t, "centers": trace.centers},
        "events": [],
        "report": {},
    }
    if trace.tip_radius and abs(trace.tip_radius - r) > 1e-9:
        out["events"].append(
            Event(
                "tip_radius_mismatch",
                f"the data file says tip_radius={trace.tip_radius} m; the scenario's {r} m is used",
            )
        )
    for name in ("contacts", "normals"):
        if getattr(trace, name) is not None:
            out["arrays"][name] = getattr(trace, name)
    with ctx.timer("detect"):
        signals, feats, scores = _detect_all(config, trace, out)
    if scores:
        _best(scores, trace.truth.observable, out)
    if signals:
        with ctx.timer("noise"):
            out["metrics"].update(_noise_table(trace.t, trace.centers, signals, feats, r))
    multiscale = None
    if config.multiscale_radii:
        with ctx.timer("multiscale"):
            multiscale = _multiscale(config, trace, out["metrics"])
    figures = {}
    if ctx.plots and signals:
        with ctx.timer("plots"):
            figures = _figures(config, trace, signals, feats, multiscale)
    return RunResult(
        status="ok",
        metrics=out["metrics"],
        arrays=out["arrays"],
        events=out["events"],
        figures=figures,
        files={"features.json": json.dumps(out["report"], indent=1)},
    )


__all__ = ["run"]
