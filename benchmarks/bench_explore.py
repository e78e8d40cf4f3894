"""Benchmark of the ch. 4 explorer: control step, type identification, closed-loop exploration.

Run: ``python benchmarks/bench_explore.py [--quick] [--closed-loop N] [--out DIR]``. Writes
``bench_explore_control``, ``bench_explore_identify`` and ``bench_explore_closed_loop``
(CSV + Markdown in ``benchmarks/results/``).

1. **Control step** (warm): the compiled hybrid-law step (numba, :mod:`planner.control.
   hybrid_kernel`) and the controller call around it, against the plain numpy implementation
   of the same law (:mod:`planner.control.hybrid_reference`), in the same run, on the same
   inputs. Targets: <= 15 µs median, >= 4x faster than numpy.
2. **Type identification** over seeded random plates (6 types x sizes 1-5 mm x 2 orientations
   x 2 noise levels = 96 plates): the fingertip resting on the plate geometry along the
   crossings of the extended Fig. 4.7 (search at a random angle and offset, then across and
   along), centre noise Gaussian plus 0.05 mm encoder quantization; and the raster
   pattern-matching alternative on a subset. Geometric crossings, not the simulator: these
   rows measure the identification logic and the detector, fast enough for 96 plates.
3. **Closed loop** (``--closed-loop N`` plates, default 8): :func:`explore_surface` in the
   :class:`planner.sim.SpatialWorld` at 1 kHz with the OWTS at 5 kHz: one feature at the
   region's centre, found by the raster, identified, traced and modelled; type accuracy,
   boundary deviation against the true outline, closure, skeleton Hausdorff, real-time factor.
   Two OWTS noise levels (0.5° default, 1.5°).
"""

from __future__ import annotations

import math
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _common import arg_parser, write_report  # noqa: E402

from planner.control import hybrid_kernel as hk  # noqa: E402
from planner.control.hybrid_frames import tcs_rotation  # noqa: E402
from planner.control.hybrid_law import (  # noqa: E402
    HybridController,
    HybridSettings,
    kernel_parameters,  # noqa: E402
)
from planner.control.hybrid_reference import reference_step  # noqa: E402
from planner.exploration.surface.identify import KINDS, evidence, identify  # noqa: E402
from planner.exploration.surface.kinematic import ball_trace, line_points  # noqa: E402
from planner.exploration.surface.plates import plate_height, random_plate  # noqa: E402
from planner.exploration.surface.raster_match import raster_identify  # noqa: E402
from robots.sensors import OWTS  # noqa: E402
from robots.three_gm import ThreeGM  # noqa: E402

R = 0.008


def _load() -> str:
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


