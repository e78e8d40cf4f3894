"""Benchmark of surface geometry, feature extraction and contact kinematics (issue #3).

Rows (time and a correctness column each):

* ``K`` and principal curvatures of the bump (eq. 3.13) and the sphere (eq. A.7) on 1e6
  ``(u, v)`` points: CasADi graph translated to numpy (the library path) vs CasADi's own
  ``Function.map`` (the obvious alternative); target >= 2 M points/s;
* curvature-feature extraction on a 1000 x 1000 height field (the bump sampled on a grid):
  finite-difference principal curvatures + labelled regions + macro grouping; target <= 0.5 s;
* traced/estimated surfaces (ball dilation/closing) on the same grid (no target);
* ``montana_rates`` per call; target <= 20 us;
* ``integrate_contact`` of 1e4 RK4 steps, sphere rolling and sliding on a bump (no target).

Run: ``python benchmarks/bench_geometry.py [--quick] [--out DIR]``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _common import arg_parser, time_call, write_report  # noqa: E402

WARM = "warm median"


def bench_curvatures(quick: bool) -> list[dict]:
    from planner.geometry import surfaces as S

    n = 100_000 if quick else 1_000_000
    rng = np.random.default_rng(0)
    u, v = rng.uniform(-0.99, 0.99, n), rng.uniform(0.01, 3.1, n)
    rows = []
    for surf in (S.bump(15.0), S.sphere(0.02)):
        uu = u if surf.name.startswith("bump") else u * 1.5
        for what, fn in (
            ("principal_curvatures", surf.principal_curvatures),
            ("curvature_matrix (K)", surf.curvature_matrix),
        ):
            t = time_call(lambda fn=fn, uu=uu: fn(uu, v), repeat=3 if quick else 5, min_time=0.01)
            k = fn(uu[:1000], v[:1000])
            if isinstance(k, tuple):
                ok = (
                    np.allclose(k[0], 1 / 0.02)
                    if surf.name.startswith("sphere")
                    else bool(np.all(np.abs(k[0]) >= np.abs(k[1])))
                )
            else:
                ok = bool(np.all(np.isfinite(k)))
            rows.append(
                {
                    "benchmark": f"{what}, {surf.name}",
                    "setting": "numpy from CasADi graph",
                    "n": n,
                    "time_s": t["median_s"],
                    "timing": WARM,
                    "rate_Mpts_s": n / t["median_s"] / 1e6,
                    "target": ">= 2 M/s",
                    "check": "ok" if ok else "FAIL",
                }
            )
        fmap = surf.functions["curvature_matrix"].map(n)
        t0 = time.perf_counter()
        out = np.array(fmap(uu[None, :], v[None, :]))
        dt = time.perf_counter() - t0
        rows.append(
            {
                "benchmark": f"curvature_matrix (K), {surf.name}",
                "setting": "CasADi Function.map (reference)",
                "n": n,
                "time_s": dt,
                "timing": "one call, cold",
                "rate_Mpts_s": n / dt / 1e6,
                "target": "",
                "check": "ok"
                if np.allclose(
                    out.reshape(4, n, order="F")[0], surf.curvature_matrix(uu, v)[:, 0, 0]
                )
                else "FAIL",
            }
        )
    return rows


def bump_grid(n: int):
    x = np.linspace(-1, 1, n)
    gx, gy = np.meshgrid(x, x, indexing="ij")
    return x, 1 / (1 + 15 * (gx**2 + gy**2))


def bench_features(quick: bool) -> list[dict]:
    from planner.geometry.feature_maps import curvature_feature_map
    from planner.geometry.surfaces import grid_principal_curvatures, offset_surfaces

    n = 300 if quick else 1000
    x, z = bump_grid(n)

    def extract():
        k1, k2 = grid_principal_curvatures(x, x, z)
        return curvature_feature_map(x, x, k1, k2, 1.0)

    t = time_call(extract, repeat=3, min_time=0.01)
    fm = extract()
    rows = [
        {
            "benchmark": f"feature extraction, {n}x{n} height field",
            "setting": "FD curvatures + regions + macros",
            "n": n * n,
            "time_s": t["median_s"],
            "timing": WARM,
            "rate_Mpts_s": n * n / t["median_s"] / 1e6,
            "target": "<= 0.5 s",
            "check": "ok" if [m.kind for m in fm.macros] == ["bump"] else "FAIL",
        }
    ]
    k1, k2 = grid_principal_curvatures(x, x, z)
    t = time_call(lambda: curvature_feature_map(x, x, k1, k2, 1.0), repeat=3, min_time=0.01)
    rows.append(
        {
            "benchmark": f"feature extraction, {n}x{n} height field",
            "setting": "regions + macros only (curvatures given)",
            "n": n * n,
            "time_s": t["median_s"],
            "timing": WARM,
            "rate_Mpts_s": n * n / t["median_s"] / 1e6,
            "target": "",
            "check": "ok",
        }
    )
    for r in (0.02, 0.05):
        t0 = time.perf_counter()
        off = offset_surfaces(x, x, z, r)
        dt = time.perf_counter() - t0
        rows.append(
            {
                "benchmark": f"traced+estimated surfaces, {n}x{n}",
                "setting": f"ball r = {r:g} ({int(r / (x[1] - x[0]))} cells)",
                "n": n * n,
                "time_s": dt,
                "timing": "one call, cold",
                "rate_Mpts_s": n * n / dt / 1e6,
                "target": "",
                "check": "ok" if np.all(off.estimated >= z - 1e-12) else "FAIL",
            }
        )
    return rows


def bench_contact(quick: bool) -> list[dict]:
    from planner.contact import integrate_contact, montana_rates
    from planner.geometry import surfaces as S

    k1, k2 = np.eye(2) / 0.02, np.diag([30.0, 2.0])
    t1, t2 = np.array([[0.0, -0.5]]), np.zeros((1, 2))
    m1, m2 = np.diag([0.02, 0.018]), np.diag([1.2, 0.4])
    v, w = np.array([0.01, 0.0, 0.0]), np.array([0.1, 0.5, 0.2])
    t = time_call(lambda: montana_rates(k1, t1, m1, k2, t2, m2, 0.3, v, w))
    rows = [
        {
            "benchmark": "montana_rates",
            "setting": "per call (validated inputs)",
            "n": 1,
            "time_s": t["median_s"],
            "timing": WARM,
            "rate_Mpts_s": 1 / t["median_s"] / 1e6,
            "target": "<= 20 us",
            "check": "ok",
        }
    ]
    steps = 1000 if quick else 10_000
    t0 = time.perf_counter()
    tr = integrate_contact(
        S.sphere(0.02),
        S.bump(3.0),
        [0.1, 0.2],
        [0.3, 1.0],
        0.2,
        ([0.002, 0.0, 0.0], [0.0, 0.5, 0.1]),
        1.0,
        steps,
    )
    dt = time.perf_counter() - t0
    rows.append(
        {
            "benchmark": f"integrate_contact, {steps} RK4 steps",
            "setting": "sphere rolling+sliding on bump",
            "n": steps,
            "time_s": dt,
            "timing": "one call, cold",
            "rate_Mpts_s": steps / dt / 1e6,
            "target": "",
            "check": f"residual {tr.residual.max():.1e} m",
        }
    )
    return rows


def main() -> None:
    args = arg_parser(__doc__.splitlines()[0]).parse_args()
    rows = bench_curvatures(args.quick) + bench_features(args.quick) + bench_contact(args.quick)
    write_report(
        "bench_geometry",
        rows,
        title="hapex geometry and contact benchmark",
        out=args.out,
        columns=["benchmark", "setting", "n", "time_s", "timing", "rate_Mpts_s", "target", "check"],
        notes=[
            "time_s: 'warm median' = median per call over the timed batches (3 to 7) that "
            "follow an untimed warm-up call (time_call of benchmarks/_common.py); 'one call, "
            "cold' = a single timed call (the slow rows, and the CasADi reference)",
            "rate_Mpts_s: points (or calls, or steps) per second / 1e6",
            "machine shared with other jobs: expect +-30 % between runs",
        ],
    )


if __name__ == "__main__":
    main()
