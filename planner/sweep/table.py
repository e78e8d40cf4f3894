"""The tidy results table of a sweep, rebuilt from its run directories.

One row per complete run: ``run_id``, every swept parameter (column = its key path),
``seed``, ``status``, ``reason``, every scalar metric, ``wall_s`` (run time on its worker
[s]) and ``host``. Metrics whose name collides with one of those columns get a ``metric.``
prefix; list- and mapping-valued metrics stay in ``result.json``.
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from planner.sweep.worker import read_run

FIXED = ("run_id", "seed", "status", "reason", "wall_s", "host")


def _cell(value: Any) -> Any:
    """A parameter value as a table cell: scalars as is, lists/mappings as JSON text."""
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return json.dumps(value, sort_keys=True)


def _scalar(value: Any) -> bool:
    return value is None or isinstance(value, (bool, int, float, str))


def _rows(out: Path, runs: Sequence | None) -> tuple[list[dict], list[str]]:
    runs_dir = Path(out) / "runs"
    if runs is None:
        found = sorted(runs_dir.iterdir()) if runs_dir.is_dir() else []
        wanted = [(p.name, None) for p in found if p.is_dir() and not p.name.startswith(".")]
    else:
        wanted = [(r.run_id, r.params) for r in runs]
    rows, params = [], []
    for rid, planned in wanted:
        found = read_run(runs_dir / rid)
        if found is None:
            continue
        result, meta = found
        p = planned if planned is not None else meta.get("params", {})
        params.extend(k for k in p if k not in params)
        row = {"run_id": rid, **{k: _cell(v) for k, v in p.items()}}
        row.update(seed=result.get("seed"), status=result["status"], reason=result["reason"])
        row["_metrics"] = {k: v for k, v in result.get("metrics", {}).items() if _scalar(v)}
        row.update(wall_s=meta.get("wall_s"), host=meta.get("host"))
        rows.append(row)
    return rows, params


def results_table(out: str | Path, runs: Sequence | None = None):
    """The tidy table (a ``pandas.DataFrame``) of the complete runs under ``out/runs``.

    Args:
        out: the sweep's output folder.
        runs: the planned runs (:func:`planner.sweep.plan`) whose rows to build, in order;
            default every complete run directory (sorted by run id).
    """
    import pandas as pd

    rows, params = _rows(Path(out), runs)
    taken = set(FIXED) | set(params)
    metric_cols: list[str] = []
    for row in rows:
        for k, v in row.pop("_metrics").items():
            col = f"metric.{k}" if k in taken else k
            row[col] = v
            if col not in metric_cols:
                metric_cols.append(col)
    columns = ["run_id", *params, "seed", "status", "reason", *metric_cols, "wall_s", "host"]
    df = pd.DataFrame(rows, columns=columns)
    for col in df.columns:  # a column of mixed types (e.g. 1 and "a") becomes text
        if df[col].dtype == object:
            kinds = {type(v) for v in df[col] if v is not None and v == v}
            if len(kinds) > 1 and not kinds <= {int, float}:
                df[col] = df[col].map(lambda v: None if v is None else str(v))
    df.attrs["params"] = params
    df.attrs["metrics"] = metric_cols
    return df


def write_tables(df, out: str | Path) -> tuple[Path, Path]:
    """Write ``results.parquet`` and ``results.csv`` in ``out`` (each atomically)."""
    out = Path(out)
    paths = []
    for name, write in (
        ("results.parquet", lambda p: df.to_parquet(p, index=False)),
        ("results.csv", lambda p: df.to_csv(p, index=False)),
    ):
        tmp = out / f".{name}.tmp-{os.getpid()}"
        try:
            write(tmp)
            os.replace(tmp, out / name)
        finally:
            tmp.unlink(missing_ok=True)
        paths.append(out / name)
    return paths[0], paths[1]


__all__ = ["FIXED", "results_table", "write_tables"]
