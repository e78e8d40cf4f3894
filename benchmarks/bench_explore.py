"""Benchmark of the ch. 4 explorer's accuracy: type identification, closed-loop exploration.

Run: ``python benchmarks/bench_explore.py [--quick] [--closed-loop N] [--raster N]
[--out DIR]``. Writes ``bench_explore_identify`` (+ ``_plates``) and
``bench_explore_closed_loop`` (+ ``_plates``) (CSV + Markdown in ``benchmarks/results/``).
The control step and the normal-force variants are ``benchmarks/bench_explore_control.py``.

1. **Type identification** over seeded random plates (6 types x sizes 1-5 mm x 2 orientations
   x 2 noise levels = 96 plates): the fingertip resting on the plate geometry along the
   crossings of the extended Fig. 4.7 (search at a random angle and offset, then across and
   along), centre noise Gaussian plus 0.05 mm encoder quantization; and the raster
   pattern-matching alternative on a subset. Geometric crossings, not the simulator: these
   rows measure the identification logic and the detector, fast enough for 96 plates.
2. **Closed loop** (``--closed-loop N`` seeded random plates, default 54; ``--quick``: 6):
   :func:`explore_surface` in the :class:`planner.sim.SpatialWorld` at 1 kHz with the OWTS
   at 5 kHz: one feature per plate (the six kinds x sizes 1-5 mm x random orientation
   within 60 deg of the search lines x OWTS noise 0.5/1.5/3 deg, up to 2 mm off the search
   line), found by the search, identified, traced and modelled; type accuracy, boundary
   deviation against the true outline, closure, skeleton Hausdorff against the true
   skeleton, real-time factor; tables
   by noise level, by feature size and by kind (``bench_explore_closed_loop``) and per plate
   (``bench_explore_closed_loop_plates``). ``--raster N`` (default 6, 0 with ``--quick``)
   more plates with ``identify="raster"`` (raster lines 6 mm apart, pattern matching).
   ``--seed N`` (default 7, the reference set) draws another set of closed-loop plates
   (reports suffixed ``_seedN``; identification and raster rows skipped). Per plate also
   the CPU-time real-time factor (the machine is shared; load inflates wall time) and the
   feature's height at the region border (what the plate level next to a long-tailed bump
   or pit is lifted by).
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

from planner.exploration.surface.identify import KINDS, evidence, identify  # noqa: E402
from planner.exploration.surface.kinematic import ball_trace, line_points  # noqa: E402
from planner.exploration.surface.plates import plate_height, random_plate  # noqa: E402
from planner.exploration.surface.raster_match import raster_identify  # noqa: E402
from robots.sensors import OWTS  # noqa: E402
from robots.three_gm import ThreeGM  # noqa: E402

R = 0.008


def _load() -> str:
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


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
NOISES_DEG = (0.5, 1.5, 3.0)  # OWTS polar-angle noise, 1 sigma [deg]
SIZES = (1e-3, 2e-3, 3e-3, 4e-3, 5e-3)  # feature heights [m]
REGION = np.array([[-0.02, 0.02], [-0.02, 0.02]])


def closed_cases(n: int, seed: int = 7) -> list[dict]:
    """``n`` seeded random plates: the six kinds in turn, the OWTS noise levels in blocks of
    six, sizes cycling across kinds and blocks, random orientation and a random offset of the
    feature from the search line (up to 2 mm).

    The orientation (the direction *across* the feature) is uniform within 60 degrees of
    the search lines: the search crosses every feature at 30 degrees or more. A crest
    nearly parallel to the raster lines is never crossed (a search problem, solved by a
    second raster across the first), not an identification one."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        block = i // len(KINDS)
        out.append(
            {
                "kind": KINDS[i % len(KINDS)],
                "size": SIZES[(i + 2 * block) % len(SIZES)],
                "angle": float(rng.uniform(-math.pi / 3, math.pi / 3)),
                "offset": float(rng.uniform(-2e-3, 2e-3)),
                "noise_deg": NOISES_DEG[block % len(NOISES_DEG)],
                "seed": int(rng.integers(1 << 30)),
            }
        )
    return out


