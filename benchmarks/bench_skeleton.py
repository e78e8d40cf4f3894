"""Benchmark of planner.skeleton: speed of feature/global skeletons and accuracy vs noise.

Run: ``python benchmarks/bench_skeleton.py [--quick] [--out DIR]``. Writes
``bench_skeleton_speed`` and ``bench_skeleton_accuracy`` (CSV + Markdown).

Speed: the feature skeleton of a noisy ellipse outline (ordered samples, as boundary tracing
gives) with 1k / 10k / 100k samples, next to the time of qhull's Delaunay triangulation
alone on the same samples (the floor) and of ``scipy.spatial.Voronoi``; the same with
shuffled samples (region rebuilt by an MST ordering); the global skeleton of 10 features x
2k samples. Accuracy: Hausdorff distance
between the skeleton and the closed-form medial axis of an ellipse and a rectangle, for
several sample spacings and noise levels, in units of the spacing.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _common import arg_parser, time_call, write_report  # noqa: E402
from scipy.spatial import Delaunay, Voronoi, cKDTree  # noqa: E402

from planner.skeleton import feature_skeleton, global_skeleton  # noqa: E402
from planner.skeleton import shapes as sh  # noqa: E402

A, B = 0.02, 0.008  # ellipse semi-axes [m]


def ellipse_samples(n: int, noise_frac: float, rng: np.random.Generator) -> np.ndarray:
    """About ``n`` ordered samples of the ellipse outline, noise ``noise_frac`` x spacing."""
    perimeter = np.pi * (3 * (A + B) - np.sqrt((3 * A + B) * (A + 3 * B)))
    s = perimeter / n
    pts = sh.ellipse_outline(A, B, s, n_poly=max(4096, 2 * n))
    return pts + rng.normal(0, noise_frac * s, pts.shape)


def hausdorff(a: np.ndarray, b: np.ndarray) -> float:
    return float(max(cKDTree(b).query(a)[0].max(), cKDTree(a).query(b)[0].max()))


def speed_rows(quick: bool) -> list[dict]:
    rng = np.random.default_rng(0)
    rows = []
    sizes = (1_000, 10_000) if quick else (1_000, 10_000, 100_000)
    for n in sizes:
        pts = ellipse_samples(n, 0.05, rng)
        shuffled = pts[rng.permutation(len(pts))]
        repeat = 3 if n >= 100_000 else 7
        t_q = time_call(lambda p=pts: Delaunay(p), repeat=repeat)
        t_v = time_call(lambda p=pts: Voronoi(p), repeat=repeat)
        t_f = time_call(lambda p=pts: feature_skeleton(p), repeat=repeat)
        t_u = time_call(lambda p=shuffled: feature_skeleton(p), repeat=repeat)
        sk = feature_skeleton(pts)
        target = "<= 100 ms" if n == 10_000 else ""
        rows.append(
            {
                "case": f"feature skeleton, ellipse, {n} samples (ordered)",
                "samples": len(pts),
                "median_ms": 1e3 * t_f["median_s"],
                "best_ms": 1e3 * t_f["best_s"],
                "qhull_ms": 1e3 * t_q["median_s"],
                "overhead_ms": 1e3 * (t_f["median_s"] - t_q["median_s"]),
                "scipy_voronoi_ms": 1e3 * t_v["median_s"],
                "skeleton_points": len(sk.points),
                "target": target,
            }
        )
        rows.append(
            {
                "case": f"feature skeleton, ellipse, {n} samples (shuffled)",
                "samples": len(pts),
                "median_ms": 1e3 * t_u["median_s"],
                "best_ms": 1e3 * t_u["best_s"],
                "qhull_ms": 1e3 * t_q["median_s"],
                "overhead_ms": 1e3 * (t_u["median_s"] - t_q["median_s"]),
                "skeleton_points": len(feature_skeleton(shuffled).points),
                "target": "",
            }
        )
    n_feat, per = (4, 1000) if quick else (10, 2000)
    bnd = []
    for k in range(n_feat):
        cl = np.array([[0.0, 0.0], [0.03, 0.008 * (k % 3)]]) + [0.05 * (k % 5), 0.04 * (k // 5)]
        poly = sh.ridge_polygon(cl, 0.006)
        bnd.append(sh.sample_outline(poly, poly.length / per, 3e-5, rng))
    total = sum(len(b) for b in bnd)
    t_g = time_call(lambda: global_skeleton(bnd), repeat=5)
    t_q = time_call(lambda: Delaunay(np.concatenate(bnd)), repeat=5)
    rows.append(
        {
            "case": f"global skeleton, {n_feat} features x {per} samples",
            "samples": total,
            "median_ms": 1e3 * t_g["median_s"],
            "best_ms": 1e3 * t_g["best_s"],
            "qhull_ms": 1e3 * t_q["median_s"],
            "overhead_ms": 1e3 * (t_g["median_s"] - t_q["median_s"]),
            "skeleton_points": len(global_skeleton(bnd).points),
            "target": "",
        }
    )
    return rows


def accuracy_rows(quick: bool) -> list[dict]:
    rows = []
    spacings = (0.0005, 0.001) if quick else (0.00025, 0.0005, 0.001, 0.002)
    noises = (0.0, 0.1) if quick else (0.0, 0.05, 0.1, 0.2)
    shapes = {
        "ellipse 40x16 mm": (lambda s: sh.ellipse_outline(A, B, s), sh.ellipse_medial_axis(A, B)),
        "rectangle 40x10 mm": (
            lambda s: sh.rectangle_outline(0.04, 0.01, s),
            sh.rectangle_medial_axis(0.04, 0.01),
        ),
    }
    seeds = range(3 if quick else 10)
    for name, (outline, truth) in shapes.items():
        for s in spacings:
            base = outline(s)
            for nf in noises:
                h, spurs, ok = [], 0, 0
                for seed in seeds:
                    rng = np.random.default_rng(seed)
                    sk = feature_skeleton(base + rng.normal(0, nf * s, base.shape), s)
                    h.append(hausdorff(sk.points, truth) / s)
                    want_ends = 2 if name.startswith("ellipse") else 4
                    ok += len(sk.end_points) == want_ends
                    spurs += max(len(sk.end_points) - want_ends, 0)
                rows.append(
                    {
                        "shape": name,
                        "spacing_mm": 1e3 * s,
                        "noise_over_spacing": nf,
                        "hausdorff_over_spacing_median": float(np.median(h)),
                        "hausdorff_over_spacing_max": float(np.max(h)),
                        "right_topology": f"{ok}/{len(seeds)}",
                        "spurious_end_points": spurs,
                    }
                )
    return rows


def main() -> None:
    args = arg_parser(__doc__.splitlines()[0]).parse_args()
    write_report(
        "bench_skeleton_speed",
        speed_rows(args.quick),
        out=args.out,
        title="planner.skeleton speed",
        notes=[
            "median/best per call over repeated batches (time_call); qhull_ms is "
            "scipy.spatial.Delaunay alone on the same samples (the qhull floor: the "
            "Voronoi diagram is built as its dual); scipy_voronoi_ms is "
            "scipy.spatial.Voronoi, for reference",
            "ellipse outline with noise 0.05 x spacing; shuffled = same samples in "
            "random order (region rebuilt by an MST ordering)",
        ],
    )
    write_report(
        "bench_skeleton_accuracy",
        accuracy_rows(args.quick),
        out=args.out,
        title="planner.skeleton accuracy (Hausdorff to the closed-form medial axis)",
        notes=[
            "default settings; spacing passed, noise estimated from the samples",
            "right topology: ellipse 2 end points and no branch point; rectangle "
            "4 end points (corner branches)",
        ],
    )


if __name__ == "__main__":
    main()
