"""Benchmark of ``hapex sweep`` (issue #13): what the sweep machinery costs per run, and
what parallel execution buys.

* **Overhead per run** of each backend against a plain serial loop over the same runs
  (``planner.runner.execute`` into a run directory each): short runs (a ~0.1 s ``detect``
  scenario) so that the machinery dominates. Overhead per run = (wall time x workers - serial
  wall time) / runs, i.e. worker-seconds spent on anything but the runs themselves (packing,
  transfer, unpacking, tables; no report). Target <= 50 ms.
* **Speed-up** on runs of >= 1 s (a fine ``grasp_map`` + gait search): serial wall time /
  backend wall time with 2 workers. Target >= 1.8x on 2 cores.
* **Scaling** of a Dask ``LocalCluster`` with 1 and 2 workers on those runs.

Every backend is measured **warm**: its worker processes are started and have imported hapex
(a warm-up sweep ran first); start-up times are reported separately. The machine's load
average is stamped on the report: on a shared machine, parallel speed-ups are bounded by the
cores the other processes leave free.

Run: ``python benchmarks/bench_sweep.py [--quick] [--out DIR]``.
"""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(1, str(Path(__file__).resolve().parent.parent))  # this checkout's planner
from _common import arg_parser, write_report  # noqa: E402

SHORT = {
    "kind": "detect",
    "tip_radius": 0.01,
    "algorithms": [3],
    "output": {"plots": False},
    "simulation": {"shape": "wire", "length": 0.005, "spacing": 1.0e-4},
}
LONG = {
    "kind": "grasp_map",
    "object": {"shape": "ellipse", "a": 0.055, "b": 0.045},
    "resolution": 360,
    "gait_resolution": 144,
    "require_gait": False,
    "output": {"plots": False},
}

WARM_LONG = {**LONG, "resolution": 60, "gait_resolution": 24}


def study(name: str, base: dict, n: int, first_seed: int = 0):
    from planner.sweep import sweep_from_dict

    return sweep_from_dict(
        {"name": name, "base": base, "seeds": list(range(first_seed, first_seed + n))}
    )


def serial_loop(sweep, out: Path) -> float:
    """The baseline: a plain loop of ``execute`` over the same runs [s]."""
    from planner.runner import execute
    from planner.sweep import plan

    runs = plan(sweep)
    t0 = time.perf_counter()
    for r in runs:
        execute(r.config, out / r.run_id, plots=False)
    return time.perf_counter() - t0


def timed_sweep(sweep, out: Path, **kw) -> tuple[float, float]:
    """Wall time of ``run_sweep`` (no report) and the summed run times its workers report
    (run + writing its directory) [s]; every run must be complete."""
    from planner.sweep import plan, run_sweep

    t0 = time.perf_counter()
    df = run_sweep(sweep, out, report=False, progress=False, **kw)
    dt = time.perf_counter() - t0
    assert sorted(df["run_id"]) == sorted(r.run_id for r in plan(sweep)), "incomplete sweep"
    return dt, float(df["wall_s"].sum())


def backends(workers: int) -> list[tuple[str, dict, bool]]:
    """(label, run_sweep keyword arguments, needs a Dask client) for ``workers`` workers."""
    label = "joblib (loky)" if workers > 1 else "joblib (in process)"
    return [(label, {"jobs": workers}, False), ("dask LocalCluster", {"backend": "dask"}, True)]


