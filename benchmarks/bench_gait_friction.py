"""Robustness of the executed gait to friction above the thesis' mu = 1 (issue 11, "mu" of
``explore_object``): more friction must not make the gait fail.

Every run is ``explore_object(profile, mu=MU, seed=N, duration=D)`` with the library's
defaults, in two configurations:

* ``capped``: the default :class:`GaitSettings` (``mu_cap`` 1: the planners and the
  grasp-force QP count on at most mu 1, less the 20 % reserve, i.e. cones of 0.8);
* ``full``: ``GaitSettings(mu=MU, mu_cap=MU)``: the planners and the QP use the full
  cones of the true friction, less the reserve (the gait before ``mu_cap``).

At ``mu <= 1`` both are the same gait. Objects: the 10 cm ridge ball (ridge at 170 deg, as
in ``ball_with_ridge``, and at 45 deg), circles of 2, 3, 5 and 7 cm radius, a 1.1:1
ellipse and an 8 cm square with 1.6 cm corners, each resting on the palm; the planner's
model is the default feature-less circle.

Per run: status and reason, rotation, coverage, wall and CPU time. The summary counts full
turns (status ok and >= 360 deg) per mu and configuration.

Run: ``python benchmarks/bench_gait_friction.py [--mus 1,1.25,1.5,2,3] [--seeds 0,1]
[--config capped,full] [--duration 90] [--jobs 2] [--quick]`` (``--quick``: 3 objects,
mu 1 and 2, one seed, 20 s). 144 runs by default (the full gait is not run at mu <= 1),
~1.5 min on 2 cores (most runs at high mu fail early).
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from _common import arg_parser, comma_list, load_average, run_pool, write_report  # noqa: E402

#: name -> (kind, parameters [m, rad])
OBJECTS = {
    "ridge_ball_170": ("ridge", (0.05, 0.004, 0.003, math.radians(170.0))),
    "ridge_ball_45": ("ridge", (0.05, 0.004, 0.003, math.radians(45.0))),
    "circle_2cm": ("circle", (0.02,)),
    "circle_3cm": ("circle", (0.03,)),
    "circle_5cm": ("circle", (0.05,)),
    "circle_7cm": ("circle", (0.07,)),
    "ellipse_1.1to1": ("ellipse", (0.044, 0.04)),
    "rounded_square_8cm": ("rounded_rectangle", (0.08, 0.08, 0.016)),
}
CONFIGS = ("capped", "full")


def _profile(name: str):
    from planner.exploration.planar import circle_with_ridge
    from planner.geometry import shapes

    kind, par = OBJECTS[name]
    if kind == "ridge":
        return circle_with_ridge(*par[:3], angle=par[3])
    return {"circle": shapes.circle, "ellipse": shapes.ellipse,
            "rounded_rectangle": shapes.rounded_rectangle}[kind](*par)  # fmt: skip


def _run(task: tuple) -> dict:
    config, name, mu, seed, duration = task
    import resource

    from planner.exploration import explore_object
    from planner.exploration.planar import GaitSettings

    cpu0 = resource.getrusage(resource.RUSAGE_SELF).ru_utime
    t0 = time.perf_counter()
    s = GaitSettings(mu=mu) if config == "capped" else GaitSettings(mu=mu, mu_cap=mu)
    r = explore_object(_profile(name), mu=mu, seed=seed, duration=duration, settings=s)
    wall = time.perf_counter() - t0
    cpu = resource.getrusage(resource.RUSAGE_SELF).ru_utime - cpu0
    turn = -math.degrees(r.rotation)
    return {
        "config": config, "object": name, "mu": mu, "planning_mu": round(s.planning_mu, 3),
        "seed": seed, "status": r.status, "full_turn": r.status == "ok" and turn >= 360.0,
        "turn_deg": round(turn, 1), "coverage": round(r.coverage, 3),
        "reason": r.reason[:90], "wall_s": round(wall, 1), "cpu_s": round(cpu, 1),
    }  # fmt: skip


def _summary(rows: list[dict]) -> list[str]:
    out = []
    for mu in sorted({r["mu"] for r in rows}):
        parts = []
        for config in CONFIGS:
            rs = [r for r in rows if r["mu"] == mu and r["config"] == config]
            if rs:
                parts.append(f"{config} {sum(r['full_turn'] for r in rs)}/{len(rs)}")
        out.append(f"mu {mu:g}: full turns " + ", ".join(parts))
    return out


def main() -> None:
    p = arg_parser(__doc__.splitlines()[0])
    p.add_argument("--mus", type=comma_list(float), default="1,1.25,1.5,2,3",
                   help="true friction coefficients")  # fmt: skip
    p.add_argument("--seeds", type=comma_list(int), default="0,1", help="sensor seeds")
    p.add_argument("--config", type=comma_list(choices=CONFIGS), default="capped,full",
                   help="capped and/or full")  # fmt: skip
    p.add_argument("--objects", type=comma_list(choices=tuple(OBJECTS)),
                   default=",".join(OBJECTS), help="object names")  # fmt: skip
    p.add_argument("--duration", type=float, default=90.0, help="simulated s per run")
    p.add_argument("--jobs", type=int, default=2, help="worker processes")
    args = p.parse_args()
    mus, seeds, names, configs = args.mus, args.seeds, args.objects, args.config
    if bad := [m for m in mus if not (math.isfinite(m) and m > 0)]:
        p.error(f"--mus: expected positive numbers, got {bad}")
    if args.quick:
        names, mus, seeds, args.duration = names[:3], [1.0, 2.0], seeds[:1], 20.0
    # at mu <= 1 the two configurations are the same gait: run it once
    tasks = [(c, n, m, s, args.duration) for c in configs for n in names for m in mus
             for s in seeds if c == "capped" or m > 1.0]  # fmt: skip
    t0 = time.perf_counter()
    rows = run_pool(_run, tasks, args.jobs)
    rows.sort(key=lambda r: (r["config"], r["mu"], r["object"], r["seed"]))
    notes = _summary(rows) + [
        "capped: GaitSettings(mu) (mu_cap 1: planning cones of min(mu, 1) x 0.8); full: "
        "GaitSettings(mu, mu_cap=mu) (cones of mu x 0.8); at mu <= 1 only capped is run "
        "(the same gait); full turn: status ok and >= 360 deg within the duration",
        f"duration {args.duration:g} simulated s per run; planner's model: the default "
        "feature-less circle; the world's friction is mu everywhere (fingers, palm, object)",
        f"total wall {time.perf_counter() - t0:.0f} s with {args.jobs} worker processes; load "
        f"average at the end {load_average()}",
    ]
    write_report(
        "bench_gait_friction", rows, title="Gait robustness: friction above mu 1",
        out=args.out, notes=notes,
    )  # fmt: skip


if __name__ == "__main__":
    main()
