"""``report.md`` of a sweep: metric against each swept parameter (mean and spread over
seeds and the other parameters), success maps for pairs of parameters, the failures.

Figures go to ``DIR/report/*.png``; the report links them. Metrics plotted are the sweep's
``report.metrics`` (names or fnmatch patterns; a pattern matching several metrics draws one
line per metric, e.g. ``alg*_f1``), by default every numeric metric that varies (at most
:data:`MAX_DEFAULT_METRICS`). ``success`` (the fraction of runs with status ok) is always drawn.
"""

from __future__ import annotations

import fnmatch
import itertools
from pathlib import Path

import numpy as np

MAX_DEFAULT_METRICS = 8
MAX_LEVELS = 12  # a parameter with more distinct values is drawn as a scatter
MAX_HUE = 6
MAX_MAPS = 6
MAX_FAILURES = 100
DPI = 80


def _numeric_metrics(df) -> list[str]:
    out = []
    for col in df.attrs.get("metrics", []):
        s = df[col].dropna()
        if s.empty or s.map(lambda v: isinstance(v, str)).any():
            continue
        if s.astype(float).nunique() > 1:
            out.append(col)
    return out


def selected_metrics(df, patterns: list[str]) -> list[tuple[str, list[str]]]:
    """(title, metric columns) per subplot: ``success`` first, then each pattern's matches."""
    numeric = _numeric_metrics(df)
    if patterns:
        groups = [(p, [c for c in numeric if fnmatch.fnmatchcase(c, p)]) for p in patterns]
        groups = [(p, cols) for p, cols in groups if cols]
    else:
        groups = [(c, [c]) for c in numeric[:MAX_DEFAULT_METRICS]]
    return [("success", ["success"]), *groups]


def _levels(s) -> list:
    vals = list(dict.fromkeys(s.dropna().tolist()))
    try:
        return sorted(vals)
    except TypeError:
        return vals


def _is_number(levels: list) -> bool:
    return all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in levels)


def _curve(ax, df, x: str, col: str, label: str | None) -> None:
    levels = _levels(df[x])
    numeric = _is_number(levels)
    y = df[col].astype(float)
    if numeric and len(levels) > MAX_LEVELS:
        ax.plot(df[x].astype(float), y, ".", alpha=0.6, label=label)
        return
    g = y.groupby(df[x].map(str) if not numeric else df[x]).agg(["mean", "std", "count"])
    keys = levels if numeric else [str(v) for v in levels]
    g = g.reindex(keys)
    pos = np.asarray(levels, float) if numeric else np.arange(len(levels))
    ax.errorbar(pos, g["mean"], yerr=g["std"].fillna(0.0), marker="o", capsize=3, label=label)
    if not numeric:
        ax.set_xticks(pos, [str(v) for v in levels], rotation=30, ha="right")


