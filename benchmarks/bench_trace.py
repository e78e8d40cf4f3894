"""Benchmark: traced + estimated curves (§3.2.1) versus the number of profile samples.

For each profile and sample count it times :func:`planner.geometry.curves.traced_curve` and
:func:`estimated_curve`, and measures their accuracy against closed forms (interference
points of a step and a wire; the estimated curve's distance to the true profile).

    python benchmarks/bench_trace.py [--quick] [--out DIR] [--max-samples N]

Target (issue #2): 1e5 samples in <= 50 ms.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _common import arg_parser, write_report  # noqa: E402

from planner.geometry import curves  # noqa: E402

R = 0.01  # fingertip radius [m]


def cases():
    a = 0.00065 / 2
    return [
        ("step_15mm", curves.step(0.015, length=0.08), np.array([[-R, R]])),
        (
            "wire_0.65mm",
            curves.wire_on_plane(0.00065, length=0.08),
            np.array([[-2 * np.sqrt(R * a), R], [2 * np.sqrt(R * a), R]]),
        ),
        ("gaussian_pit", curves.pit(0.003, 0.004, "gaussian", length=0.08), None),
        ("ellipse", curves.ellipse(0.05, 0.03), np.empty((0, 2))),
    ]


def main(argv=None) -> int:
    p = arg_parser(__doc__.splitlines()[0])
    p.add_argument(
        "--max-samples",
        type=float,
        default=1e5,
        help="largest sample count (1e6 takes minutes at present)",
    )
    args = p.parse_args(argv)
    sizes = [1e3, 1e4] if args.quick else [s for s in (1e3, 1e4, 1e5, 1e6) if s <= args.max_samples]
    rows = []
    for name, prof, expect in cases():
        for n in sizes:
            spacing = prof.length / n
            t0 = time.perf_counter()
            tc = curves.traced_curve(prof, R, spacing=spacing)
            t1 = time.perf_counter()
            est = curves.estimated_curve(tc, R)
            t2 = time.perf_counter()
            obs = ~est.unobservable
            err = curves.distance_to_profile(est.points[obs][:: max(1, int(n) // 5000)], prof)
            ip_err = float("nan")
            if expect is not None and len(expect) == len(tc.interference_points):
                ip_err = float(np.max(np.abs(tc.interference_points - expect), initial=0.0))
            rows.append(
                {
                    "profile": name,
                    "samples": int(n),
                    "traced_points": len(tc.points),
                    "traced_ms": (t1 - t0) * 1e3,
                    "estimated_ms": (t2 - t1) * 1e3,
                    "total_ms": (t2 - t0) * 1e3,
                    "interference_error_m": ip_err,
                    "estimated_median_error_m": float(np.median(err)) if len(err) else 0.0,
                    "estimated_max_error_m": float(err.max()) if len(err) else 0.0,
                }
            )
            print(f"{name:14s} {int(n):>8d}  {rows[-1]['total_ms']:9.1f} ms", flush=True)
    at = [r["total_ms"] for r in rows if r["samples"] == 100000]
    notes = ["Target: 1e5 samples in <= 50 ms (traced + estimated)."]
    if at:
        notes.append(
            f"At 1e5 samples: {min(at):.0f}-{max(at):.0f} ms. Above 4000 samples the removal "
            "test runs exactly on a sub-sampling of spacing r_f/32 and the gap edges are "
            "re-cut on the fine branches; the rest is O(N) numpy work (sampling, offsets, "
            "chord deviations, normals) and KD-tree queries."
        )
    write_report(
        "bench_trace",
        rows,
        title="Traced + estimated curves (hapex bench_trace)",
        out=args.out,
        notes=notes,
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
