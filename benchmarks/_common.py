"""Shared helpers of the benchmark scripts: timing, environment stamp, CSV + Markdown report.

Every ``bench_*.py`` script prints a table on stdout and writes
``benchmarks/results/<name>.csv`` and ``<name>.md`` (override with ``--out DIR``), stamped with
hapex's git commit, the versions of hapex's dependencies and of every QP backend, the CPU,
the load average and the date (:func:`environment`). Benchmarks measure; they never assert on
time. The load average says whether the machine was shared while measuring.
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import platform
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from datetime import datetime, timezone
from pathlib import Path

#: The checkout these benchmarks belong to: measured code and stamped commit must match, so
#: its ``planner`` and ``robots`` shadow any other installed copy.
ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from planner.results import package_versions  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"


def cpu_name() -> str:
    """The CPU model name (from /proc/cpuinfo on Linux), or platform.processor()."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


#: Packages whose versions every report carries besides hapex's own dependency list
#: (the QP backends and the solvers behind the numbers).
SOLVER_PACKAGES = ("daqp", "proxsuite", "clarabel", "osqp", "qpsolvers", "casadi", "pin")


def git_commit() -> str:
    """hapex's git commit (short hash, ``+dirty`` with uncommitted changes outside
    ``benchmarks/results/``), or ``unknown``."""
    root = Path(__file__).resolve().parents[1]
    try:
        head = subprocess.run(
            ["git", "rev-parse", "--short=12", "HEAD"],
            cwd=root,
            capture_output=True,
            text=True,
            timeout=10,
            check=True,
        ).stdout
        dirty = subprocess.run(  # reports of earlier runs are results, not measured code
            [
                "git",
                "status",
                "--porcelain",
                "--untracked-files=no",
                "--",
                ".",
                ":(exclude)benchmarks/results",
            ],
            cwd=root,
            capture_output=True,
            text=True,
            timeout=10,
        ).stdout
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return head.strip() + ("+dirty" if dirty.strip() else "")


def solver_versions() -> dict[str, str]:
    """Versions of :data:`SOLVER_PACKAGES` (``"not installed"`` when missing)."""
    from importlib.metadata import PackageNotFoundError, version

    out = {}
    for name in SOLVER_PACKAGES:
        try:
            out[name] = version(name)
        except PackageNotFoundError:
            out[name] = "not installed"
    return out


def load_average() -> str:
    """The 1, 5 and 15 min load averages (``os.getloadavg``), or ``unknown``."""
    try:
        return " ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        return "unknown"


def environment() -> dict[str, str]:
    """Report header: date, git commit, CPU, cores, load average, platform and versions."""
    env = {
        "date": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "hapex_commit": git_commit(),
        "cpu": cpu_name(),
        "cores": str(os.cpu_count()),
        "load_average_1_5_15min": load_average(),
        "platform": platform.platform(),
    }
    env.update(package_versions())
    env.update(solver_versions())
    return env


def time_call(
    fn: Callable[[], object], *, repeat: int = 7, min_time: float = 0.05
) -> dict[str, float]:
    """Time ``fn()``: calls per batch chosen so a batch lasts ``min_time`` [s].

    Returns:
        ``{"best_s", "median_s", "calls"}``: per-call best and median over ``repeat``
        batches [s], and the batch size.
    """
    fn()  # warm-up (imports, caches, JIT of code paths)
    n = 1
    while True:
        t0 = time.perf_counter()
        for _ in range(n):
            fn()
        dt = time.perf_counter() - t0
        if dt >= min_time or n >= 1 << 20:
            break
        n *= 2 if dt == 0 else max(2, min(100, math.ceil(min_time / dt)))
    samples = [dt / n]
    for _ in range(repeat - 1):
        t0 = time.perf_counter()
        for _ in range(n):
            fn()
        samples.append((time.perf_counter() - t0) / n)
    return {"best_s": min(samples), "median_s": statistics.median(samples), "calls": n}