def measure(tmp: Path, n_short: int, n_long: int) -> list[dict]:
    from contextlib import nullcontext

    from planner.sweep.backends import dask_client

    rows = []
    short, long_ = study("short", SHORT, n_short), study("long", LONG, n_long)
    for k, warm in enumerate((SHORT, WARM_LONG)):  # imports and caches of this process
        serial_loop(study("warm", warm, 2, 1000 + 10 * k), tmp / f"warm{k}")
    serial_short = serial_loop(short, tmp / "serial_short")
    serial_long = serial_loop(long_, tmp / "serial_long")
    rows.append(
        {
            "backend": "serial loop (execute)",
            "workers": 1,
            "runs": n_short,
            "wall_s": serial_short,
            "per_run_ms": 1e3 * serial_short / n_short,
            "overhead_ms_per_run": 0.0,
            "target_overhead_ms": 50,
        }
    )
    rows.append(
        {
            "backend": "serial loop (execute)",
            "workers": 1,
            "runs": n_long,
            "wall_s": serial_long,
            "per_run_ms": 1e3 * serial_long / n_long,
            "speedup": 1.0,
        }
    )
    for workers in (1, 2):
        for label, kw, dask in backends(workers):
            t0 = time.perf_counter()
            with dask_client(workers=workers) if dask else nullcontext() as client:
                start = time.perf_counter() - t0 if dask else None
                if client is not None:
                    kw = {**kw, "client": client}
                for k, warm in enumerate((SHORT, WARM_LONG)):
                    seeds = 2000 + 100 * k + 10 * workers
                    timed_sweep(study("warm", warm, 2 * workers, seeds), tmp / f"w{seeds}", **kw)
                ws, busy = timed_sweep(short, tmp / f"s{label}{workers}", **kw)
                wl, _ = timed_sweep(long_, tmp / f"l{label}{workers}", **kw)
            rows.append(
                {
                    "backend": label,
                    "workers": workers,
                    "runs": n_short,
                    "wall_s": ws,
                    "per_run_ms": 1e3 * ws / n_short,
                    "overhead_ms_per_run": 1e3 * (ws * workers - serial_short) / n_short,
                    "dispatch_ms_per_run": 1e3 * (ws * workers - busy) / n_short,
                    "target_overhead_ms": 50,
                    "startup_s": start,
                }
            )
            rows.append(
                {
                    "backend": label,
                    "workers": workers,
                    "runs": n_long,
                    "wall_s": wl,
                    "per_run_ms": 1e3 * wl / n_long,
                    "speedup": serial_long / wl,
                    "target_speedup": 1.8 if workers == 2 else None,
                }
            )
            print(rows[-2], rows[-1], flush=True)
    return rows


def main() -> None:
    args = arg_parser(__doc__.splitlines()[0]).parse_args()
    os.environ.setdefault("MPLBACKEND", "Agg")
    n_short, n_long = (8, 4) if args.quick else (40, 8)
    tmp = Path(tempfile.mkdtemp(prefix="bench-sweep-"))
    load0 = os.getloadavg()
    try:
        rows = measure(tmp, n_short, n_long)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    load1 = os.getloadavg()
    write_report(
        "sweep",
        rows,
        title="hapex sweep: overhead per run and parallel speed-up (warm workers)",
        out=args.out,
        columns=[
            "backend",
            "workers",
            "runs",
            "wall_s",
            "per_run_ms",
            "overhead_ms_per_run",
            "dispatch_ms_per_run",
            "target_overhead_ms",
            "speedup",
            "target_speedup",
            "startup_s",
        ],
        notes=[
            f"short runs: a ~0.1 s `detect` scenario ({n_short} seeds); long runs: a "
            f"360x360 `grasp_map` + gait search ({n_long} seeds)",
            "overhead_ms_per_run = (wall_s x workers - serial wall_s) / runs, short runs; "
            "dispatch_ms_per_run = (wall_s x workers - run times the workers report) / runs "
            "(the machinery alone, insensitive to the load changing between the serial loop "
            "and the backend); speedup = serial wall_s / wall_s, long runs",
            "warm: worker processes started and hapex imported before timing; startup_s is "
            "the time to start the pool/cluster",
            f"load average (1, 5, 15 min) before: {', '.join(f'{v:.2f}' for v in load0)}; "
            f"after: {', '.join(f'{v:.2f}' for v in load1)} on {os.cpu_count()} cores",
        ],
    )


if __name__ == "__main__":
    main()
