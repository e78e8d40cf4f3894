"""One run of a sweep on a worker, and its installation on the client.

Where results go: **workers send them back to the client**. A worker runs the scenario,
writes its normal run directory into a private temporary folder with
:func:`planner.results.write_run_directory` (figures rendered on the worker), packs it into
an uncompressed tar archive (bytes) and returns it; the client unpacks it next to
``DIR/runs/<run-id>`` and renames it into place. Workers therefore need no shared
filesystem, only the same hapex installation; the client's disk is the one source of truth,
and a run directory appears complete or not at all.
"""

from __future__ import annotations

import io
import json
import shutil
import socket
import tarfile
import tempfile
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

#: file added to every run directory of a sweep: run id, sweep, parameters, host, wall time
SWEEP_FILE = "sweep.json"


@dataclass(frozen=True)
class Task:
    """What travels to a worker: plain data only (no pydantic objects, no open files)."""

    run_id: str
    sweep: str
    params: dict[str, Any]
    data: dict[str, Any]
    base_dir: str
    quick: bool = False
    plots: bool = False


@dataclass(frozen=True)
class Finished:
    """What a worker sends back: the packed run directory and a summary.

    Attributes:
        archive: tar of the run directory's contents (bytes).
        wall_s: wall-clock time of the run on the worker, writing included [s].
    """

    run_id: str
    status: str
    reason: str
    host: str
    wall_s: float
    archive: bytes = field(repr=False)


def _run(task: Task):
    """(result, timings, resolved scenario, output settings); a crash is a failed run."""
    from planner.results import Event, RunResult
    from planner.runner import run_config
    from planner.scenario import scenario_from_dict

    try:
        config = scenario_from_dict(task.data)
        result, timings = run_config(
            config, plots=task.plots, quick=task.quick, base_dir=Path(task.base_dir)
        )
        return result, timings, config.model_dump(mode="json"), config.output
    except Exception as exc:  # one run that crashes is a failed run, not the end of the study
        result = RunResult(
            status="failed",
            reason=f"{type(exc).__name__}: {exc}".splitlines()[0],
            events=[Event("exception", traceback.format_exc())],
        )
        return result, {}, dict(task.data), None


def run_task(task: Task) -> Finished:
    """Run one task and return its packed run directory (called on the worker)."""
    from planner.results import write_run_directory

    t0 = time.perf_counter()
    result, timings, resolved, output = _run(task)
    host = socket.gethostname()
    with tempfile.TemporaryDirectory(prefix="hapex-sweep-") as tmp:
        out = Path(tmp) / task.run_id
        meta = {"run_id": task.run_id, "sweep": task.sweep, "params": task.params, "host": host}
        result.files[SWEEP_FILE] = json.dumps(meta)  # completed with wall_s below
        write_run_directory(
            out,
            result,
            name=str(task.data.get("name", task.sweep)),
            kind=str(task.data.get("kind", "?")),
            seed=int(task.data.get("seed", 0)),
            resolved_scenario=resolved,
            timings_s=timings,
            plot_formats=tuple(output.formats) if output else ("png",),
            dpi=output.dpi if output else 120,
        )
        wall = time.perf_counter() - t0
        (out / SWEEP_FILE).write_text(json.dumps({**meta, "wall_s": wall}))
        archive = pack(out)
    return Finished(task.run_id, result.status, result.reason, host, wall, archive)


def pack(run_dir: Path) -> bytes:
    """The contents of a directory as an uncompressed tar archive."""
    buf = io.BytesIO()
    with tarfile.open(fileobj=buf, mode="w") as tar:
        for path in sorted(Path(run_dir).rglob("*")):
            tar.add(path, arcname=str(path.relative_to(run_dir)), recursive=False)
    return buf.getvalue()


def _extract(tar: tarfile.TarFile, dest: Path) -> None:
    """Extract plain files and folders inside ``dest`` only (no links, no ``..``)."""
    if hasattr(tarfile, "data_filter"):
        tar.extractall(dest, filter="data")
        return
    for m in tar.getmembers():  # Python < 3.10.12 / 3.11.4: the same rules by hand
        if not (m.isfile() or m.isdir()) or m.name.startswith("/") or ".." in Path(m.name).parts:
            raise ValueError(f"refusing to unpack {m.name!r} from a run archive")
    tar.extractall(dest)


def install(archive: bytes, run_dir: Path) -> Path:
    """Unpack a run directory at ``run_dir`` atomically (temporary sibling, then rename);
    a previous run directory there (a failed run being retried) is replaced."""
    from planner.results import replace_directory

    run_dir = Path(run_dir)
    run_dir.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{run_dir.name}.tmp-", dir=run_dir.parent))
    try:
        with tarfile.open(fileobj=io.BytesIO(archive), mode="r") as tar:
            _extract(tar, tmp)
        replace_directory(tmp, run_dir)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return run_dir


def lost_run(task: Task, reason: str) -> Finished:
    """A failed run the client records itself when its worker could not return it (e.g. the
    run killed every worker it was given: Dask's ``KilledWorker``)."""
    from planner.results import Event, RunResult, write_run_directory

    result = RunResult(status="failed", reason=reason, events=[Event("lost", reason)])
    host = socket.gethostname()
    meta = {"run_id": task.run_id, "sweep": task.sweep, "params": task.params, "host": host}
    result.files[SWEEP_FILE] = json.dumps({**meta, "wall_s": None})
    with tempfile.TemporaryDirectory(prefix="hapex-sweep-") as tmp:
        out = write_run_directory(
            Path(tmp) / task.run_id,
            result,
            name=str(task.data.get("name", task.sweep)),
            kind=str(task.data.get("kind", "?")),
            seed=int(task.data.get("seed", 0)),
            resolved_scenario=task.data,
            timings_s={},
        )
        return Finished(task.run_id, "failed", reason, host, float("nan"), pack(out))


def read_run(run_dir: Path) -> tuple[dict, dict] | None:
    """``(result.json, sweep.json)`` of a complete run directory, or ``None``."""
    try:
        result = json.loads((Path(run_dir) / "result.json").read_text())
        meta = json.loads((Path(run_dir) / SWEEP_FILE).read_text())
    except (OSError, ValueError):
        return None
    if meta.get("run_id") != Path(run_dir).name or result.get("status") not in ("ok", "failed"):
        return None
    return result, meta


__all__ = ["SWEEP_FILE", "Finished", "Task", "install", "lost_run", "pack", "read_run", "run_task"]