def _closed_plate(case: dict):
    """The plate of one case; ridges and ravines are finite (12 mm long): closed outlines."""
    from planner.sim.spatial.plate import Plate, PlateFeature

    kind, angle = case["kind"], case["angle"]
    pos = (0.0, case["offset"])
    p = random_plate(np.random.default_rng(case["seed"]), kind, case["size"], angle, pos)
    f = p.features[0]
    if kind in ("ridge", "ravine"):
        d = 0.006 * np.array([-math.sin(angle), math.cos(angle)])
        c = np.asarray(pos)
        path = (tuple(c - d), tuple(c + d))
        f = PlateFeature(kind, f.height, f.width, pos, angle, path=path)
    return Plate((f,), name=p.name)


def _sensors(noise_deg: float, seed: int):
    from planner.sim import SensorSettings
    from robots.sensors import Encoder, OWTSSampler

    owts = OWTSSampler(OWTS(radius=R), np.random.default_rng(seed), None, math.radians(noise_deg))
    return SensorSettings(encoder=Encoder(ThreeGM().encoder_resolution), tactile=None, owts=owts)


def _case_columns(case: dict, identify_mode: str) -> dict:
    """The columns that say which plate a row is (kind, size [mm], angle [deg], noise [deg])."""
    return {
        "kind": case["kind"],
        "size_mm": case["size"] * 1e3,
        "angle_deg": math.degrees(case["angle"]),
        "owts_noise_deg": case["noise_deg"],
        "identify": identify_mode,
    }


def _failed_row(case: dict, identify_mode: str, reason: str) -> dict:
    """The row of a plate the explorer could not run (counts as not identified)."""
    nan = math.nan
    return {
        **_case_columns(case, identify_mode),
        "identified": "error",
        "confidence": nan,
        "correct": False,
        "features_found": 0,
        "boundary_dev_mean_mm": nan,
        "boundary_dev_max_mm": nan,
        "boundary_dev_own_level_mm": nan,
        "closed": False,
        "closure": 0.0 if case["kind"] in ("bump", "pit", "ridge", "ravine") else nan,
        "skeleton_hausdorff_mm": nan,
        "latency_s": nan,
        "sim_s": 0.0,
        "wall_s": 0.0,
        "real_time_factor": nan,
        "cpu_real_time_factor": nan,
        "tail_at_edge_mm": nan,
        "status": f"error: {reason}",
    }


def closed_row(case: dict, identify_mode: str = "flow_chart", all_contacts: bool = False) -> dict:
    """Explore one plate in the SpatialWorld and score it against the truth (``all_contacts``:
    the simulator's every tip-plate contact, :class:`planner.sim.spatial.SpatialWorld`)."""
    from planner.errors import HapexError
    from planner.exploration.surface import explore_surface
    from planner.exploration.surface.metrics import exploration_metrics

    plate = _closed_plate(case)
    opts = {"line_spacing": 0.05} if identify_mode == "flow_chart" else {"line_spacing": 0.006}
    opts["all_contacts"] = all_contacts
    try:
        return _explore_row(case, identify_mode, plate, opts, explore_surface, exploration_metrics)
    except HapexError as exc:  # a valid plate the explorer refused: reported, not hidden
        return _failed_row(case, identify_mode, str(exc))


def _explore_row(case, identify_mode, plate, opts, explore_surface, exploration_metrics) -> dict:
    t0 = time.perf_counter()
    res = explore_surface(
        plate,
        region=REGION,
        duration=60.0 if identify_mode == "raster" else 40.0,
        speed=0.03,
        seed=case["seed"] % 1000,
        sensors=_sensors(case["noise_deg"], case["seed"]),
        identify=identify_mode,
        **opts,
    )
    wall = time.perf_counter() - t0
    m = exploration_metrics(res, plate, REGION, R, 0.3)
    f = res.features[0] if res.features else None
    return {
        **_case_columns(case, identify_mode),
        "identified": f.kind if f else "missed",
        "confidence": f.confidence if f else math.nan,
        "correct": bool(f is not None and f.kind == case["kind"]),
        "features_found": len(res.features),
        "boundary_dev_mean_mm": m["boundary_deviation_mean_mm"],
        "boundary_dev_max_mm": m["boundary_deviation_max_mm"],
        "boundary_dev_own_level_mm": m["boundary_deviation_own_level_mm"],
        "closed": bool(f.closed) if f else False,
        "closure": m["closure"],
        "skeleton_hausdorff_mm": m["skeleton_hausdorff_mm"],
        "latency_s": m["detection_latency_mean_s"],
        "sim_s": res.sim_time,
        "wall_s": wall,
        "real_time_factor": res.real_time_factor,
        "cpu_real_time_factor": res.cpu_real_time_factor,
        "tail_at_edge_mm": _tail_at_edge(plate) * 1e3,
        "status": res.status,
    }