# ----------------------------------------------------------------------------- 1. control step
def control_rows(quick: bool) -> list[dict]:
    gm = ThreeGM()
    owts = OWTS(radius=R)
    s = HybridSettings()
    par = kernel_parameters(gm, s, owts)
    th = gm.center_theta
    rng = np.random.default_rng(0)
    n = 2000 if quick else 20000
    thetas = th + 0.05 * rng.standard_normal((n, 3))
    thds = 0.2 * rng.standard_normal((n, 3))
    volts = owts.voltages_from_contact(
        np.column_stack([0.3 * rng.standard_normal((n, 2)), np.ones(n)])
    )
    target = np.array([0.02, 0.0, 0.0])
    state = np.zeros(12)
    state[:3] = tcs_rotation(gm.state(th).gamma1, th[2])[:, 2]
    out = np.zeros(hk.NOUT)
    hk.hybrid_step(thetas[0], thds[0], volts[0], state, target, par, out)  # JIT / cache load
    ctl = HybridController(gm, s, owts)
    ctl.command_velocity(target)
    ctl.step(thetas[0], thds[0], volts[0])

    def timed(fn, count):
        ts = np.empty(count)
        for i in range(count):
            t0 = time.perf_counter()
            fn(i)
            ts[i] = time.perf_counter() - t0
        return ts

    t_k = timed(lambda i: hk.hybrid_step(thetas[i], thds[i], volts[i], state, target, par, out), n)
    t_c = timed(lambda i: ctl.step(thetas[i], thds[i], volts[i]), n)
    m = max(200, n // 10)
    st2 = state.copy()
    t_n = timed(
        lambda i: reference_step(gm, owts, thetas[i], thds[i], volts[i], st2, target, par), m
    )
    med_n = float(np.median(t_n))
    rows = []
    for name, ts in (
        ("compiled step (numba kernel)", t_k),
        ("controller.step (kernel + Python wrapper)", t_c),
        ("plain numpy, same law", t_n),
    ):
        med = float(np.median(ts))
        rows.append(
            {
                "implementation": name,
                "calls": len(ts),
                "median_us": med * 1e6,
                "p10_us": float(np.percentile(ts, 10)) * 1e6,
                "p90_us": float(np.percentile(ts, 90)) * 1e6,
                "speedup_vs_numpy": med_n / med,
                "target": "<= 15 us, >= 4x" if "controller" in name else "",
            }
        )
    return rows


# ----------------------------------------------------------------------------- 2. identification
def _quantized(c: np.ndarray, sigma: float, rng) -> np.ndarray:
    return np.round((c + rng.normal(0.0, sigma, c.shape)) / 5e-5) * 5e-5


def _identify_plate(kind, size, angle, sigma, rng) -> tuple[str, float]:
    H = plate_height(random_plate(rng, kind, size, angle))
    phi = angle + rng.uniform(-0.7, 0.7)
    d = np.array([math.cos(phi), math.sin(phi)])
    off = rng.uniform(-0.3, 0.3) * (size + 1e-3) * np.array([-d[1], d[0]])

    def cross(c, v, half, role):
        tr = ball_trace(H, line_points(c - half * v, c + half * v, 1e-4), R)
        return tr, evidence(_quantized(tr.centers, sigma, rng), tr.normals, R, role)

    tr, (e0, a0, across) = cross(off, d, 0.025, "search")
    if not a0.features:
        return "missed", 0.0
    idx = [f.index for f in a0.features]
    mid = tr.centers[int(round(0.5 * (min(idx) + max(idx)))), :2]
    tr1, (e1, _, _) = cross(mid, across, 0.02, "across")
    base = np.linspace(tr1.centers[0, 2], tr1.centers[-1, 2], len(tr1.centers))
    top = tr1.centers[int(np.argmax(np.abs(tr1.centers[:, 2] - base))), :2]
    _, (e2, _, _) = cross(top, np.array([-across[1], across[0]]), 0.02, "along")
    dec = identify([e0, e1, e2])
    return dec.kind, dec.confidence


def _raster_plate(kind, size, angle, rng) -> str:
    H = plate_height(random_plate(rng, kind, size, angle))
    lines = []
    for i, y in enumerate(np.arange(-0.018, 0.0181, 0.006)):
        a, b = np.array([-0.02, y]), np.array([0.02, y])
        tr = ball_trace(H, line_points(*(a, b) if i % 2 == 0 else (b, a), 1.5e-4), R)
        lines.append(_quantized(tr.centers, 2e-5, rng))
    found = raster_identify(lines, R)
    return found[0].decision.kind if found else "missed"


def identify_rows(quick: bool) -> tuple[list[dict], list[dict]]:
    rng = np.random.default_rng(12)
    sizes = (2e-3, 4e-3) if quick else (1e-3, 2e-3, 3e-3, 5e-3)
    angles = (0.3,) if quick else (0.3, 1.9)
    noises = (2e-5,) if quick else (2e-5, 6e-5)
    per = []
    for kind in KINDS:
        for size in sizes:
            for angle in angles:
                for sigma in noises:
                    got, conf = _identify_plate(kind, size, angle, sigma, rng)
                    raster = _raster_plate(kind, size, angle, rng) if sigma == noises[0] else ""
                    per.append(
                        {
                            "kind": kind,
                            "size_mm": size * 1e3,
                            "angle": angle,
                            "noise_mm": sigma * 1e3,
                            "identified": got,
                            "confidence": conf,
                            "correct": got == kind,
                            "raster": raster,
                        }
                    )
    summary = []
    for key, vals in (("kind", KINDS), ("size_mm", sorted({r["size_mm"] for r in per}))):
        for v in vals:
            rows = [r for r in per if r[key] == v]
            rr = [r for r in rows if r["raster"]]
            summary.append(_acc(f"{key} = {v}", rows, rr))
    for nz in sorted({r["noise_mm"] for r in per}):
        summary.append(_acc(f"noise = {nz} mm", [r for r in per if r["noise_mm"] == nz], []))
    summary.append(_acc("all plates", per, [r for r in per if r["raster"]]))
    return per, summary


def _acc(name, rows, raster_rows) -> dict:
    return {
        "group": name,
        "plates": len(rows),
        "flow_chart_accuracy": float(np.mean([r["correct"] for r in rows])) if rows else math.nan,
        "missed": sum(r["identified"] == "missed" for r in rows),
        "mean_confidence": float(np.mean([r["confidence"] for r in rows])) if rows else math.nan,
        "raster_plates": len(raster_rows),
        "raster_accuracy": (
            float(np.mean([r["raster"] == r["kind"] for r in raster_rows]))
            if raster_rows
            else math.nan
        ),
    }


# ----------------------------------------------------------------------------- 3. closed loop
CLOSED_CASES = (
    ("bump", 2e-3, 0.0),
    ("pit", 2e-3, 0.0),
    ("ridge", 2e-3, 0.6),
    ("ravine", 2e-3, 0.4),
    ("step", 2e-3, 1.2),
    ("cusp", 1e-3, 1.0),
    ("bump", 4e-3, 0.0),
    ("ridge", 1e-3, 2.2),
)


def _closed_plate(kind, size, angle, rng):
    from planner.sim.spatial.plate import Plate, PlateFeature

    p = random_plate(rng, kind, size, angle)
    f = p.features[0]
    if kind in ("ridge", "ravine"):  # finite: a closed outline the tracer can close
        d = 0.006 * np.array([-math.sin(angle), math.cos(angle)])
        f = PlateFeature(kind, f.height, f.width, (0.0, 0.0), angle, path=(tuple(-d), tuple(d)))
    return Plate((f,), name=p.name)


def closed_rows(n: int) -> list[dict]:
    from planner.exploration.surface import explore_surface
    from planner.exploration.surface.metrics import exploration_metrics
    from planner.sim import SensorSettings
    from robots.sensors import Encoder, OWTSSampler

    rng = np.random.default_rng(7)
    region = np.array([[-0.016, 0.016], [-0.016, 0.016]])
    rows = []
    cases = [(c, nz) for nz in (0.5, 1.5) for c in CLOSED_CASES][:n]
    for (kind, size, angle), noise_deg in cases:
        plate = _closed_plate(kind, size, angle, rng)
        sensors = None
        if noise_deg != 0.5:
            owts = OWTSSampler(
                OWTS(radius=R), np.random.default_rng(0), None, math.radians(noise_deg)
            )
            sensors = SensorSettings(
                encoder=Encoder(ThreeGM().encoder_resolution), tactile=None, owts=owts
            )
        t0 = time.perf_counter()
        res = explore_surface(
            plate, region=region, duration=40.0, speed=0.03, line_spacing=0.05, sensors=sensors
        )
        wall = time.perf_counter() - t0
        m = exploration_metrics(res, plate, region, R, 0.3)
        f = res.features[0] if res.features else None
        rows.append(
            {
                "kind": kind,
                "size_mm": size * 1e3,
                "owts_noise_deg": noise_deg,
                "identified": f.kind if f else "missed",
                "confidence": f.confidence if f else math.nan,
                "boundary_dev_mean_mm": m["boundary_deviation_mean_mm"],
                "boundary_dev_max_mm": m["boundary_deviation_max_mm"],
                "closed": f.closed if f else False,
                "skeleton_hausdorff_mm": m["skeleton_hausdorff_mm"],
                "fn_rms_error_N": m["normal_force_rms_error_N"],
                "latency_s": m["detection_latency_mean_s"],
                "sim_s": res.sim_time,
                "wall_s": wall,
                "real_time_factor": res.real_time_factor,
                "status": res.status,
            }
        )
        print(rows[-1], flush=True)
    return rows


def main() -> None:
    p = arg_parser(__doc__.splitlines()[0])
    p.add_argument("--closed-loop", type=int, default=None, help="closed-loop plates (0: skip)")
    args = p.parse_args()
    load0 = _load()
    rows = control_rows(args.quick)
    notes = [f"load average at start: {load0} (2 cores shared with other engineers)"]
    write_report(
        "bench_explore_control",
        rows,
        title="Hybrid force/velocity control step (warm, per call)",
        out=args.out,
        notes=[*notes, "same inputs for all three; numpy = hybrid_reference.reference_step"],
    )
    per, summary = identify_rows(args.quick)
    write_report(
        "bench_explore_identify",
        summary,
        title=f"Type identification over {len(per)} random plates (geometric crossings)",
        out=args.out,
        notes=[
            *notes,
            "flow chart = search + across + along crossings (Fig. 4.7 extended), target >= 95 %",
            "raster = pattern matching of 7 raster lines 6 mm apart (one noise level)",
            "noise: Gaussian centre noise + 0.05 mm quantization (the 3GM encoders)",
        ],
    )
    write_report("bench_explore_identify_plates", per, title="Per plate", out=args.out)
    n = (2 if args.quick else 8) if args.closed_loop is None else args.closed_loop
    if n > 0:
        crow = closed_rows(n)
        write_report(
            "bench_explore_closed_loop",
            crow,
            title=f"Closed-loop exploration in the SpatialWorld ({len(crow)} plates)",
            out=args.out,
            notes=[
                *notes,
                f"load average at the end: {_load()}",
                "targets: boundary deviation <= 0.5 mm mean, closure 100 % (closed features), "
                "skeleton Hausdorff <= 1 mm, >= 10x real time",
                "steps and cusps are open (traced along: pseudo-skeleton, closure n/a)",
            ],
        )


if __name__ == "__main__":
    main()
