"""Boundary samples from a data file: CSV or NPZ with columns ``feature_id, x, y`` [m].

CSV: a header line naming the columns ``feature_id``, ``x``, ``y`` (any order, other columns
ignored; ``#`` comment lines and blank lines skipped), then one sample per line. NPZ: arrays
``feature_id``, ``x``, ``y`` of equal length. Features keep the order of first appearance.
Every problem is reported at once as a :class:`ScenarioError` with file and line.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from planner.errors import InputIssue, ScenarioError

COLUMNS = ("feature_id", "x", "y")


def _group(ids: list[str], xy: np.ndarray) -> tuple[list[str], list[np.ndarray]]:
    order: dict[str, list[int]] = {}
    for k, i in enumerate(ids):
        order.setdefault(i, []).append(k)
    return list(order), [xy[np.asarray(v)] for v in order.values()]


def _read_csv(path: Path, src: str) -> tuple[list[str], list[np.ndarray]]:
    issues: list[InputIssue] = []
    ids: list[str] = []
    rows: list[tuple[float, float]] = []
    header: dict[str, int] | None = None
    with open(path, newline="") as fh:
        for lineno, row in enumerate(csv.reader(fh), start=1):
            if not row or not "".join(row).strip() or row[0].lstrip().startswith("#"):
                continue
            cells = [c.strip() for c in row]
            if header is None:
                header = {c: k for k, c in enumerate(cells)}
                missing = [c for c in COLUMNS if c not in header]
                if missing:
                    raise ScenarioError(
                        [
                            InputIssue(
                                src,
                                lineno,
                                "(header)",
                                f"missing column(s) {missing}; expected a header naming "
                                f"{list(COLUMNS)}, got {cells}",
                            )
                        ]
                    )
                continue
            if len(cells) <= max(header[c] for c in COLUMNS):
                issues.append(
                    InputIssue(
                        src, lineno, "(row)", f"expected {len(header)} columns, got {len(cells)}"
                    )
                )
                continue
            vals = []
            for col in ("x", "y"):
                text = cells[header[col]]
                try:
                    v = float(text)
                except ValueError:
                    v = math.nan
                if not math.isfinite(v):
                    issues.append(
                        InputIssue(src, lineno, col, f"expected a finite number [m], got {text!r}")
                    )
                vals.append(v)
            fid = cells[header["feature_id"]]
            if not fid:
                issues.append(InputIssue(src, lineno, "feature_id", "empty feature_id"))
            ids.append(fid)
            rows.append((vals[0], vals[1]))
    if header is None:
        issues.append(
            InputIssue(
                src, 1, "(root)", f"empty file; expected a header {list(COLUMNS)} and samples"
            )
        )
    if issues:
        raise ScenarioError(issues)
    return _group(ids, np.asarray(rows, dtype=float).reshape(-1, 2))


def _read_npz(path: Path, src: str) -> tuple[list[str], list[np.ndarray]]:
    try:
        data = np.load(path, allow_pickle=False)
    except (OSError, ValueError) as exc:
        raise ScenarioError(
            [InputIssue(src, 0, "(root)", f"not a readable npz file: {exc}")]
        ) from None
    issues = [
        InputIssue(src, 0, c, f"missing array {c!r}; expected arrays {list(COLUMNS)}")
        for c in COLUMNS
        if c not in data.files
    ]
    if issues:
        raise ScenarioError(issues)
    fid, x, y = (np.ravel(data[c]) for c in COLUMNS)
    if not (len(fid) == len(x) == len(y)):
        raise ScenarioError(
            [
                InputIssue(
                    src,
                    0,
                    "(root)",
                    f"arrays feature_id, x, y must have "
                    f"equal lengths, got {len(fid)}, {len(x)}, {len(y)}",
                )
            ]
        )
    try:
        xy = np.column_stack([x.astype(float), y.astype(float)])
    except ValueError:
        raise ScenarioError([InputIssue(src, 0, "x", "x and y must be numbers [m]")]) from None
    bad = np.flatnonzero(~np.isfinite(xy).all(axis=1))
    if bad.size:
        raise ScenarioError(
            [InputIssue(src, 0, f"x/y[{int(i)}]", "expected finite numbers") for i in bad[:20]]
        )
    return _group([str(v) for v in fid], xy)


def load_boundaries(path: str | Path) -> tuple[list[str], list[np.ndarray]]:
    """Read boundary samples grouped by feature.

    Args:
        path: a ``.csv`` or ``.npz`` file.

    Returns:
        ``(feature_ids, boundaries)``: ids in order of first appearance and one (M_i, 2)
        array of samples [m] per feature.

    Raises:
        ScenarioError: unreadable file, missing columns, bad values (all at once).
    """
    path = Path(path)
    src = str(path)
    if not path.is_file():
        raise ScenarioError([InputIssue(src, 0, "(root)", "data file not found")])
    suffix = path.suffix.lower()
    if suffix == ".csv":
        return _read_csv(path, src)
    if suffix == ".npz":
        return _read_npz(path, src)
    raise ScenarioError(
        [InputIssue(src, 0, "(root)", f"unknown data file type {suffix!r}; expected .csv or .npz")]
    )


__all__ = ["COLUMNS", "load_boundaries"]
