"""``hapex sweep``: the command-line front of :func:`planner.sweep.run_sweep`.

Exit codes: 0 every run of the study is complete (failed runs are results of the study,
listed in report.md); 1 runs are missing (the backend failed; run again to resume);
2 bad input (nothing ran); 130 interrupted (run again to resume).
"""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path

from planner.exit_codes import EXIT_BAD_INPUT, EXIT_FAILED, EXIT_INTERRUPTED, EXIT_OK


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``hapex sweep``."""
    p.add_argument("sweep", type=Path, help="sweep YAML file")
    p.add_argument(
        "--out", type=Path, default=None, help="output folder (default: sweeps/<name>[-quick])"
    )
    p.add_argument(
        "--jobs", type=int, default=None, help="local worker processes (default: all cores)"
    )
    where = p.add_mutually_exclusive_group()
    where.add_argument(
        "--scheduler", default=None, metavar="ADDRESS", help="Dask scheduler, tcp://host:8786"
    )
    where.add_argument(
        "--dask-local",
        type=int,
        default=None,
        metavar="N",
        help="start a Dask LocalCluster with N workers",
    )
    p.add_argument("--quick", action="store_true", help="the sweep's quick variant, quick runs")
    p.add_argument("--retry-failed", action="store_true", help="run failed runs again")
    p.add_argument("--no-report", action="store_true", help="do not write report.md")
    p.add_argument(
        "--dry-run", action="store_true", help="validate every run and list them; run nothing"
    )
    p.add_argument("-v", "--verbose", action="store_true", help="tracebacks on errors")


def _bad(message: str) -> int:
    """Print ``OPTION: VALUE: problem`` (the form ``hapex run`` and ``reproduce`` use for
    their options) to stderr; the exit code 2."""
    print(message, file=sys.stderr)
    return EXIT_BAD_INPUT


def resume_command(args: argparse.Namespace, out: Path) -> list[str]:
    """The ``hapex sweep`` command that resumes an interrupted one: the same sweep file, output
    folder, variant, backend and every option that changes what is run or written."""
    again = ["hapex", "sweep", str(args.sweep), "--out", str(out)]
    again += ["--quick"] if args.quick else []
    again += ["--scheduler", args.scheduler] if args.scheduler else []
    again += ["--dask-local", str(args.dask_local)] if args.dask_local else []
    again += ["--jobs", str(args.jobs)] if args.jobs else []
    again += ["--retry-failed"] if args.retry_failed else []
    again += ["--no-report"] if args.no_report else []
    return again


def run_command(args: argparse.Namespace) -> int:
    """Run ``hapex sweep`` with parsed arguments; returns the exit code."""
    from planner.sweep import (
        SchedulerUnreachable,
        SweepBackendError,
        SweepInterrupted,
        load_sweep,
        pending,
        plan,
        run_sweep,
    )
    from planner.sweep.run import out_problem

    if args.jobs is not None and args.jobs < 1:
        return _bad(f"--jobs: {args.jobs}: must be >= 1")
    if args.dask_local is not None and args.dask_local < 1:
        return _bad(f"--dask-local: {args.dask_local}: must be >= 1")
    dask = args.scheduler is not None or args.dask_local is not None
    if dask and args.jobs is not None:
        return _bad("--jobs is for local runs; a Dask cluster runs as many as it has workers")
    sweep = load_sweep(args.sweep, quick=args.quick)
    runs = plan(sweep)  # every combination validated before anything starts
    if args.dry_run:
        for r in runs:
            print(f"{r.run_id}  {r.label}")
        print(f"{sweep.name}: {len(runs)} runs, all valid")
        return EXIT_OK
    out = args.out or Path("sweeps") / (sweep.name + ("-quick" if args.quick else ""))
    problem = out_problem(out, sweep)
    if problem:
        return _bad(f"--out: {out}: {problem}")
    todo, _ = pending(runs, out, args.retry_failed) if out.is_dir() else (runs, None)
    where = (
        f"Dask scheduler {args.scheduler}"
        if args.scheduler
        else f"a Dask LocalCluster of {args.dask_local} workers"
        if args.dask_local
        else f"joblib ({args.jobs or 'all'} processes)"
    )
    done = len(runs) - len(todo)
    print(f"{sweep.name}: {len(runs)} runs, {done} complete, {len(todo)} to run on {where}")
    try:
        table = run_sweep(
            sweep,
            out,
            backend="dask" if dask else "joblib",
            jobs=args.jobs,
            scheduler=args.scheduler,
            dask_workers=args.dask_local,
            retry_failed=args.retry_failed,
            report=not args.no_report,
        )
    except SchedulerUnreachable as exc:  # raised before anything is written
        return _bad(f"--scheduler: {exc.address}: {exc.reason}")
    except SweepInterrupted as exc:
        again = shlex.join(resume_command(args, out))
        print(f"{exc}; complete runs are kept. Resume with: {again}", file=sys.stderr)
        return EXIT_INTERRUPTED
    except SweepBackendError as exc:
        print(f"hapex sweep: {exc}. Run the same command again to resume.", file=sys.stderr)
        return EXIT_FAILED
    n_ok = int((table["status"] == "ok").sum())
    n_bad = len(table) - n_ok
    print(f"{sweep.name}: {len(table)} of {len(runs)} runs complete: {n_ok} ok, {n_bad} failed")
    print(f"results: {out / 'results.parquet'}, {out / 'results.csv'}")
    if not args.no_report:
        print(f"report: {out / 'report.md'}")
    return EXIT_OK if len(table) == len(runs) else EXIT_FAILED


__all__ = ["add_arguments", "resume_command", "run_command"]
