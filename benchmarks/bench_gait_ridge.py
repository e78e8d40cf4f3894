"""Robustness of the executed gait on the ridge ball (issue 11, "ball_with_ridge: full 360°,
ridge found within 5°, no drop"): the same ball with its ridge placed anywhere.

The bundled ``ball_with_ridge`` scenario puts the ridge at 170 deg (as the thesis'
Fig. 2.14 shows it) and is checked on sensor seeds 0-3. This benchmark moves the ridge
around the ball (``object.ridge_angle_deg``) and varies the seed, so that it says how the
gait and the feature detection fare where nothing was tuned. Two configurations:

* ``scenario``: the bundled scenario's settings (0.4 N hold for Fig. 2.14's sign change,
  200 N/m tip stiffness, 400 deg), run like ``hapex run --seed N --set
  object.ridge_angle_deg=A`` (the kind derives the noise seed from N);
* ``default``: ``explore_object(circle_with_ridge(...), seed=N)`` with every default (the
  gait's hand, :class:`GaitSettings()`: 2 N hold, 60 N/m tip, 360 deg).

Per run: status and reason, rotation, coverage, the ridge found (angle error of the detected
ridge nearest the true one, within 20 deg), phantom features (every other detection), wall
and CPU time, and (scenario runs) Fig. 2.14's tangential-force sign changes at the phase
2 -> 3 switches. The summary counts full turns, ridges within 5 deg and phantoms.

Run: ``python benchmarks/bench_gait_ridge.py [--angles 0,45,...] [--seeds 0,1,2,3,4,5]
[--jobs 2] [--config scenario,default] [--set KEY.PATH=VALUE] [--quick]`` (``--quick``: 3
angles, 1 seed, 20 s; ``--set`` overrides a key of the scenario configuration, e.g.
``left_hold_force=2.0``). Seeds 0-5 by default (96 runs, ~2 min on 2 cores): with seeds
0-1 a single change moved the counts by more than its effect (the gait is chaotic at the
friction cone's edge).
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from _common import (  # noqa: E402
    ROOT,
    arg_parser,
    comma_list,
    load_average,
    run_pool,
    write_report,
)

SCENARIO = ROOT / "scenarios" / "ball_with_ridge.yaml"
#: a detected ridge this close to the true one is "the ridge" [deg]; farther: a phantom
MATCH_DEG = 20.0
TARGET_DEG = 5.0
#: the issue's coverage target for ball_with_ridge (fraction of the outline touched)
TARGET_COVERAGE = 0.99


def _run(task: tuple) -> dict:
    config, angle, seed, duration, extra = task
    import resource

    cpu0 = resource.getrusage(resource.RUSAGE_SELF).ru_utime
    t0 = time.perf_counter()
    if config == "scenario":
        from planner.runner import run_config
        from planner.scenario import load_scenario

        overrides = [f"seed={seed}", f"object.ridge_angle_deg={angle}", *extra]
        if duration is not None:
            overrides.append(f"duration={duration}")
        res, _ = run_config(load_scenario(SCENARIO, overrides=overrides), plots=False)
        m = res.metrics
        status, reason = res.status, res.reason or str(m.get("end_event", ""))
        rotation, coverage = -m["rotation_deg"], m["coverage"]
        feats = [(f["kind"], f["error_deg"]) for f in m["features"]]
        signs = m.get("tangential_sign_changes_2to3", "")
    else:
        from planner.exploration import explore_object
        from planner.exploration.planar import circle_with_ridge

        ball = circle_with_ridge(0.05, 0.004, 0.003, angle=math.radians(angle))
        r = explore_object(ball, seed=seed, duration=duration)
        status, reason = r.status, r.reason
        rotation, coverage = -math.degrees(r.rotation), r.coverage
        feats = [(f.kind, math.degrees(f.error)) for f in r.features]
        signs = ""
    wall = time.perf_counter() - t0
    cpu = resource.getrusage(resource.RUSAGE_SELF).ru_utime - cpu0
    errs = [e for k, e in feats if k == "ridge" and e is not None and abs(e) <= MATCH_DEG]
    best = min(errs, key=abs) if errs else float("nan")
    phantoms = len(feats) - (1 if errs else 0)
    return {
        "config": config, "ridge_deg": angle, "seed": seed, "status": status,
        "reason": reason[:90], "turn_deg": round(rotation, 1), "coverage": round(coverage, 3),
        "ridge_error_deg": None if math.isnan(best) else round(best, 2),
        "within_5deg": bool(errs) and abs(best) <= TARGET_DEG, "phantoms": phantoms,
        "fig214_sign_changes": signs,
        "wall_s": round(wall, 1), "cpu_s": round(cpu, 1),
    }  # fmt: skip


def _summary(rows: list[dict]) -> list[str]:
    out = []
    for config in dict.fromkeys(r["config"] for r in rows):
        rs = [r for r in rows if r["config"] == config]
        full = sum(r["status"] == "ok" and r["turn_deg"] >= 360 for r in rs)
        within = sum(r["within_5deg"] for r in rs)
        found = sum(r["ridge_error_deg"] is not None for r in rs)
        ph = sum(r["phantoms"] for r in rs)
        covered = sum(r["coverage"] >= TARGET_COVERAGE for r in rs)
        clean = sum(r["status"] == "ok" and r["turn_deg"] >= 360 and r["within_5deg"]
                    and r["phantoms"] == 0 and r["coverage"] >= TARGET_COVERAGE
                    for r in rs)  # fmt: skip
        out.append(
            f"{config}: {len(rs)} runs; full turn {full}/{len(rs)}; coverage >= "
            f"{TARGET_COVERAGE:g} {covered}/{len(rs)}; ridge found {found}, "
            f"within {TARGET_DEG:g} deg {within}/{len(rs)}; phantom features {ph} in "
            f"{sum(r['phantoms'] > 0 for r in rs)} runs; all targets met {clean}/{len(rs)}"
        )
    return out


def main() -> None:
    p = arg_parser(__doc__.splitlines()[0])
    p.add_argument("--angles", type=comma_list(float), default="0,45,90,135,170,225,270,315",
                   help="ridge angles [deg]")  # fmt: skip
    p.add_argument("--seeds", type=comma_list(int), default="0,1,2,3,4,5", help="sensor seeds")
    p.add_argument("--config", type=comma_list(choices=("scenario", "default")),
                   default="scenario,default", help="scenario and/or default")  # fmt: skip
    p.add_argument("--jobs", type=int, default=2, help="worker processes")
    p.add_argument("--duration", type=float, default=None, help="simulated s (default: full)")
    p.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY.PATH=VALUE",
        help="override a key of the scenario configuration (repeatable)",
    )
    args = p.parse_args()
    angles, seeds, configs = args.angles, args.seeds, args.config
    if args.quick:
        angles, seeds, args.duration = angles[:3], seeds[:1], 20.0
    tasks = [(c, a, s, args.duration, tuple(args.set)) for c in configs for a in angles
             for s in seeds]  # fmt: skip
    t0 = time.perf_counter()
    rows = run_pool(_run, tasks, args.jobs)
    rows.sort(key=lambda r: (r["config"], r["ridge_deg"], r["seed"]))
    notes = _summary(rows) + [
        f"ridge: 4 mm wide, 3 mm high on a 10 cm ball, mu = 1; a detection within "
        f"{MATCH_DEG:g} deg of the true ridge is the ridge (the nearest counts), every other "
        "one a phantom; full turn: status ok and >= 360 deg",
        "scenario = scenarios/ball_with_ridge.yaml with seed and ridge angle overridden (the "
        "kind derives the noise seed from the scenario seed); default = explore_object with "
        "every default" + (f"; scenario overrides: {', '.join(args.set)}" if args.set else ""),
        f"total wall {time.perf_counter() - t0:.0f} s with {args.jobs} worker processes; load "
        f"average at the end {load_average()} (2-core machine shared with other jobs: wall "
        "times vary, cpu_s much less)",
    ]
    write_report(
        "bench_gait_ridge", rows, title="Gait robustness: the ridge ball with its ridge anywhere",
        out=args.out, notes=notes,
    )  # fmt: skip


if __name__ == "__main__":
    main()
