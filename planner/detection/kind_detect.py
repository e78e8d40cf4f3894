"""The runner of the ``detect`` scenario kind (:mod:`planner.kinds.detect`)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from planner.detection.algorithms import curvature_signal, features_from_signal
from planner.detection.datafile import read_trace_file
from planner.detection.macro import macro_features
from planner.detection.multiscale import detect_multiscale
from planner.detection.scoring import score_features
from planner.detection.synthetic import Shape, simulate
from planner.errors import HapexError
from planner.results import Event, RunResult


def _signs(feats) -> str:
    return "".join("+" if f.sign > 0 else "-" for f in feats)


def _load(config, ctx):
    """(t, centers, contacts, normals, synthetic trace or None)."""
    sim = config.simulation
    if sim is not None and sim.profile is not None:
        from planner.detection.profile_trace import simulate_profile
        from planner.kinds._profiles import build_profile

        tr = simulate_profile(
            build_profile(sim.profile),
            config.tip_radius,
            spacing=sim.spacing,
            speed=sim.speed,
            center_sigma=sim.center_sigma,
            contact_sigma=sim.contact_sigma,
            normal_sigma=np.deg2rad(sim.normal_sigma_deg),
            rng=ctx.rng,
        )
        return tr.t, tr.centers, tr.contacts, tr.normals, tr
    if sim is not None:
        shape = Shape(
            kind=sim.shape,
            size=sim.size_mm * 1e-3,
            width=sim.width_mm * 1e-3,
            angle=np.deg2rad(sim.angle_deg),
            length=sim.length,
        )
        tr = simulate(
            shape,
            config.tip_radius,
            spacing=sim.spacing,
            speed=sim.speed,
            center_sigma=sim.center_sigma,
            contact_sigma=sim.contact_sigma,
            normal_sigma=np.deg2rad(sim.normal_sigma_deg),
            rng=ctx.rng,
        )
        return tr.t, tr.centers, tr.contacts, tr.normals, tr
    path = Path(config.data_file)
    if not path.is_absolute():
        path = Path(ctx.base_dir) / path
    data = read_trace_file(path)
    return data.t, data.centers, data.contacts, data.normals, data


def _noise_table(t, centers, signals, feats, r) -> dict:
    """App. B.1 noise analysis (Table B.1) of each coordinate of the fingertip centres over
    the longest stretch at least r_f away from every detected feature."""
    from planner.detection.noise import noise_analysis

    alg = 3 if 3 in signals else next(iter(signals))
    sig = signals[alg]
    blocked = [(f.start - r, f.end + r) for fs in feats.values() for f in fs]
    s_raw = np.interp(np.arange(len(t)), sig.index, sig.s)
    free = np.ones(len(t), dtype=bool)
    for a, b in blocked:
        free &= ~((s_raw >= a) & (s_raw <= b))
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


def run_detect(config, ctx) -> RunResult:
    """Detect features with each requested algorithm; score them when the truth is known."""
    r = float(config.tip_radius)
    with ctx.timer("load"):
        t, centers, contacts, normals, src = _load(config, ctx)
    truth = getattr(src, "observable", None)
    events: list[Event] = []
    if getattr(src, "tip_radius", None) and abs(src.tip_radius - r) > 1e-9:
        events.append(
            Event(
                "tip_radius_mismatch",
                f"the data file says tip_radius={src.tip_radius} m; the scenario's {r} m is used",
            )
        )
    settings = {}
    if config.smoothing_scale is not None:
        settings["smoothing_scale"] = config.smoothing_scale
    tol = config.tolerance or r / 2
    metrics: dict = {
        "n_samples": int(len(t)),
        "tip_radius": r,
        "tolerance": tol,
        "duration_s": float(t[-1] - t[0]),
    }
    arrays: dict = {"t": t, "centers": centers}
    if contacts is not None:
        arrays["contacts"] = contacts
    if normals is not None:
        arrays["normals"] = normals
    signals, feats, scores, report = {}, {}, {}, {}
    with ctx.timer("detect"):
        for alg in config.algorithms:
            if alg == 1 and contacts is None:
                events.append(Event("skipped", "algorithm 1 needs contact points"))
                continue
            if alg == 2 and normals is None and contacts is None:
                events.append(Event("skipped", "algorithm 2 needs normals or contacts"))
                continue
            sig = curvature_signal(centers, r, alg, normals=normals, contacts=contacts, **settings)
            fs = features_from_signal(sig, sig.scale, r)
            macros = macro_features(fs, r)
            signals[alg], feats[alg] = sig, fs
            key = f"alg{alg}"
            metrics[f"{key}_n_features"] = len(fs)
            metrics[f"{key}_signs"] = _signs(fs)
            metrics[f"{key}_macro"] = [m.kind for m in macros]
            metrics[f"{key}_smoothing_scale_m"] = sig.scale
            arrays[f"{key}_s"] = sig.s
            arrays[f"{key}_curvature"] = sig.curvature
            arrays[f"{key}_features"] = np.array(
                [[f.sign, f.start, f.end, f.peak, f.peak_curvature] for f in fs]
            ).reshape(-1, 5)
            arrays[f"{key}_positions"] = np.array([f.position for f in fs]).reshape(
                -1, centers.shape[1]
            )
            if truth is not None:
                sc = score_features(fs, truth, tol)
                scores[alg] = sc
                for name in ("tp", "fp", "fn", "precision", "recall", "f1", "localization"):
                    metrics[f"{key}_{name}" + ("_m" if name == "localization" else "")] = getattr(
                        sc, name
                    )
            report[key] = {
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
    if scores:
        best = max(
            scores, key=lambda a: (scores[a].f1, -np.nan_to_num(scores[a].localization, nan=np.inf))
        )
        metrics["best_algorithm"] = int(best)
        metrics["truth_signs"] = _signs(truth)
        arrays["truth_positions"] = np.array([f.position for f in truth]).reshape(-1, 2)
        arrays["truth_signs"] = np.array([f.sign for f in truth])
    if signals:
        with ctx.timer("noise"):
            metrics.update(_noise_table(t, centers, signals, feats, r))
    if config.multiscale_radii:
        with ctx.timer("multiscale"):
            ms = detect_multiscale(centers, r, config.multiscale_radii, **settings)
        for ri, fs in ms.items():
            metrics[f"multiscale_{ri * 1e3:g}mm_signs"] = _signs(fs)
            metrics[f"multiscale_{ri * 1e3:g}mm_macro"] = [m.kind for m in macro_features(fs, ri)]
    figures = {}
    if ctx.plots and signals:
        from planner.detection.plots import signal_figure, trace_figure

        with ctx.timer("plots"):
            figures["trace"] = trace_figure(
                centers,
                {a: s.surface for a, s in signals.items()},
                feats,
                r,
                profile=getattr(src, "profile", None),
                truth=truth,
                title=f"{config.name}: features (truth: black dots)",
            )
            figures["curvature"] = signal_figure(
                signals, feats, title=f"{config.name}: curvature signals"
            )
    return RunResult(
        status="ok",
        metrics=metrics,
        arrays=arrays,
        events=events,
        figures=figures,
        files={"features.json": json.dumps(report, indent=1)},
    )
