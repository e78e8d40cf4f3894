"""Running a sweep: resume, dispatch to a backend, install run directories, tables, report.

Output folder layout::

    DIR/sweep.json        the study: name, source file, quick, number of runs
    DIR/runs/<run-id>/    the normal run directory of every run, plus sweep.json
    DIR/results.parquet   the tidy table (also results.csv), rebuilt from DIR/runs
    DIR/report.md         plots of the study (DIR/report/*.png) and a table of failures

A run is complete when its run directory is (they are installed atomically). Starting the
same sweep again skips complete runs and runs the missing ones (failed ones too with
``retry_failed``), so an interrupted study loses at most the runs that were in flight.
"""

from __future__ import annotations

import json
import os
import signal
import threading
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from planner.checks import choice, integer
from planner.errors import HapexError, InvalidParameter
from planner.results import out_folder_problem
from planner.sweep.expansion import PlannedRun, as_sweep, plan
from planner.sweep.spec import Sweep
from planner.sweep.worker import Finished, Task, install, read_run

STUDY_FILE = "sweep.json"


class SweepInterrupted(KeyboardInterrupt):
    """Ctrl-C during a sweep: the complete runs are kept; run the same sweep again to resume.

    Attributes:
        done: runs complete in ``out`` (ok or failed).
        total: runs of the sweep.
        out: the sweep's output folder.
    """

    def __init__(self, done: int, total: int, out: Path):
        super().__init__(f"interrupted: {done} of {total} runs complete in {out}")
        self.done, self.total, self.out = done, total, out


def out_problem(out: Path, sweep: Sweep) -> str | None:
    """Why ``out`` cannot hold this sweep (``None`` when it can): it or a parent is a file,
    it holds another sweep, or it is a non-empty folder that is not a sweep. Reads only."""
    problem = out_folder_problem(out, STUDY_FILE, "a hapex sweep")
    study = out / STUDY_FILE
    if problem or not study.is_file():
        return problem
    try:
        name = json.loads(study.read_text()).get("name")
    except (OSError, ValueError, AttributeError):
        name = None
    if name != sweep.name:
        return f"holds the sweep {name!r}, not {sweep.name!r}; choose another --out"
    return None


def _write_study(out: Path, sweep: Sweep, n_runs: int) -> None:
    """Create ``out`` (checked by :func:`out_problem`) and write its ``sweep.json``."""
    (out / "runs").mkdir(parents=True, exist_ok=True)
    doc = {
        "name": sweep.name,
        "description": sweep.model.description,
        "source": sweep.source,
        "quick": sweep.quick,
        "runs": n_runs,
        "updated": datetime.now(timezone.utc).isoformat(timespec="seconds"),
    }
    tmp = out / f".{STUDY_FILE}.tmp-{os.getpid()}"
    tmp.write_text(json.dumps(doc, indent=2))
    os.replace(tmp, out / STUDY_FILE)


def pending(
    runs: list[PlannedRun], out: Path, retry_failed: bool = False
) -> tuple[list[PlannedRun], dict[str, int]]:
    """The runs still to do, and the counts of complete ones (``{"ok": n, "failed": m}``)."""
    todo, counts = [], {"ok": 0, "failed": 0}
    for r in runs:
        found = read_run(Path(out) / "runs" / r.run_id)
        status = found[0]["status"] if found else None
        if status == "ok" or (status == "failed" and not retry_failed):
            counts[status] += 1
        else:
            todo.append(r)
    return todo, counts


def _task(r: PlannedRun, sweep: str) -> Task:
    return Task(r.run_id, sweep, dict(r.params), dict(r.data), str(r.base_dir), r.quick, r.plots)


@contextmanager
def _sigint_between_runs(active: bool) -> Iterator[Callable[[], bool]]:
    """While runs execute in this process, Ctrl-C stops the sweep after the current run.

    A KeyboardInterrupt raised at an arbitrary point of a run can land inside an import or a
    compiled extension (numba, CasADi, pyarrow) and leave the process in a state that crashes
    at exit; so the first SIGINT only sets a flag that :func:`_install_all` checks between
    runs, and a second one interrupts at once. Yields the flag's reader. Outside the main
    thread or with worker processes (they get the terminal's SIGINT themselves) nothing
    changes.
    """
    if not active or threading.current_thread() is not threading.main_thread():
        yield lambda: False
        return
    pending: list[int] = []

    def handler(signum, frame):
        if pending:
            raise KeyboardInterrupt
        pending.append(signum)

    old = signal.signal(signal.SIGINT, handler)
    try:
        yield lambda: bool(pending)
    finally:
        signal.signal(signal.SIGINT, old)


