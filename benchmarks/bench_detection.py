"""Benchmark of planner.detection: accuracy and speed of the four algorithms of Fig. 3.8.

Run: ``python benchmarks/bench_detection.py [--quick] [--out DIR]``. Writes
``bench_detection_accuracy`` and ``bench_detection_speed`` (CSV + Markdown).

Accuracy: seeded random surfaces from :mod:`planner.geometry.shapes` (wires 0.5-1.5 mm,
steps up/down 1-4 mm, rectangular ridges and ravines, arc pits, on planes inclined 0-60 deg,
r_f 5-15 mm), traced by :func:`planner.geometry.measurement.simulate_trace` at 20 um spacing
(0.03 m/s at 1.5 kHz) with Gaussian noise at 0, 0.5, 1 and 2 times the thesis' level
(centre 0.1 mm, contact 0.25 mm, normal 1 deg, 1 sigma). Each algorithm's features are
matched to the observable ground truth (same sign; same-sign features inside one
unobservable region, or passed within r_f/4, count once) at two tolerances: r_f/2 (does the
algorithm find the feature) and 0.3 mm (the localization goal: is it found *there*);
precision, recall, F1 (pooled counts) and the mean localization error of the r_f/2 matches,
for all features and per sign; ``recall_all_truth`` is the recall against every true feature
of the profile, seen or not.
Targets (issue #6), algorithm 3 at the thesis noise: F1 >= 0.95, localization <= 0.3 mm.

Speed: samples per second of ``detect_features`` per algorithm (warm: after one call) on a
trace that has features: tiles of a wire, a step up, a ridge and a step down (the thesis'
noise, 5 kHz at 0.03 m/s), traced end to end; the features each algorithm finds are
reported beside the time (target >= 2 M samples/s for algorithm 3).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _common import arg_parser, time_call, write_report  # noqa: E402

from planner.detection import detect_features, score_features  # noqa: E402
from planner.geometry import shapes  # noqa: E402
from planner.geometry.measurement import (  # noqa: E402
    THESIS_CENTER_SIGMA,
    THESIS_CONTACT_SIGMA,
    THESIS_NORMAL_SIGMA,
    simulate_trace,
)

SHAPES = ("wire", "step", "ridge", "ravine", "pit")
SPAN = 0.06  # length of each profile [m]
GOAL_TOL = 0.3e-3  # localization goal, the second matching tolerance [m]


def random_case(rng: np.random.Generator):
    """One random surface (kind, profile) and fingertip radius [m]."""
    kind = SHAPES[int(rng.integers(len(SHAPES)))]
    r = float(rng.uniform(5e-3, 15e-3))
    ang = float(np.deg2rad(rng.uniform(0, 60)))
    if kind == "wire":
        return kind, shapes.wire_on_plane(rng.uniform(0.5e-3, 1.5e-3), ang, 0.0, SPAN), r
    if kind == "step":
        prof = shapes.step(rng.choice([-1, 1]) * rng.uniform(1e-3, 4e-3), 0.0, SPAN)
    elif kind == "ridge":
        prof = shapes.ridge(rng.uniform(0.3, 1.0) * r, rng.uniform(1e-3, 3e-3), 0.0, 0.0, SPAN)
    elif kind == "ravine":
        prof = shapes.ravine(rng.uniform(0.6, 1.6) * r, rng.uniform(1e-3, 3e-3), 0.0, 0.0, SPAN)
    else:
        w = rng.uniform(0.6, 1.6) * r
        prof = shapes.pit(rng.uniform(0.15, 0.45) * w, w, "arc", 0.0, SPAN)
    return kind, prof.transformed(ang), r


def accuracy(n_cases: int, noises: list[float], seed: int = 0) -> list[dict]:
    """Pooled detection scores per (noise level, algorithm)."""
    rng = np.random.default_rng(seed)
    cases = [random_case(rng) for _ in range(n_cases)]
    rows = []
    for noise in noises:
        acc = {
            a: {
                "tp": 0,
                "fp": 0,
                "fn": 0,
                "loc": [],
                "loc+": [],
                "loc-": [],
                "tp+": 0,
                "fn+": 0,
                "tp-": 0,
                "fn-": 0,
            }
            for a in (1, 2, 3, 4)
        }
        kinds_f1 = {a: {k: [0, 0, 0] for k in SHAPES} for a in (1, 2, 3, 4)}
        for i, (kind, prof, r) in enumerate(cases):
            tr = simulate_trace(
                prof,
                r,
                spacing=2e-5,
                center_sigma=noise * THESIS_CENTER_SIGMA,
                contact_sigma=noise * THESIS_CONTACT_SIGMA,
                normal_sigma=noise * THESIS_NORMAL_SIGMA,
                rng=np.random.default_rng(seed * 100003 + i),
            )
            obs, exact = tr.truth.observable, tr.truth.features
            for a in (1, 2, 3, 4):
                fs = detect_features(tr.centers, r, a, normals=tr.normals, contacts=tr.contacts)
                sc = score_features(fs, obs, r / 2)
                goal = score_features(fs, obs, GOAL_TOL)
                full = score_features(fs, exact, r / 2)
                d = acc[a]
                d["tp_all"] = d.get("tp_all", 0) + full.tp
                d["n_all"] = d.get("n_all", 0) + len(exact)
                for key, v in (("tp_goal", goal.tp), ("fp_goal", goal.fp), ("fn_goal", goal.fn)):
                    d[key] = d.get(key, 0) + v
                d["tp"] += sc.tp
                d["fp"] += sc.fp
                d["fn"] += sc.fn
                kk = kinds_f1[a][kind]
                kk[0] += sc.tp
                kk[1] += sc.fp
                kk[2] += sc.fn
                matched = {j for _, j, _ in sc.matches}
                for _, j, dist in sc.matches:
                    sg = "+" if obs[j].sign > 0 else "-"
                    d["loc"].append(dist)
                    d["loc" + sg].append(dist)
                    d["tp" + sg] += 1
                for j, f in enumerate(obs):
                    if j not in matched:
                        d["fn" + ("+" if f.sign > 0 else "-")] += 1
        for a in (1, 2, 3, 4):
            d = acc[a]
            p = d["tp"] / max(d["tp"] + d["fp"], 1)
            rc = d["tp"] / max(d["tp"] + d["fn"], 1)
            f1 = 2 * p * rc / (p + rc) if p + rc else 0.0
            row = {
                "noise_x_thesis": noise,
                "algorithm": a,
                "cases": n_cases,
                "tp": d["tp"],
                "fp": d["fp"],
                "fn": d["fn"],
                "precision": p,
                "recall": rc,
                "f1": f1,
                "f1_at_0.3mm": 2
                * d["tp_goal"]
                / max(2 * d["tp_goal"] + d["fp_goal"] + d["fn_goal"], 1),
                "recall_all_truth": d["tp_all"] / max(d["n_all"], 1),
                "recall_convex": d["tp+"] / max(d["tp+"] + d["fn+"], 1),
                "recall_concave": d["tp-"] / max(d["tp-"] + d["fn-"], 1),
                "loc_mm": 1e3 * float(np.mean(d["loc"])) if d["loc"] else float("nan"),
                "loc_convex_mm": 1e3 * float(np.mean(d["loc+"])) if d["loc+"] else float("nan"),
                "loc_concave_mm": 1e3 * float(np.mean(d["loc-"])) if d["loc-"] else float("nan"),
            }
            for k in SHAPES:
                tp, fp, fn = kinds_f1[a][k]
                row[f"f1_{k}"] = 2 * tp / max(2 * tp + fp + fn, 1)
            rows.append(row)
    return rows


def tiled_trace(n: int, r: float = 0.01, seed: int = 1):
    """An n-sample trace over tiles of a wire, a step up, a ridge and a step down, each
    traced end to end at the thesis' noise and joined into one path [m]; with the number
    of observable features it holds."""
    rng = np.random.default_rng(seed)
    tiles = [
        shapes.wire_on_plane(0.65e-3, 0.0, 0.0, SPAN),
        shapes.step(2e-3, 0.0, SPAN),
        shapes.ridge(6e-3, 2e-3, 0.0, 0.0, SPAN),
        shapes.step(-2e-3, 0.0, SPAN),
    ]
    h = 6e-6  # 0.03 m/s at 5 kHz
    traces = [
        simulate_trace(
            p,
            r,
            spacing=h,
            center_sigma=THESIS_CENTER_SIGMA,
            contact_sigma=THESIS_CONTACT_SIGMA,
            normal_sigma=THESIS_NORMAL_SIGMA,
            rng=rng,
        )
        for p in tiles
    ]
    cs, ps, ns, n_feat, end = [], [], [], 0, np.zeros(2)
    k = 0
    while sum(len(c) for c in cs) < n:
        tr = traces[k % len(traces)]
        shift = end - tr.truth.centers[0] + [h, 0.0]
        cs.append(tr.centers + shift)
        ps.append(tr.contacts + shift)
        ns.append(tr.normals)
        end = tr.truth.centers[-1] + shift
        n_feat += len(tr.truth.observable)
        k += 1
    c, p, nrm = (np.concatenate(x)[:n] for x in (cs, ps, ns))
    return c, p, nrm, n_feat, k


def speed(n: int) -> list[dict]:
    """Samples per second per algorithm on an n-sample trace that has features (warm)."""
    c, p, nrm, n_feat, n_tiles = tiled_trace(n)
    rows = []
    for a in (1, 2, 3, 4):
        found = len(detect_features(c, 0.01, a, normals=nrm, contacts=p))  # also the warm-up
        t = time_call(
            lambda a=a: detect_features(c, 0.01, a, normals=nrm, contacts=p), repeat=3, min_time=0.2
        )
        rows.append(
            {
                "algorithm": a,
                "samples": n,
                "tiles": n_tiles,
                "features_observable": n_feat,
                "features_found": found,
                "best_s": t["best_s"],
                "median_s": t["median_s"],
                "msamples_per_s": n / t["median_s"] / 1e6,
            }
        )
    return rows


def main() -> None:
    args = arg_parser(__doc__.splitlines()[0]).parse_args()
    n_cases = 20 if args.quick else 200
    noises = [0.0, 1.0] if args.quick else [0.0, 0.5, 1.0, 2.0]
    rows = accuracy(n_cases, noises)
    cols = [
        "noise_x_thesis",
        "algorithm",
        "cases",
        "tp",
        "fp",
        "fn",
        "precision",
        "recall",
        "f1",
        "f1_at_0.3mm",
        "recall_all_truth",
        "recall_convex",
        "recall_concave",
        "loc_mm",
        "loc_convex_mm",
        "loc_concave_mm",
        *[f"f1_{k}" for k in SHAPES],
    ]
    a3 = next(r for r in rows if r["noise_x_thesis"] == 1.0 and r["algorithm"] == 3)
    write_report(
        "bench_detection_accuracy",
        rows,
        out=args.out,
        columns=cols,
        title="Feature detection accuracy (planner.detection.detect_features)",
        notes=[
            f"{n_cases} seeded random surfaces per noise level; r_f 5-15 mm; "
            "spacing 20 um; observable ground truth; matching tolerance r_f/2 (f1) and "
            "0.3 mm, the localization goal (f1_at_0.3mm)",
            f"target (alg. 3, thesis noise): F1 >= 0.95 -> {a3['f1']:.3f} "
            f"({a3['f1_at_0.3mm']:.3f} within 0.3 mm); "
            f"localization <= 0.3 mm -> {a3['loc_mm']:.3f} mm "
            f"(convex {a3['loc_convex_mm']:.3f}, concave "
            f"{a3['loc_concave_mm']:.3f})",
        ],
    )
    srows = speed(100_000 if args.quick else 1_000_000)
    write_report(
        "bench_detection_speed",
        srows,
        out=args.out,
        title="Feature detection speed (detect_features, default settings, warm)",
        notes=[
            "trace: tiles of a 0.65 mm wire, a 2 mm step up, a 6 x 2 mm ridge and a 2 mm "
            "step down (r_f 10 mm, thesis noise, 6 um spacing); features_found beside "
            "features_observable shows each algorithm worked on real features",
            "target: >= 2 M samples/s for algorithm 3",
        ],
    )


if __name__ == "__main__":
    main()
