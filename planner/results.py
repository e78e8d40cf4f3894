"""Run results and the run directory (contract in DESIGN.md).

A runner returns a :class:`RunResult`; :func:`write_run_directory` writes it atomically:
everything goes to a temporary sibling directory that is renamed to the final name only when
complete, so an interrupted run never leaves a half-written run directory behind.

Run directory layout::

    scenario.yaml     the resolved scenario (defaults filled in, overrides applied)
    result.json       {"schema": 1, "name", "kind", "status", "reason", "seed", "metrics",
                       "events", "timings_s", "versions", "files"}
    trajectory.npz    the arrays (time series, traces, maps)
    plots/*.png       figures (other formats if the scenario's output.formats asks)
    *                 extra files a runner adds (e.g. gait.json, features.geojson,
                      plots/animation.gif): text, bytes, or written by a callback
"""

from __future__ import annotations

import json
import math
import os
import platform
import shutil
import tempfile
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from datetime import datetime, timezone
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any, Literal

import numpy as np
import yaml

from planner.errors import HapexError

SCHEMA_VERSION = 1

#: What an extra file of a run directory holds: text (UTF-8), raw bytes, or a writer called
#: with the file's path inside the (temporary) run directory, which must create that file.
FileContent = str | bytes | Callable[[Path], None]

#: Names the run directory writes itself; an extra file may not take them.
_RESERVED = ("scenario.yaml", "result.json", "trajectory.npz")
_VERSIONED = (
    "hapex",
    "pin",
    "casadi",
    "numpy",
    "scipy",
    "shapely",
    "qpsolvers",
    "osqp",
    "pydantic",
    "matplotlib",
)


@dataclass(frozen=True)
class Event:
    """Something that happened during a run.

    Attributes:
        t: simulation time or step index at which it happened (``None`` when not timed) [s].
        kind: short machine-readable tag, e.g. ``"phase_transition"``, ``"solver_failed"``.
        message: human-readable sentence.
        data: extra JSON-serialisable details.
    """

    kind: str
    message: str = ""
    t: float | None = None
    data: Mapping[str, Any] = field(default_factory=dict)

    def to_json(self) -> dict[str, Any]:
        return {"t": self.t, "kind": self.kind, "message": self.message, "data": dict(self.data)}


@dataclass
class RunResult:
    """What a scenario runner returns.

    Attributes:
        status: ``"ok"`` or ``"failed"`` (the scenario ran but its task failed; exit code 1).
        reason: why it failed (empty when ok).
        metrics: scalar results, JSON-serialisable (floats, ints, bools, strings, small lists).
        arrays: named numpy arrays written to ``trajectory.npz``.
        events: what happened during the run, in order.
        figures: name -> matplotlib Figure, saved as ``plots/<name>.<fmt>``.
        files: relative path -> content of extra files of the run directory: ``str``
            (written as UTF-8 text, e.g. ``{"gait.json": "..."}``), ``bytes`` (written as
            is, e.g. ``{"plots/animation.gif": b"GIF89a..."}``), or a writer callback
            ``f(path)`` that creates the file at ``path`` (for large outputs streamed to
            disk). Every file is written inside the temporary run directory, so a writer
            that raises leaves nothing behind (see :func:`write_run_directory`).
    """

    status: Literal["ok", "failed"] = "ok"
    reason: str = ""
    metrics: dict[str, Any] = field(default_factory=dict)
    arrays: dict[str, np.ndarray] = field(default_factory=dict)
    events: list[Event] = field(default_factory=list)
    figures: dict[str, Any] = field(default_factory=dict)
    files: dict[str, FileContent] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.status not in ("ok", "failed"):
            raise ValueError(f"status must be 'ok' or 'failed', got {self.status!r}")


def package_versions() -> dict[str, str]:
    """Versions of hapex and its main dependencies (``"not installed"`` when missing)."""
    out = {}
    for name in _VERSIONED:
        try:
            out[name] = version(name)
        except PackageNotFoundError:
            out[name] = "not installed"
    out["python"] = platform.python_version()
    out["numpy_simd"] = numpy_simd()
    return out


def numpy_dispatch_targets() -> list[str]:
    """NumPy's runtime SIMD dispatch targets: those its build can dispatch to (``X86_V3``,
    ``AVX512_ICL``, ...), whether this CPU runs them or not ([] when NumPy does not say)."""
    return list(_numpy_cpu()[0])


