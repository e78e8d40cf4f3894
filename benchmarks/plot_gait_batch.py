"""Figure of the §2.3.1 batch (``bench_gait.py``'s CSV): per object, how far the executor
turned it beside how far map space can turn it from rest.

One row per object, grouped by family. Bars: map space from the object resting unturned
(``rest_turn_deg``: plan_gait's tables at the full friction, force closure alone; darker,
``rest_turn_reserve_deg``: with the friction reserve and stability threshold the executor
plans with). Markers: each run's turn when it ended (``run_turn_deg``: given
``--full-turn`` simulated seconds, 120 by default; clockwise positive [deg]), filled for
the circle model, hollow for the posed true outline, green where the run made a full
turn. Where the markers sit at the darker bar's end, the executor stops where map space at
its margins does.

Usage::

    python benchmarks/plot_gait_batch.py [CSV] [--out PNG]

Default: ``benchmarks/results/bench_gait.csv`` to ``bench_gait.png`` beside it; the title
carries the commit and date of the report (``.md``) beside the CSV. ``bench_gait.py``
draws it after every batch.
"""

from __future__ import annotations

import argparse
import csv
import math
import re
import sys
from pathlib import Path

RESULTS = Path(__file__).resolve().parent / "results"
#: x range of the figure [deg] (a turn beyond it is an arrow at its edge, with its value)
X_RANGE = (-80.0, 400.0)
FULL_TURN = 360.0
#: (family, colour) in the figure's order (top to bottom)
FAMILIES = (
    ("circle", "#4c72b0"),
    ("ellipse", "#8172b2"),
    ("rounded square", "#dd8452"),
    ("sharp square", "#c44e52"),
    ("polygon", "#937860"),
)


class BatchCsvError(ValueError):
    """A CSV that holds no batch rows, or lacks a column the figure needs."""


def family(name: str) -> str:
    """The batch family of an object name (``bench_gait.objects``' names)."""
    if name.startswith("circle"):
        return "circle"
    if name.startswith("ellipse"):
        return "ellipse"
    if name.startswith("square"):
        return "sharp square" if name.endswith("sharp") else "rounded square"
    if re.match(r"\d+-gon", name):
        return "polygon"
    return "other"


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        return math.nan


def read_batch(path: Path) -> list[dict]:
    """One dict per object (in the figure's order): name, family, size, the map-space
    turns and the runs (model, turn, full turn?)."""
    need = {"benchmark", "object", "model", "size_cm", "run_turn_deg", "run_end"}
    try:
        with open(path, newline="") as fh:
            rows = list(csv.DictReader(fh))
    except (UnicodeDecodeError, csv.Error) as exc:
        raise BatchCsvError(f"{path}: not a CSV report: {exc}") from None
    if not rows:
        raise BatchCsvError(f"{path}: no rows")
    missing = need - set(rows[0])
    if missing:
        raise BatchCsvError(f"{path}: missing columns {sorted(missing)}")
    objects: dict[str, dict] = {}
    for r in rows:
        if r["benchmark"] != "batch":
            continue
        o = objects.setdefault(
            r["object"],
            {
                "name": r["object"],
                "family": family(r["object"]),
                "size": _number(r["size_cm"]),
                "rest": _number(r.get("rest_turn_deg", "")),
                "reserve": _number(r.get("rest_turn_reserve_deg", "")),
                "runs": [],
            },
        )
        turn = _number(r["run_turn_deg"])
        if math.isnan(turn):
            turn = _number(r.get("rotation_deg", ""))
        o["runs"].append((r["model"], turn, r["run_end"] == "full turn"))
    if not objects:
        raise BatchCsvError(f"{path}: no batch rows (run benchmarks/bench_gait.py)")
    order = {f: i for i, (f, _) in enumerate(FAMILIES)}
    return sorted(
        objects.values(), key=lambda o: (order.get(o["family"], 99), _aspect(o["name"]), o["size"])
    )


def _aspect(name: str) -> float:
    """An ellipse's aspect ratio from its name (``"ellipse 1.5:1 a=5cm"``), else 0."""
    m = re.search(r"(\d+(?:\.\d+)?):1", name)
    return float(m.group(1)) if m else 0.0