def shifted_geometric_mean(values: Sequence[float], shift: float = 1e-3) -> float:
    """Shifted geometric mean (qpbenchmark style) of positive values."""
    if not values:
        return float("nan")
    return math.exp(sum(math.log(v + shift) for v in values) / len(values)) - shift


def run_pool(fn, tasks: Sequence, jobs: int) -> list:
    """``fn`` over ``tasks`` in ``jobs`` spawned worker processes, with a progress bar on
    stderr; the results in the order they finished."""
    import multiprocessing as mp

    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover - tqdm is a dependency of the CLI
        tqdm = None
    rows = []
    with mp.get_context("spawn").Pool(max(1, jobs)) as pool:
        it = pool.imap_unordered(fn, tasks)
        for row in tqdm(it, total=len(tasks), desc="runs") if tqdm else it:
            rows.append(row)
    return rows


def comma_list(convert: Callable = str, choices: Sequence | None = None) -> Callable:
    """An argparse ``type`` for a comma-separated option (``--seeds 0,1``): each item passed
    through ``convert`` and, with ``choices``, one of them; a bad item is argparse's usage
    error (one line, exit 2)."""

    def parse(text: str) -> list:
        items = [t.strip() for t in text.split(",") if t.strip()]
        try:
            values = [convert(t) for t in items]
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"expected comma-separated {convert.__name__} values, got {text!r}"
            ) from None
        if choices is not None and (bad := [v for v in values if v not in choices]):
            raise argparse.ArgumentTypeError(f"unknown {bad}; known: {', '.join(choices)}")
        return values

    return parse


def arg_parser(description: str) -> argparse.ArgumentParser:
    """An argparse parser with the options every benchmark script takes."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--out", type=Path, default=RESULTS, help="folder for the CSV/Markdown report")
    p.add_argument("--quick", action="store_true", help="smaller sizes, for a smoke test")
    return p


def _fmt(v: object) -> str:
    if isinstance(v, float):
        if v == 0 or math.isnan(v):
            return f"{v:g}"
        return f"{v:.4g}" if 1e-3 <= abs(v) < 1e5 else f"{v:.3e}"
    return str(v)


def markdown_table(rows: Sequence[dict], columns: Sequence[str]) -> str:
    """Rows (dicts) as a GitHub Markdown table in the given column order."""
    head = "| " + " | ".join(columns) + " |"
    sep = "|" + "|".join("---" for _ in columns) + "|"
    body = ["| " + " | ".join(_fmt(r.get(c, "")) for c in columns) + " |" for r in rows]
    return "\n".join([head, sep, *body])


def write_report(
    name: str,
    rows: Sequence[dict],
    *,
    title: str,
    out: Path = RESULTS,
    notes: Sequence[str] = (),
    columns: Sequence[str] | None = None,
) -> Path:
    """Print the table and write ``<out>/<name>.csv`` and ``<out>/<name>.md``.

    Returns:
        The Markdown file's path.
    """
    if columns is None:
        columns = list(dict.fromkeys(k for r in rows for k in r))
    table = markdown_table(rows, columns)
    print(f"\n{title}\n")
    print(table)
    for n in notes:
        print(f"- {n}")
    env = environment()  # before writing: a rewritten tracked report is not a dirty tree
    out.mkdir(parents=True, exist_ok=True)
    with open(out / f"{name}.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(columns), extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow(r)
    md = [
        f"# {title}",
        "",
        "| | |",
        "|---|---|",
        *(f"| {k} | {v} |" for k, v in env.items()),
        "",
        table,
        "",
    ]
    md += [f"- {n}" for n in notes]
    path = out / f"{name}.md"
    path.write_text("\n".join(md) + "\n")
    print(f"\nwrote {out / (name + '.csv')} and {path}")
    return path


__all__ = [
    "SOLVER_PACKAGES",
    "arg_parser",
    "cpu_name",
    "environment",
    "git_commit",
    "load_average",
    "markdown_table",
    "shifted_geometric_mean",
    "solver_versions",
    "time_call",
    "write_report",
]