def _tail_at_edge(plate, n: int = 400) -> float:
    """Largest height [m] of the feature on the border of the region: what its flanks or
    tails still lift (or lower) the plate where the explorer can first see it (a diagnostic:
    the true outline is a level line above the feature's foot,
    :func:`planner.exploration.surface.plates.foot_levels`, which the region sees, not above
    the asymptotic plate, which its tails hide)."""
    from planner.exploration.surface.plates import plate_height

    (u0, u1), (v0, v1) = REGION
    s = np.linspace(0.0, 1.0, n)
    u = np.concatenate([u0 + (u1 - u0) * s, np.full(n, u1), u1 - (u1 - u0) * s, np.full(n, u0)])
    v = np.concatenate([np.full(n, v0), v0 + (v1 - v0) * s, np.full(n, v1), v1 - (v1 - v0) * s])
    return float(np.max(np.abs(plate_height(plate)(u, v) - plate.base)))


def _nanmean(x) -> float:
    x = np.asarray([v for v in x if math.isfinite(v)], float)
    return float(x.mean()) if x.size else math.nan


def _nanmedian(x) -> float:
    x = np.asarray([v for v in x if math.isfinite(v)], float)
    return float(np.median(x)) if x.size else math.nan


def _nanmax(x) -> float:
    x = np.asarray([v for v in x if math.isfinite(v)], float)
    return float(x.max()) if x.size else math.nan


def closed_summary(rows: list[dict]) -> list[dict]:
    """Accuracy by OWTS noise, by feature size, by kind and over all plates."""
    groups = [
        (f"noise {nz} deg", [r for r in rows if r["owts_noise_deg"] == nz]) for nz in NOISES_DEG
    ]
    groups += [
        (f"size {s * 1e3:g} mm", [r for r in rows if r["size_mm"] == s * 1e3]) for s in SIZES
    ]
    groups += [(f"kind {k}", [r for r in rows if r["kind"] == k]) for k in KINDS]
    groups.append(("all plates", rows))
    out = []
    for name, rr in groups:
        if not rr:
            continue
        haus = [r["skeleton_hausdorff_mm"] for r in rr]
        fin = [h for h in haus if math.isfinite(h)]
        out.append(
            {
                "group": name,
                "plates": len(rr),
                "type_accuracy": float(np.mean([r["correct"] for r in rr])),
                "missed": sum(r["identified"] == "missed" for r in rr),
                "mean_confidence": _nanmean(r["confidence"] for r in rr),
                "boundary_dev_mean_mm": _nanmean(r["boundary_dev_mean_mm"] for r in rr),
                "boundary_dev_max_mm": _nanmax(r["boundary_dev_max_mm"] for r in rr),
                "boundary_dev_own_level_mm": _nanmean(r["boundary_dev_own_level_mm"] for r in rr),
                "closure": _nanmean(r["closure"] for r in rr),
                "hausdorff_median_mm": float(np.median(fin)) if fin else math.nan,
                "hausdorff_max_mm": max(fin) if fin else math.nan,
                "hausdorff_le_1mm": float(np.mean([h <= 1.0 for h in fin])) if fin else math.nan,
                "rtf_median": _nanmedian(r["real_time_factor"] for r in rr),
                "rtf_cpu_median": _nanmedian(r["cpu_real_time_factor"] for r in rr),
            }
        )
    return out


def closed_rows(
    cases: list[dict], identify_mode: str = "flow_chart", all_contacts: bool = False
) -> list[dict]:
    rows = []
    for case in cases:
        rows.append(closed_row(case, identify_mode, all_contacts))
        print(
            {
                k: rows[-1][k]
                for k in (
                    "kind",
                    "size_mm",
                    "owts_noise_deg",
                    "identified",
                    "boundary_dev_mean_mm",
                    "skeleton_hausdorff_mm",
                    "wall_s",
                )
            },
            flush=True,
        )
    return rows