def stamp(csv_path: Path) -> str:
    """``commit, date`` of the report beside the CSV ("" without one)."""
    md = csv_path.with_suffix(".md")
    if not md.exists():
        return ""
    text = md.read_text()
    commit = re.search(r"\| hapex_commit \| (\S+) \|", text)
    date = re.search(r"\| date \| (\S+) \|", text)
    parts = [m.group(1)[:19] for m in (commit, date) if m]
    return ", ".join(parts)


def plot(objects: list[dict], out: Path, title_note: str = "") -> Path:
    """Draw the figure to ``out`` (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    colours = dict(FAMILIES)
    n = len(objects)
    fig, ax = plt.subplots(figsize=(9.0, 0.28 * n + 2.4))
    lo, hi = X_RANGE
    for i, o in enumerate(objects):
        y = n - 1 - i
        c = colours.get(o["family"], "grey")
        if not math.isnan(o["rest"]):
            ax.barh(y, o["rest"], height=0.7, color=c, alpha=0.18, lw=0)
        if not math.isnan(o["reserve"]):
            ax.barh(y, o["reserve"], height=0.7, color=c, alpha=0.45, lw=0)
        for model, turn, full in o["runs"]:
            if math.isnan(turn):
                continue
            x = min(max(turn, lo + 4), hi - 4)
            dy = 0.12 if model == "circle" else -0.12
            edge = "#2ca02c" if full else "black"
            face = edge if model == "circle" else "white"
            marker = "o" if model == "circle" else "D"
            if x != turn:  # beyond the axis: an arrow at its edge, the turn written beside
                marker = "<" if turn < lo else ">"
                ax.annotate(f"{turn:.0f}", (x, y + dy), xytext=(4 if turn < lo else -4, 0),
                            textcoords="offset points", fontsize=6, va="center",
                            ha="left" if turn < lo else "right")  # fmt: skip
            ax.plot(x, y + dy, marker, ms=4.5, mfc=face, mec=edge, mew=1.0, alpha=0.85,
                    zorder=3)  # fmt: skip
    ax.axvline(FULL_TURN, color="black", ls="--", lw=0.8)
    ax.axvline(0.0, color="black", lw=0.6)
    ax.set_yticks(range(n))
    ax.set_yticklabels([o["name"] for o in reversed(objects)], fontsize=7.5)
    for label, o in zip(ax.get_yticklabels(), reversed(objects), strict=True):
        label.set_color(colours.get(o["family"], "grey"))
    ax.set_xlim(lo, hi)
    ax.set_ylim(-0.7, n - 0.3)
    ax.set_xlabel("object turn [deg] (clockwise positive; full turn at 360)")
    legend = [
        Line2D([], [], color="grey", alpha=0.3, lw=6, label="map space from rest, full mu"),
        Line2D(
            [],
            [],
            color="grey",
            alpha=0.7,
            lw=6,
            label="map space, executor's friction reserve + threshold",
        ),  # fmt: skip
        Line2D([], [], ls="", marker="o", mfc="black", mec="black", label="run, circle model"),
        Line2D([], [], ls="", marker="D", mfc="white", mec="black", label="run, true outline"),
        Line2D([], [], ls="", marker="o", mfc="#2ca02c", mec="#2ca02c", label="full turn"),
    ]
    ax.legend(handles=legend, loc="upper center", bbox_to_anchor=(0.5, -0.045 * 40 / (n + 8)),
              ncol=3, fontsize=7, frameon=False)  # fmt: skip
    title = "§2.3.1 batch: the executor's turn per run vs map space from rest"
    ax.set_title(title + (f"\n{title_note}" if title_note else ""), fontsize=9)
    ax.grid(axis="x", alpha=0.3)
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_name(out.name + ".part.png")
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    tmp.replace(out)  # nothing half-written
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("csv", nargs="?", type=Path, default=RESULTS / "bench_gait.csv")
    p.add_argument("--out", type=Path, default=None, help="PNG (default: beside the CSV)")
    args = p.parse_args(argv)
    if not args.csv.is_file():
        p.error(f"{args.csv}: no such file")
    try:
        objects = read_batch(args.csv)
    except BatchCsvError as exc:
        p.error(str(exc))
    try:
        out = plot(objects, args.out or args.csv.with_suffix(".png"), stamp(args.csv))
    except OSError as exc:  # an --out that cannot be written
        p.error(f"--out: {exc}")
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
