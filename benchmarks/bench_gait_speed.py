"""Benchmark of the gait's speed (issue 11, target "ball_with_ridge ... >= 20x real time").

Runs ``planner.exploration.explore_object`` on the bundled ``ball_with_ridge`` scenario (its
object, hand, gains and limits, from scenarios/ball_with_ridge.yaml) and reports, per run:
simulated time, wall and CPU time of ``explore_object``, the real-time factors (simulated /
wall and simulated / CPU: the CPU factor is what a shared machine does not distort), and a
breakdown: controller calls, simulator steps, steps run by the Python reference step (the
compiled step's fallback), tactile images computed, the phase-1 NLP (build and solves),
the sensed-feature detection, the run loop and the rest.

Rows: ``cold`` (the first run in the process: it pays the imports and the loading of the
numba caches, as a ``hapex run`` does) and ``warm`` (the same run again in the same
process). The outcome columns (status, rotation, coverage, phases, ridge angle) show that
the runs compute the same gait.

Run: ``python benchmarks/bench_gait_speed.py [--quick] [--seed N] [--out DIR]`` (``--quick``:
3 simulated seconds).
"""

from __future__ import annotations

import math
import sys
import time
from contextlib import contextmanager
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from _common import ROOT, arg_parser, load_average, write_report  # noqa: E402

SCENARIO = ROOT / "scenarios" / "ball_with_ridge.yaml"
TARGET_RTF = 20.0


class Timers:
    """Wall time [s] and calls of wrapped functions (module attribute patches)."""

    def __init__(self) -> None:
        self.wall: dict[str, float] = {}
        self.calls: dict[str, int] = {}

    @contextmanager
    def wrap(self, owner, attr: str, name: str):
        fn = getattr(owner, attr)

        def timed(*args, **kwargs):
            t0 = time.perf_counter()
            try:
                return fn(*args, **kwargs)
            finally:
                self.wall[name] = self.wall.get(name, 0.0) + time.perf_counter() - t0
                self.calls[name] = self.calls.get(name, 0) + 1

        setattr(owner, attr, timed)
        try:
            yield
        finally:
            setattr(owner, attr, fn)


def run_once(cfg, seed: int, duration: float) -> dict:
    """One ``explore_object`` run of the scenario with its breakdown."""
    from planner.exploration.planar import explore_object, metrics
    from planner.sim.planar import stepper
    from planner.sim.planar.world import PlanarWorld
    from planner.trajectory import RollingNLP

    timers = Timers()
    c0, w0 = time.process_time(), time.perf_counter()
    with (
        timers.wrap(metrics, "detect_pad_features", "detection"),
        timers.wrap(PlanarWorld, "run", "run loop"),
        timers.wrap(PlanarWorld, "step", "python iterations"),
        timers.wrap(stepper, "step", "python steps"),
        timers.wrap(RollingNLP, "solve", "nlp solves"),
    ):
        res = explore_object(cfg.object.profile(), hand=cfg.hand.hand(cfg.mu), mu=cfg.mu,
                             nominal=cfg.nominal.profile(), seed=seed, duration=duration,
                             settings=cfg.settings(),
                             max_rotation=math.radians(cfg.max_rotation_deg))  # fmt: skip
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    sim = float(res.log.t[-1] - res.log.t[0])
    calls = len(res.timings["control_step_us"])
    ridge = [math.degrees(f.angle) for f in res.features if f.kind == "ridge"]
    tw = timers.wall
    loop = tw.get("run loop", 0.0)
    return {
        "sim_s": round(sim, 3),
        "wall_s": round(wall, 3),
        "cpu_s": round(cpu, 3),
        "rtf_wall": round(sim / wall, 2),
        "rtf_cpu": round(sim / cpu, 2),
        "controller_calls": calls,
        "sim_steps": len(res.log.t) - 1,
        "python_iterations": timers.calls.get("python iterations", 0),
        "python_iterations_s": round(tw.get("python iterations", 0.0), 3),
        "python_ref_steps": timers.calls.get("python steps", 0),
        "images": calls if "left" in _flat_fingers(cfg) else 0,
        "run_loop_s": round(loop, 3),
        "loop_us_per_step": round(1e6 * loop / max(len(res.log.t) - 1, 1), 1),
        "nlp_build_s": round(res.timings["nlp_build_s"], 3),
        "nlp_solves": timers.calls.get("nlp solves", 0),
        "nlp_solve_s": round(tw.get("nlp solves", 0.0), 3),
        "detection_s": round(tw.get("detection", 0.0), 3),
        "rest_s": round(wall - loop - tw.get("nlp solves", 0.0) - tw.get("detection", 0.0), 3),
        "status": res.status,
        "rotation_deg": round(math.degrees(res.rotation), 6),
        "coverage": round(res.coverage, 6),
        "phases": len(res.phases),
        "ridge_deg": ";".join(f"{a:.4f}" for a in ridge),
    }


def _flat_fingers(cfg) -> tuple[str, ...]:
    hand = cfg.hand.hand(cfg.mu)
    return tuple(f for f in ("left", "right") if hand.params.finger(f).tip == "flat")


def main() -> None:
    p = arg_parser(__doc__.splitlines()[0])
    p.add_argument("--seed", type=int, default=0, help="sensor-noise seed")
    args = p.parse_args()
    import yaml

    from planner.kinds.gait import Config

    cfg = Config.model_validate({"name": "ball_with_ridge", **yaml.safe_load(SCENARIO.read_text())})
    duration = 3.0 if args.quick else cfg.duration
    rows = []
    for label in ("cold", "warm"):
        row = {"run": label, "seed": args.seed, **run_once(cfg, args.seed, duration)}
        row["target_20x_wall"] = "met" if row["rtf_wall"] >= TARGET_RTF else "missed"
        rows.append(row)
    write_report(
        "bench_gait_speed",
        rows,
        title="Gait speed: ball_with_ridge, explore_object (issue 11 target >= 20x real time)",
        out=args.out,
        notes=[
            f"load average while measuring: {load_average()} (2 cores shared with other "
            "engineers: wall factors vary with load; CPU factors much less)",
            "cold = first run in the process (imports, numba cache loading); warm = the same "
            "run again in the process",
            "python_iterations: loop iterations the compiled loop handed back to Python (the "
            "compiled step could not do them), python_ref_steps of them ran the all-Python "
            "reference step (position projection / unverified LCP); run_loop_s includes them",
            "rest_s = wall - run loop - NLP solves - detection (planning, sensing at phase "
            "starts, prior, world build, NLP build, metrics, imports when cold)",
        ],
    )


if __name__ == "__main__":
    main()