def _install_all(results, out: Path, counts: dict, bar, on_result, stop=lambda: False) -> None:
    """Install each finished run as it arrives; keep the counts and the progress bar;
    raise KeyboardInterrupt between runs when ``stop()`` says Ctrl-C was pressed."""
    left = bar.total - bar.n
    for fin in results:
        install(fin.archive, out / "runs" / fin.run_id)
        counts[fin.status] += 1
        left -= 1
        bar.update(1)
        bar.set_postfix(ok=counts["ok"], failed=counts["failed"], left=left)
        if on_result is not None:
            on_result(fin)
        if stop():
            raise KeyboardInterrupt


def run_sweep(
    sweep: Sweep | str | Path | Mapping[str, Any],
    out: str | Path,
    *,
    backend: str = "joblib",
    jobs: int | None = None,
    scheduler: str | None = None,
    dask_workers: int | None = None,
    client: Any = None,
    processes: bool = True,
    quick: bool = False,
    retry_failed: bool = False,
    progress: bool | None = None,
    report: bool = True,
    on_result: Callable[[Finished], None] | None = None,
):
    """Run every missing run of a sweep and return its tidy table.

    Args:
        sweep: a :class:`Sweep`, a sweep file, or a mapping.
        out: output folder (created; reused to resume the same study).
        backend: ``"joblib"`` (local processes) or ``"dask"``.
        jobs: joblib worker processes (default: all cores; 1 runs in this process).
        scheduler: Dask scheduler address (``tcp://host:8786``) of an existing cluster.
        dask_workers: workers of the ``LocalCluster`` started when no scheduler/client is
            given (default: all cores).
        client: an existing ``distributed.Client`` to use (backend ``"dask"``).
        processes: LocalCluster workers as processes (``False``: threads of this process).
        quick: the sweep file's ``--quick`` variant (when ``sweep`` is a path or mapping).
        retry_failed: run failed runs again (default: a failed run is a result and is kept).
        progress: tqdm progress bar (``None``: only on a terminal).
        report: write ``report.md`` and its plots.
        on_result: called with each finished run after its directory is installed.

    Returns:
        The ``pandas.DataFrame`` also written as ``results.parquet`` / ``results.csv``.

    Raises:
        ScenarioError: the sweep or one of its combinations is invalid (nothing has run).
        SweepInterrupted: Ctrl-C; complete runs are kept and the tables written.
        SchedulerUnreachable: ``scheduler`` is malformed or does not answer (nothing
            written).
        HapexError: the output folder cannot be used (nothing written), or the backend
            failed.
    """
    from contextlib import ExitStack

    from tqdm.auto import tqdm

    from planner.sweep import backends
    from planner.sweep.report import write_report
    from planner.sweep.table import results_table, write_tables

    choice("backend", backend, ("joblib", "dask"))
    if jobs is not None:
        integer("jobs", jobs, minimum=1)
    if backend == "joblib" and (scheduler or client is not None or dask_workers):
        raise InvalidParameter(
            "backend: scheduler, client and dask_workers need backend='dask', got 'joblib'"
        )
    sweep = as_sweep(sweep, quick)
    runs = plan(sweep)
    out = Path(out)
    problem = out_problem(out, sweep)
    if problem:
        raise HapexError(f"--out {out}: {problem}")
    todo, counts = pending(runs, out, retry_failed)
    with ExitStack() as stack:
        if backend == "dask" and todo and client is None:
            # reach the cluster (or start the LocalCluster) before writing anything: a bad or
            # unreachable scheduler then leaves no folder behind
            client = stack.enter_context(
                backends.dask_client(scheduler, dask_workers, processes=processes)
            )
        _write_study(out, sweep, len(runs))
        bar = tqdm(
            total=len(runs),
            initial=len(runs) - len(todo),
            desc=sweep.name,
            unit="run",
            disable=None if progress is None else not progress,
        )
        bar.set_postfix(ok=counts["ok"], failed=counts["failed"], left=len(todo))
        interrupted = False
        try:
            if todo:
                tasks = [_task(r, sweep.name) for r in todo]
                in_process = backend == "joblib" and jobs == 1
                with _sigint_between_runs(in_process) as stop:
                    if backend == "joblib":
                        results = backends.joblib_results(tasks, jobs)
                    else:
                        results = backends.dask_results(tasks, client)
                    _install_all(results, out, counts, bar, on_result, stop)
        except KeyboardInterrupt:
            interrupted = True
        finally:
            bar.close()
            table = results_table(out, runs)
            write_tables(table, out)
            if report:
                write_report(table, out, sweep)
    if interrupted:
        raise SweepInterrupted(len(table), len(runs), out)
    return table


__all__ = ["STUDY_FILE", "SweepInterrupted", "out_problem", "pending", "run_sweep"]