def _metric_figure(df, x: str, params: list[str], groups, path: Path) -> None:
    import matplotlib.pyplot as plt

    n = len(groups)
    ncol = min(3, n)
    fig, axes = plt.subplots(
        (n + ncol - 1) // ncol,
        ncol,
        figsize=(4.2 * ncol, 3.2 * ((n + ncol - 1) // ncol)),
        squeeze=False,
    )
    others = [p for p in params if p != x and 1 < df[p].nunique() <= MAX_HUE]
    hue = min(others, key=lambda p: df[p].nunique()) if others else None
    for ax, (title, cols) in zip(axes.flat, groups, strict=False):
        if len(cols) > 1 or hue is None:
            for col in cols:
                _curve(ax, df, x, col, col if len(cols) > 1 else None)
        else:
            for level in _levels(df[hue]):
                _curve(ax, df[df[hue] == level], x, cols[0], f"{hue}={level}")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(x)
        ax.tick_params(axis="x", labelsize=7, labelrotation=30)
        levels = _levels(df[x])
        if _is_number(levels) and min(levels) > 0 and max(levels) / min(levels) > 50:
            ax.set_xscale("log")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    fig.suptitle(f"metrics vs {x} (mean ± std over seeds and other parameters)", fontsize=10)
    fig.subplots_adjust(left=0.08, right=0.98, bottom=0.12, top=0.88, wspace=0.3, hspace=0.6)
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


def _success_map(df, p: str, q: str, path: Path) -> None:
    import matplotlib.pyplot as plt

    pl, ql = _levels(df[p]), _levels(df[q])
    grid = np.full((len(ql), len(pl)), np.nan)
    for i, qv in enumerate(ql):
        for j, pv in enumerate(pl):
            cell = df[(df[p] == pv) & (df[q] == qv)]
            if len(cell):
                grid[i, j] = cell["success"].mean()
    fig, ax = plt.subplots(figsize=(1.0 + 0.8 * len(pl), 1.0 + 0.6 * len(ql)))
    im = ax.imshow(grid, origin="lower", cmap="RdYlGn", vmin=0, vmax=1, aspect="auto")
    for (i, j), v in np.ndenumerate(grid):
        if v == v:
            ax.text(j, i, f"{v:.2f}", ha="center", va="center", fontsize=8)
    ax.set_xticks(
        range(len(pl)), [f"{v:g}" if _is_number([v]) else str(v) for v in pl], rotation=30
    )
    ax.set_yticks(range(len(ql)), [f"{v:g}" if _is_number([v]) else str(v) for v in ql])
    ax.set_xlabel(p)
    ax.set_ylabel(q)
    ax.set_title("fraction of runs ok", fontsize=9)
    fig.colorbar(im, ax=ax)
    fig.savefig(path, dpi=DPI, bbox_inches="tight")
    plt.close(fig)


def _slug(text: str) -> str:
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in text)


def _failures(df, params: list[str]) -> list[str]:
    bad = df[df["status"] != "ok"]
    if bad.empty:
        return ["No run failed."]
    lines = ["| run | " + " | ".join([*params, "seed"]) + " | reason |"]
    lines.append("|" + "---|" * (len(params) + 3))
    for _, row in bad.head(MAX_FAILURES).iterrows():
        reason = str(row["reason"]).replace("|", "\\|").replace("\n", " ")[:160]
        cells = [str(row[p]) for p in [*params, "seed"]]
        lines.append(f"| `{row['run_id']}` | " + " | ".join(cells) + f" | {reason} |")
    if len(bad) > MAX_FAILURES:
        lines.append(f"\n... and {len(bad) - MAX_FAILURES} more (see results.csv)")
    return lines


def axes(sweep, params: list[str]) -> list[str]:
    """The independent parameters: every grid and random key, and the first key of each zip
    group (the others of a group are functions of it)."""
    m = sweep.model
    tied = {k for group in (m.zip or []) for k in list(group)[1:]}
    return [p for p in params if p not in tied]


def write_report(df, out: str | Path, sweep) -> Path:
    """Write ``out/report.md`` and its figures for the table ``df`` of ``sweep``."""
    import hashlib

    out = Path(out)
    path = out / "report.md"
    stamp = f"<!-- table {hashlib.sha256(df.to_csv(index=False).encode()).hexdigest()} -->"
    if path.is_file() and path.read_text().rstrip().endswith(stamp):
        return path  # same table as when the report was written: nothing to redraw
    figdir = out / "report"
    figdir.mkdir(parents=True, exist_ok=True)
    params = list(df.attrs.get("params", []))
    n_ok = int((df["status"] == "ok").sum())
    md = [f"# Sweep {sweep.name}", ""]
    if sweep.model.description:
        md += [sweep.model.description, ""]
    md += [
        f"- source: `{sweep.source}`{' (--quick variant)' if sweep.quick else ''}",
        f"- runs complete: {len(df)} ({n_ok} ok, {len(df) - n_ok} failed)",
        f"- swept parameters: {', '.join(f'`{p}`' for p in params) or 'none'}; seeds: "
        f"{df['seed'].nunique() if len(df) else 0}",
        f"- total run time on workers: {df['wall_s'].astype(float).sum():.1f} s",
        "- table: `results.parquet`, `results.csv` (one row per run)",
        "",
    ]
    if len(df):
        import matplotlib

        matplotlib.use("Agg")
        df = df.assign(success=(df["status"] == "ok").astype(float))
        groups = selected_metrics(df, sweep.model.report.metrics)
        varied = [p for p in axes(sweep, params) if df[p].nunique() > 1]
        if varied:
            md += ["## Metrics against each parameter", ""]
        for p in varied:
            name = f"metrics_vs_{_slug(p)}.png"
            _metric_figure(df, p, varied, groups, figdir / name)
            md += [f"![metrics vs {p}](report/{name})", ""]
        pairs = [
            (p, q)
            for p, q in itertools.combinations(varied, 2)
            if df[p].nunique() <= 25 and df[q].nunique() <= 25
        ][:MAX_MAPS]
        if pairs:
            md += ["## Success maps", ""]
        for p, q in pairs:
            name = f"success_{_slug(p)}__{_slug(q)}.png"
            _success_map(df, p, q, figdir / name)
            md += [f"![success {p} x {q}](report/{name})", ""]
    md += ["## Failures", "", *_failures(df, params), "", stamp, ""]
    path.write_text("\n".join(md))
    return path


__all__ = ["selected_metrics", "write_report"]
