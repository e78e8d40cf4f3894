"""Benchmark of planner.detection: accuracy and speed of the four algorithms of Fig. 3.8.

Run: ``python benchmarks/bench_detection.py [--quick] [--out DIR]``. Writes
``bench_detection_accuracy`` and ``bench_detection_speed`` (CSV + Markdown).

Accuracy: seeded random surfaces (wires 0.5-1.5 mm, steps up/down 1-4 mm, rectangular
ridges and ravines, circular pits, on planes inclined 0-60 deg, r_f 5-15 mm), traced at
20 um spacing (0.03 m/s at 1.5 kHz) with Gaussian noise at 0, 0.5, 1 and 2 times the
thesis' level (centre 0.1 mm, contact 0.25 mm, normal 1 deg, 1 sigma). Each algorithm's
features are matched to the observable ground truth (same sign, within r_f/2; same-sign
features inside one unobservable region, or passed within r_f/4, count once) -> precision,
recall, F1 (pooled counts) and the mean localization error of the matches, for all features
and per sign; ``recall_all_truth`` is the recall against every true feature of the profile,
seen or not.
Targets (issue #6), algorithm 3 at the thesis noise: F1 >= 0.95, localization <= 0.3 mm.

Speed: samples per second of ``detect_features`` per algorithm on a 10^6-sample trace
(target >= 2 M samples/s for algorithm 3, whose Gaussian smoothing is built in).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _common import arg_parser, time_call, write_report  # noqa: E402

from planner.detection import detect_features, score_features  # noqa: E402
from planner.detection.synthetic import (  # noqa: E402
    THESIS_CENTER_SIGMA,
    THESIS_CONTACT_SIGMA,
    THESIS_NORMAL_SIGMA,
    Shape,
    simulate,
)

SHAPES = ("wire", "step", "ridge", "ravine", "pit")


def random_case(rng: np.random.Generator) -> tuple[Shape, float]:
    """One random surface and fingertip radius [m]."""
    kind = SHAPES[int(rng.integers(len(SHAPES)))]
    r = float(rng.uniform(5e-3, 15e-3))
    ang = float(np.deg2rad(rng.uniform(0, 60)))
    if kind == "wire":
        return Shape("wire", rng.uniform(0.5e-3, 1.5e-3), angle=ang), r
    if kind == "step":
        return Shape("step", rng.choice([-1, 1]) * rng.uniform(1e-3, 4e-3), angle=ang), r
    if kind == "ridge":
        return Shape(
            "ridge", rng.uniform(1e-3, 3e-3), width=rng.uniform(0.3, 1.0) * r, angle=ang
        ), r
    if kind == "ravine":
        return Shape(
            "ravine", rng.uniform(1e-3, 3e-3), width=rng.uniform(0.6, 1.6) * r, angle=ang
        ), r
    w = rng.uniform(0.6, 1.6) * r
    return Shape("pit", rng.uniform(0.3, 0.9) * w / 2, width=w, angle=ang), r


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
        for i, (shape, r) in enumerate(cases):
            tr = simulate(
                shape,
                r,
                spacing=2e-5,
                center_sigma=noise * THESIS_CENTER_SIGMA,
                contact_sigma=noise * THESIS_CONTACT_SIGMA,
                normal_sigma=noise * THESIS_NORMAL_SIGMA,
                rng=np.random.default_rng(seed * 100003 + i),
            )
            for a in (1, 2, 3, 4):
                fs = detect_features(tr.centers, r, a, normals=tr.normals, contacts=tr.contacts)
                sc = score_features(fs, tr.observable, r / 2)
                full = score_features(fs, tr.truth, r / 2)
                d = acc[a]
                d["tp_all"] = d.get("tp_all", 0) + full.tp
                d["n_all"] = d.get("n_all", 0) + len(tr.truth)
                d["tp"] += sc.tp
                d["fp"] += sc.fp
                d["fn"] += sc.fn
                kk = kinds_f1[a][shape.kind]
                kk[0] += sc.tp
                kk[1] += sc.fp
                kk[2] += sc.fn
                matched = {j for _, j, _ in sc.matches}
                for _, j, dist in sc.matches:
                    sg = "+" if tr.observable[j].sign > 0 else "-"
                    d["loc"].append(dist)
                    d["loc" + sg].append(dist)
                    d["tp" + sg] += 1
                for j, f in enumerate(tr.observable):
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


def speed(n: int) -> list[dict]:
    """Samples per second per algorithm on an n-sample noisy trace."""
    rng = np.random.default_rng(1)
    h = 6e-6  # 0.03 m/s at 5 kHz
    x = np.arange(n) * h
    c = np.column_stack([x, 2e-3 * np.sin(x / 0.01)])
    c += rng.normal(0, THESIS_CENTER_SIGMA, c.shape)
    nrm = np.tile([0.0, 1.0], (n, 1))
    p = c - 0.01 * nrm + rng.normal(0, THESIS_CONTACT_SIGMA, c.shape)
    rows = []
    for a in (1, 2, 3, 4):
        t = time_call(
            lambda a=a: detect_features(c, 0.01, a, normals=nrm, contacts=p), repeat=3, min_time=0.2
        )
        rows.append(
            {
                "algorithm": a,
                "samples": n,
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
            "spacing 20 um; tolerance r_f/2; observable ground truth",
            f"target (alg. 3, thesis noise): F1 >= 0.95 -> {a3['f1']:.3f}; "
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
        title="Feature detection speed (detect_features, default settings)",
        notes=["target: >= 2 M samples/s for algorithm 3"],
    )


if __name__ == "__main__":
    main()