def numpy_simd() -> str:
    """NumPy's SIMD dispatch targets this CPU runs (e.g. ``"X86_V3 X86_V4 AVX512_ICL"``;
    ``"baseline"`` when none). They decide how NumPy's ``exp``, ``arctan2``, ``hypot``, ...
    round (AVX-512 ones differ from the C library in the last bit), so a chaotic run (a
    stalling gait) is reproduced to the bit only with the same targets: the runs of one
    machine agree, another CPU's can end at other angles."""
    targets, features = _numpy_cpu()
    return " ".join(t for t in targets if features.get(t)) or "baseline"


def _numpy_cpu() -> tuple[list, dict]:
    """NumPy's ``(__cpu_dispatch__, __cpu_features__)`` (empty where it has none)."""
    try:
        from numpy._core import _multiarray_umath as mu
    except ImportError:  # NumPy < 2
        try:
            from numpy.core import _multiarray_umath as mu
        except ImportError:
            return [], {}
    return list(getattr(mu, "__cpu_dispatch__", [])), dict(getattr(mu, "__cpu_features__", {}))


def to_jsonable(value: Any) -> Any:
    """Convert numpy scalars/arrays, tuples and non-finite floats to plain JSON values.

    NaN and infinities become ``None`` (JSON has no representation for them).
    """
    if isinstance(value, Mapping):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return to_jsonable(value.tolist())
    if isinstance(value, (np.bool_, bool)):
        return bool(value)
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        f = float(value)
        return f if math.isfinite(f) else None
    return value


def out_path_problem(out: Path) -> str | None:
    """Why no folder can be created at ``out``: it, or its nearest existing parent, is not a
    directory (``"afile is a file, not a directory"``); ``None`` when one can (or is there).
    Checked by the commands before any work, so a bad ``--out`` is bad input, not a crash."""
    out = Path(out)
    for path in (out, *out.parents):  # nearest first; the first that exists decides
        if path.exists():
            if path.is_dir():
                return None
            if path == out:
                return "exists and is not a directory"
            return f"{path} is a file, not a directory"
        if path.is_symlink():
            return f"{path} is a broken symbolic link"
    return None


def out_folder_problem(out: Path, marker: str, what: str) -> str | None:
    """Why a command cannot write its folder at ``out`` (``None`` when it can): a file is in
    the way (:func:`out_path_problem`), or ``out`` is a non-empty folder without ``marker``
    (the file an earlier result of the same command holds), i.e. not ``what``."""
    out = Path(out)
    problem = out_path_problem(out)
    if problem is None and out.is_dir() and any(out.iterdir()) and not (out / marker).is_file():
        problem = f"directory is not empty and is not {what}; choose another --out or remove it"
    return problem


def run_directory_problem(out_dir: Path) -> str | None:
    """Why a run directory cannot be written at ``out_dir`` (``None`` when it can)."""
    return out_folder_problem(out_dir, "result.json", "a hapex run directory")


def _prepare_target(out_dir: Path) -> None:
    """Refuse to replace a directory that is neither empty nor a previous hapex run."""
    problem = run_directory_problem(out_dir)
    if problem:
        raise HapexError(f"--out {out_dir}: {problem}")


def _save_figures(
    folder: Path, figures: Mapping[str, Any], plot_formats: tuple[str, ...], dpi: int
) -> dict[str, str]:
    """Save every figure under ``folder/plots`` in every format; the ``files`` entries."""
    import matplotlib.pyplot as plt

    (folder / "plots").mkdir()
    files = {}
    for fig_name, fig in figures.items():
        for fmt in plot_formats:
            rel = f"plots/{fig_name}.{fmt}"
            fig.savefig(folder / rel, dpi=dpi, bbox_inches="tight")
            key = f"plot:{fig_name}" if fmt == plot_formats[0] else f"plot:{fig_name}:{fmt}"
            files[key] = rel
        plt.close(fig)
    return files


def _check_file_name(name: str) -> Path:
    """``name`` as a relative path that stays inside the run directory."""
    rel = Path(name)
    if not name or rel.is_absolute() or ".." in rel.parts or name in _RESERVED:
        raise HapexError(
            f"RunResult.files: {name!r} is not a valid extra file name (expected a relative "
            f"path inside the run directory, not one of {list(_RESERVED)})"
        )
    return rel


