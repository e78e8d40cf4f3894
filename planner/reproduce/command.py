"""``hapex reproduce [--quick] [--out DIR] [--only ID ...] [--jobs N] [-v]``.

Runs the claims, writes ``DIR/report.md``, ``DIR/claims.json`` and ``DIR/figures/`` into a
temporary sibling folder and renames it when complete (an existing report folder is
replaced; a foreign non-empty folder is refused). Exit code 0 when every implemented claim is
reproduced or explained, 1 otherwise, 2 for bad options (an unknown claim id).
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
from datetime import datetime
from pathlib import Path

from planner.exit_codes import EXIT_BAD_INPUT, EXIT_OK

__all__ = ["add_arguments", "run"]


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the options of ``hapex reproduce`` on ``p``."""
    p.add_argument("--quick", action="store_true", help="short checks (the test suite's mode)")
    p.add_argument(
        "--out", type=Path, default=None, help="report folder (default: runs/reproduce-<timestamp>)"
    )
    p.add_argument(
        "--only",
        nargs="+",
        default=None,
        metavar="ID",
        help="run only these claims (see the report's ids, e.g. fig3.7 tableB.1)",
    )
    p.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    p.add_argument("--list", action="store_true", help="list the claims and exit")
    p.add_argument("-v", "--verbose", action="store_true", help="tracebacks of broken checks")


def _out_problem(out: Path) -> str | None:
    """Why ``out`` cannot take the report (a file is in the way, or a folder that is not an
    earlier report); ``None`` when it can. Reads only."""
    from planner.results import out_folder_problem

    return out_folder_problem(out, "claims.json", "a hapex reproduce folder")


def run(args: argparse.Namespace) -> int:
    """Run ``hapex reproduce``; returns the exit code."""
    from planner.errors import InvalidParameter
    from planner.reproduce.execute import run_claims
    from planner.reproduce.registry import select
    from planner.reproduce.report import exit_code, write_claims_json, write_report
    from planner.results import replace_directory

    if args.jobs < 1:
        print(f"--jobs: {args.jobs}: must be >= 1", file=sys.stderr)
        return EXIT_BAD_INPUT
    try:
        claims = select(args.only)
    except InvalidParameter as exc:
        print(f"--only: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    if args.list:
        for c in claims:
            print(f"{c.id:14s} {c.reference:32s} {c.statement}")
        return EXIT_OK
    out = args.out or Path("runs") / f"reproduce-{datetime.now():%Y%m%d-%H%M%S}"
    problem = _out_problem(out)
    if problem:
        print(f"--out: {out}: {problem}", file=sys.stderr)
        return EXIT_BAD_INPUT
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.tmp-", dir=out.parent))
    try:
        width = max(len(c.id) for c in claims)

        def show(r) -> None:
            line = f"{r.claim.id:{width}s}  {r.evidence.verdict.value:15s} {r.seconds:6.1f} s"
            print(f"{line}  {r.evidence.key_number}"[:160], flush=True)
            if r.error and args.verbose:
                print(r.error, file=sys.stderr)

        results = run_claims(
            [c.id for c in claims],
            quick=args.quick,
            figures=tmp / "figures",
            jobs=args.jobs,
            progress=show,
        )
        write_report(results, tmp / "report.md", quick=args.quick)
        write_claims_json(results, tmp / "claims.json", quick=args.quick)
        replace_directory(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    code = exit_code(results)
    print(
        f"report: {out / 'report.md'}"
        + ("" if code == 0 else " (some claims errored or differ without explanation)")
    )
    return code