def main() -> None:
    p = arg_parser(__doc__.splitlines()[0])
    p.add_argument("--closed-loop", type=int, default=None, help="closed-loop plates (0: skip)")
    p.add_argument("--raster", type=int, default=None, help="closed-loop plates, raster id")
    p.add_argument(
        "--seed",
        type=int,
        default=7,
        help="base seed of the closed-loop plates (7: the reference set; any other value is "
        "a second set, its reports suffixed _seedN and the identification part skipped)",
    )
    p.add_argument(
        "--all-contacts",
        action="store_true",
        help="simulate every tip-plate contact (SpatialWorld all_contacts; reports suffixed "
        "_all_contacts, identification part skipped)",
    )
    args = p.parse_args()
    tag = "" if args.seed == 7 else f"_seed{args.seed}"
    tag += "_all_contacts" if args.all_contacts else ""
    load0 = _load()
    notes = [f"load average at start: {load0} (2 cores shared with other engineers)"]
    if not tag:
        _identification_reports(args, notes)
    n = (len(KINDS) if args.quick else 54) if args.closed_loop is None else args.closed_loop
    n_r = (0 if args.quick else len(KINDS)) if args.raster is None else args.raster
    if tag:
        n_r = 0
    every = args.all_contacts
    crow = closed_rows(closed_cases(n, seed=args.seed), all_contacts=every) if n > 0 else []
    crow += closed_rows(closed_cases(n_r, seed=8), "raster", every) if n_r > 0 else []
    if crow:
        _closed_reports(args, crow, n_r, notes, tag)


def _identification_reports(args, notes: list[str]) -> None:
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


def _closed_reports(args, crow: list[dict], n_r: int, notes: list[str], tag: str) -> None:
    cl_notes = [
        *notes,
        f"load average at the end: {_load()}",
        f"closed-loop plates of base seed {args.seed}"
        + (
            " (the reference set)"
            if args.seed == 7
            else " (a second set: are the reference set's numbers seed-specific?)"
        ),
        "simulator: "
        + (
            "every tip-plate contact (all_contacts: the tip bridges grooves narrower than it)"
            if args.all_contacts
            else "one contact per sphere and plate (the default; a tip wider than a groove "
            "can sink into its far rim)"
        ),
        "one feature per plate (12 mm long ridges and ravines, closed outlines); 1 kHz control, "
        "OWTS at 5 kHz with the noise of the row, encoder quantization on",
        "targets: type accuracy >= 95 %, boundary deviation <= 0.5 mm mean, closure 100 % "
        "(closed features), skeleton Hausdorff <= 1 mm, >= 10x real time",
        "boundary deviation: traced fingertip centres vs the true outline, the level line of "
        "the traced (offset) surface at the feature's outline level above its foot (where the "
        "traced surface's tilt falls to 5 deg, §4.4.2); own level: vs the level line the "
        "tracer actually followed (tracing error "
        "alone); tail_at_edge_mm: the feature's height at the region border",
        "steps and cusps are open (traced along: pseudo-skeleton scored against the true "
        "outline line it follows, thesis §4.4.3; closure n/a)",
        "real time: rtf = simulated / wall time of the run (the machine is shared: load "
        "inflates it), rtf_cpu = simulated / CPU time of the run",
    ]
    write_report(
        f"bench_explore_closed_loop_plates{tag}",
        crow,
        title=f"Closed-loop exploration in the SpatialWorld, per plate ({len(crow)} plates)",
        out=args.out,
        notes=cl_notes,
    )
    summ = closed_summary([r for r in crow if r["identify"] == "flow_chart"])
    if n_r > 0:
        raster = [r for r in crow if r["identify"] == "raster"]
        summ += [dict(s, group=f"raster id: {s['group']}") for s in closed_summary(raster)[-1:]]
    write_report(
        f"bench_explore_closed_loop{tag}",
        summ,
        title=f"Closed-loop exploration in the SpatialWorld ({len(crow)} plates)",
        out=args.out,
        notes=cl_notes,
    )


if __name__ == "__main__":
    main()