def _write_files(folder: Path, files: Mapping[str, FileContent]) -> dict[str, str]:
    """Write the extra files (text, bytes or writer callbacks) under ``folder``; the
    ``files`` entries of result.json."""
    out = {}
    for name, content in files.items():
        target = folder / _check_file_name(name)
        target.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, str):
            target.write_text(content, encoding="utf-8")
        elif isinstance(content, (bytes, bytearray, memoryview)):
            target.write_bytes(bytes(content))
        elif callable(content):
            content(target)
            if not target.is_file():
                raise HapexError(f"RunResult.files: the writer of {name!r} did not create it")
        else:
            raise HapexError(
                f"RunResult.files: {name!r} holds a {type(content).__name__}; expected str, "
                "bytes or a writer callback f(path)"
            )
        out[name] = name
    return out


def replace_directory(tmp: Path, target: Path) -> None:
    """Move the complete folder ``tmp`` to ``target`` by renames, replacing a previous
    ``target`` (moved aside first, then removed), so ``target`` is never half-written."""
    old = None
    if target.exists():
        old = target.with_name(f".{target.name}.old-{os.getpid()}")
        os.replace(target, old)
    os.replace(tmp, target)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


def write_run_directory(
    out_dir: Path,
    result: RunResult,
    *,
    name: str,
    kind: str,
    seed: int,
    resolved_scenario: Mapping[str, Any],
    timings_s: Mapping[str, float],
    plot_formats: tuple[str, ...] = ("png",),
    dpi: int = 120,
) -> Path:
    """Write ``result`` as a complete run directory at ``out_dir``, atomically.

    Args:
        out_dir: final path of the run directory. An existing previous run there is replaced;
            an existing non-empty directory that is not a run directory is an error.
        result: what the runner returned.
        name, kind, seed: scenario identity, copied into ``result.json``.
        resolved_scenario: the validated scenario as plain data (written as scenario.yaml).
        timings_s: wall-clock time per stage [s].
        plot_formats: file formats for figures (``png``, ``svg``, ``pdf``).
        dpi: resolution of raster figures [dots per inch].

    Returns:
        ``out_dir``.

    Raises:
        HapexError: ``out_dir`` is not replaceable, or an extra file has a bad name or
            content; like any exception while writing (a failing writer callback included),
            nothing is left behind and a previous run at ``out_dir`` stays as it was.
    """
    out_dir = Path(out_dir)
    _prepare_target(out_dir)
    out_dir.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.tmp-", dir=out_dir.parent))
    try:
        files: dict[str, str] = {"scenario": "scenario.yaml", "result": "result.json"}
        with open(tmp / "scenario.yaml", "w") as fh:
            yaml.safe_dump(to_jsonable(dict(resolved_scenario)), fh, sort_keys=False)
        if result.arrays:
            np.savez_compressed(
                tmp / "trajectory.npz", **{k: np.asarray(v) for k, v in result.arrays.items()}
            )
            files["trajectory"] = "trajectory.npz"
        if result.figures:
            files.update(_save_figures(tmp, result.figures, plot_formats, dpi))
        files.update(_write_files(tmp, result.files))
        doc = {
            "schema": SCHEMA_VERSION,
            "name": name,
            "kind": kind,
            "status": result.status,
            "reason": result.reason,
            "seed": seed,
            "metrics": to_jsonable(result.metrics),
            "events": [to_jsonable(e.to_json()) for e in result.events],
            "timings_s": to_jsonable(dict(timings_s)),
            "versions": package_versions(),
            "created": datetime.now(timezone.utc).isoformat(timespec="seconds"),
            "files": files,
        }
        with open(tmp / "result.json", "w") as fh:
            json.dump(doc, fh, indent=2, allow_nan=False)
        replace_directory(tmp, out_dir)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return out_dir


__all__ = [
    "Event",
    "FileContent",
    "RunResult",
    "numpy_dispatch_targets",
    "numpy_simd",
    "out_folder_problem",
    "out_path_problem",
    "package_versions",
    "replace_directory",
    "run_directory_problem",
    "to_jsonable",
    "write_run_directory",
]
