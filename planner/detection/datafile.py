"""Users' own fingertip logs: CSV and NPZ trace files.

CSV: one header line of column names (lines starting with ``#`` before it are comments),
then one row per sample, comma-separated. Columns (any order):

=============  ========  ===============================================================
column         unit      meaning
=============  ========  ===============================================================
``t``          s         time stamp, strictly increasing (required)
``cx cy [cz]`` m         fingertip-centre position (required; ``cz`` for 3-D data)
``px py [pz]`` m         tactile contact point (optional, all or none)
``nx ny [nz]`` 1         outward unit contact normal (optional, all or none)
=============  ========  ===============================================================

A unit suffix is allowed: ``t_s``/``t_ms`` and ``cx_m``/``cx_mm`` (likewise for ``p*``);
values are converted to SI. NPZ: arrays ``t`` (N,), ``centers`` (N, D) and optionally
``contacts`` (N, D), ``normals`` (N, D) and ``tip_radius`` (scalar) — all in SI units.

Every problem found is reported at once, one line each, as a
:class:`planner.errors.ScenarioError` (the CLI exits with code 2).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from planner.errors import InputIssue, ScenarioError
from planner.geometry.measurement import FingertipTrace

MIN_SAMPLES = 20
#: largest plausible extent of a fingertip path in metres (a larger one is likely in mm)
MAX_EXTENT_M = 2.0
_SCALE = {"s": 1.0, "ms": 1e-3, "m": 1.0, "mm": 1e-3}
_UNITS = {"t": ("s", "ms"), "c": ("m", "mm"), "p": ("m", "mm"), "n": ()}
_GROUPS = {"c": "fingertip centre", "p": "contact point", "n": "contact normal"}


def read_trace_file(path: str | Path) -> FingertipTrace:
    """Read a CSV or NPZ fingertip trace (format in the module docstring).

    Returns:
        A :class:`~planner.geometry.measurement.FingertipTrace` in SI units (``truth`` is
        ``None``; ``tip_radius`` is the file's (NPZ) or ``None``; ``source`` the path).

    Raises:
        ScenarioError: every problem found (missing file, unknown extension, missing or
            unknown columns, non-numeric cells, NaNs, non-monotonic time, too few samples,
            implausible units, bad shapes, non-unit normals), one issue each.
    """
    p = Path(path)
    src = str(path)
    if not p.exists():
        raise ScenarioError([InputIssue(src, 0, "(root)", "file not found")])
    if p.is_dir():
        raise ScenarioError([InputIssue(src, 0, "(root)", "is a directory, not a file")])
    ext = p.suffix.lower()
    if ext == ".csv":
        return _read_csv(p, src)
    if ext == ".npz":
        return _read_npz(p, src)
    raise ScenarioError(
        [InputIssue(src, 0, "(root)", f"unknown file type {ext!r}; expected .csv or .npz")]
    )


def _parse_header(
    names: list[str], src: str, line: int, issues: list[InputIssue]
) -> dict[str, tuple[int, float]]:
    """Column key ('t', 'cx', ...) -> (column index, scale to SI)."""
    cols: dict[str, tuple[int, float]] = {}
    valid = ["t", "cx", "cy", "cz", "px", "py", "pz", "nx", "ny", "nz"]
    for j, raw in enumerate(names):
        name = raw.strip().lower()
        base, _, unit = name.partition("_")
        if base not in valid:
            issues.append(
                InputIssue(
                    src,
                    line,
                    raw.strip() or f"column {j + 1}",
                    f"unknown column; expected {valid} (optionally with a "
                    f"unit suffix such as t_ms or cx_mm)",
                )
            )
            continue
        allowed = _UNITS[base[0]]
        if unit and unit not in allowed:
            issues.append(
                InputIssue(
                    src,
                    line,
                    raw.strip(),
                    f"unknown unit {unit!r}; expected one of "
                    f"{list(allowed) or ['(none: normals are unitless)']}",
                )
            )
            continue
        if base in cols:
            issues.append(InputIssue(src, line, raw.strip(), "duplicate column"))
            continue
        cols[base] = (j, _SCALE[unit] if unit else 1.0)
    return cols


def _check_groups(present: set[str], src: str, line: int, issues: list[InputIssue]) -> int:
    for req in ("t", "cx", "cy"):
        if req not in present:
            issues.append(
                InputIssue(src, line, req, "required column is missing (t, cx, cy are required)")
            )
    dim = 3 if "cz" in present else 2
    for g in ("p", "n"):
        have = {a for a in ("x", "y", "z") if g + a in present}
        want = {"x", "y", "z"} if dim == 3 else {"x", "y"}
        if have and have != want:
            missing = sorted(g + a for a in want - have)
            extra = sorted(g + a for a in have - want)
            msg = (
                f"{_GROUPS[g]} columns must be all of {sorted(g + a for a in want)} "
                f"for {dim}-D data"
            )
            if missing:
                msg += f"; missing {missing}"
            if extra:
                msg += f"; unexpected {extra}"
            issues.append(InputIssue(src, line, g + "*", msg))
    return dim


def _read_csv(p: Path, src: str) -> FingertipTrace:
    try:
        text = p.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise ScenarioError([InputIssue(src, 0, "(root)", f"cannot read: {exc}")]) from None
    lines = text.splitlines()
    k = 0
    while k < len(lines) and (not lines[k].strip() or lines[k].lstrip().startswith("#")):
        k += 1
    if k == len(lines):
        raise ScenarioError(
            [
                InputIssue(
                    src,
                    max(k, 1),
                    "(root)",
                    "no header line; expected column names such as t,cx,cy",
                )
            ]
        )
    header_line = k + 1
    issues: list[InputIssue] = []
    reader = list(csv.reader(lines[k:]))
    cols = _parse_header(reader[0], src, header_line, issues)
    dim = _check_groups(set(cols), src, header_line, issues)
    if issues:
        raise ScenarioError(issues)
    rows = []
    row_lines = []
    ncol = len(reader[0])
    for i, row in enumerate(reader[1:], start=header_line + 1):
        if not row or all(not c.strip() for c in row) or row[0].lstrip().startswith("#"):
            continue
        if len(row) != ncol:
            issues.append(InputIssue(src, i, "(row)", f"expected {ncol} values, got {len(row)}"))
            continue
        vals = []
        for name, (j, _) in cols.items():
            try:
                vals.append(float(row[j]))
            except ValueError:
                issues.append(InputIssue(src, i, name, f"not a number: {row[j].strip()!r}"))
                vals.append(np.nan)
        rows.append(vals)
        row_lines.append(i)
        if len(issues) > 20:
            break
    if issues:
        raise ScenarioError(issues[:20])
    data = np.array(rows, dtype=float).reshape(-1, len(cols))
    keys = list(cols)
    arr = {kk: data[:, m] * cols[kk][1] for m, kk in enumerate(keys)}
    lines_arr = np.array(row_lines, dtype=int)

    def stack(g: str) -> np.ndarray | None:
        names = [g + a for a in ("x", "y", "z")[:dim]]
        if names[0] not in arr:
            return None
        return np.column_stack([arr[n] for n in names])

    def header(g: str) -> list[str]:
        return [raw[g + a] for a in ("x", "y", "z")[:dim] if g + a in raw]

    raw = {b: reader[0][j].strip() for b, (j, _) in cols.items()}

    return _finish(
        src,
        arr["t"],
        stack("c"),
        stack("p"),
        stack("n"),
        None,
        lambda r: int(lines_arr[r]) if r < lines_arr.size else 0,
        {"t": raw["t"], "centers": header("c"), "contacts": header("p"), "normals": header("n")},
    )


def _read_npz(p: Path, src: str) -> FingertipTrace:
    try:
        with np.load(p, allow_pickle=False) as z:
            files = {k: np.asarray(z[k]) for k in z.files}
    except (OSError, ValueError, EOFError) as exc:
        raise ScenarioError(
            [InputIssue(src, 0, "(root)", f"not a readable .npz file: {exc}")]
        ) from None
    issues: list[InputIssue] = []
    valid = ("t", "centers", "contacts", "normals", "tip_radius")
    for k in files:
        if k not in valid:
            issues.append(InputIssue(src, 0, k, f"unknown array; expected {list(valid)}"))
    for req in ("t", "centers"):
        if req not in files:
            issues.append(InputIssue(src, 0, req, "required array is missing"))
    if issues:
        raise ScenarioError(issues)
    t = files["t"]
    if t.ndim != 1:
        issues.append(InputIssue(src, 0, "t", f"expected shape (N,), got {t.shape}"))
    c = files["centers"]
    if c.ndim != 2 or c.shape[1] not in (2, 3):
        issues.append(
            InputIssue(src, 0, "centers", f"expected shape (N, 2) or (N, 3), got {c.shape}")
        )
    elif t.ndim == 1 and c.shape[0] != t.shape[0]:
        issues.append(
            InputIssue(
                src,
                0,
                "centers",
                f"expected {t.shape[0]} rows (one per time stamp), got {c.shape[0]}",
            )
        )
    opt = {}
    for k in ("contacts", "normals"):
        if k in files:
            a = files[k]
            if c.ndim == 2 and a.shape != c.shape:
                issues.append(
                    InputIssue(src, 0, k, f"expected shape {c.shape} like centers, got {a.shape}")
                )
            opt[k] = a
    tip = None
    if "tip_radius" in files:
        tr = files["tip_radius"]
        if tr.size != 1 or not np.isfinite(tr.astype(float)).all() or float(tr) <= 0:
            issues.append(
                InputIssue(src, 0, "tip_radius", f"expected a positive scalar [m], got {tr!r}")
            )
        else:
            tip = float(tr)
    if issues:
        raise ScenarioError(issues)
    try:
        t, c = t.astype(float), c.astype(float)
        opt = {k: v.astype(float) for k, v in opt.items()}
    except (TypeError, ValueError) as exc:
        raise ScenarioError(
            [InputIssue(src, 0, "(root)", f"arrays must be numeric: {exc}")]
        ) from None
    return _finish(
        src,
        t,
        c,
        opt.get("contacts"),
        opt.get("normals"),
        tip,
        lambda r: 0,
        {"t": "t", "centers": "centers", "contacts": "contacts", "normals": "normals"},
    )


def _finish(src, t, c, p, n, tip, line_of, names) -> FingertipTrace:
    """Content checks shared by CSV and NPZ."""
    label = {k: ",".join(v) if isinstance(v, list) else v for k, v in names.items()}
    issues: list[InputIssue] = []
    if t.size < MIN_SAMPLES:
        issues.append(
            InputIssue(
                src, 0, label["t"], f"too few samples: {t.size}; expected at least {MIN_SAMPLES}"
            )
        )
    for key, a in (("t", t), ("centers", c), ("contacts", p), ("normals", n)):
        if a is None:
            continue
        bad = ~np.isfinite(a.reshape(a.shape[0], -1)).all(axis=1)
        if bad.any():
            r = int(np.argmax(bad))
            where = names[key]
            if a.ndim == 2:  # the column (CSV) or the array and column (NPZ) of the value
                col = int(np.argmax(~np.isfinite(a[r])))
                where = where[col] if isinstance(where, list) else f"{where}[:, {col}]"
            issues.append(
                InputIssue(
                    src,
                    line_of(r),
                    where,
                    f"NaN or infinite value in {int(bad.sum())} row(s), "
                    f"first at row {r}; remove or interpolate them",
                )
            )
    if np.isfinite(t).all() and t.size > 1:
        dt = np.diff(t)
        if np.any(dt <= 0):
            r = int(np.argmax(dt <= 0)) + 1
            issues.append(
                InputIssue(
                    src,
                    line_of(r),
                    label["t"],
                    f"time is not strictly increasing at row {r} "
                    f"(t={float(t[r]):.9g} after {float(t[r - 1]):.9g}); sort the samples "
                    f"and remove duplicates",
                )
            )
    for key, a in (("centers", c), ("contacts", p)):
        if a is None or not np.isfinite(a).all():
            continue
        ext = float(np.max(np.ptp(a, axis=0)))
        if ext > MAX_EXTENT_M:
            issues.append(
                InputIssue(
                    src,
                    0,
                    label[key],
                    f"the path spans {ext:.4g} m, implausible for a "
                    f"fingertip; are the values in millimetres? Use "
                    f"metres, or a _mm column suffix in CSV",
                )
            )
        elif key == "centers" and ext == 0:
            issues.append(InputIssue(src, 0, label[key], "the fingertip does not move"))
    if n is not None and np.isfinite(n).all():
        lens = np.linalg.norm(n, axis=1)
        bad = np.abs(lens - 1) > 0.05
        if bad.any():
            r = int(np.argmax(bad))
            issues.append(
                InputIssue(
                    src,
                    line_of(r),
                    label["normals"],
                    f"normals must be unit vectors; row {r} has length "
                    f"{lens[r]:.4g} ({int(bad.sum())} such rows)",
                )
            )
    if issues:
        raise ScenarioError(issues)
    return FingertipTrace(t=t, centers=c, tip_radius=tip, contacts=p, normals=n, source=src)


__all__ = ["MAX_EXTENT_M", "MIN_SAMPLES", "read_trace_file"]
