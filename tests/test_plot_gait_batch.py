"""benchmarks/plot_gait_batch.py: the §2.3.1 batch figure from bench_gait's CSV (its
reading of the committed report, its families, its command line and its bad input)."""

from __future__ import annotations

import csv
import os
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import benchmark_module

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
REPORT = BENCH / "results" / "bench_gait.csv"


@pytest.fixture(scope="module")
def plot_mod():
    return benchmark_module("plot_gait_batch")


def _cli(*args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "MPLBACKEND": "Agg"}
    return subprocess.run(
        [sys.executable, str(BENCH / "plot_gait_batch.py"), *args],
        capture_output=True, text=True, timeout=120, env=env,
    )  # fmt: skip


def test_the_committed_report_reads_as_one_entry_per_object(plot_mod):
    objects = plot_mod.read_batch(REPORT)
    with open(REPORT, newline="") as fh:
        rows = [r for r in csv.DictReader(fh) if r["benchmark"] == "batch"]
    assert {o["name"] for o in objects} == {r["object"] for r in rows}
    assert sum(len(o["runs"]) for o in objects) == len(rows)
    full = sum(full for o in objects for _, _, full in o["runs"])
    assert full == sum(r["run_end"] == "full turn" for r in rows)
    # the figure's order: families as listed, sizes growing within each
    order = [f for f, _ in plot_mod.FAMILIES]
    ranks = [order.index(o["family"]) for o in objects]
    assert ranks == sorted(ranks)
    circles = [o["size"] for o in objects if o["family"] == "circle"]
    assert circles == sorted(circles)


def test_every_batch_object_has_its_family(plot_mod):
    """The figure's families are bench_gait's, read back from the object names."""
    bench = benchmark_module("bench_gait")
    expect = {"circle": "circle", "polygon": "polygon", "square sharp": "sharp square",
              "square rounded": "rounded square"}  # fmt: skip
    for obj in bench.objects(quick=False):
        want = "ellipse" if obj.family.startswith("ellipse") else expect[obj.family]
        assert plot_mod.family(obj.name) == want, obj.name


def test_the_command_draws_a_png(tmp_path):
    out = tmp_path / "batch.png"
    proc = _cli(str(REPORT), "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == str(out)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out.stat().st_size > 20_000
    assert list(tmp_path.iterdir()) == [out]  # no part file left


def test_the_report_stamp_titles_the_figure(plot_mod):
    note = plot_mod.stamp(REPORT)
    commit, date = note.split(", ")
    assert len(commit) >= 12 and date.startswith("20")


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("benchmark,object\nnlp build,\n", "missing columns"),
        (
            "benchmark,object,model,size_cm,run_turn_deg,run_end\nnlp build,,,,,\n",
            "no batch rows",
        ),  # fmt: skip
        ("", "no rows"),
    ],
)
def test_a_csv_without_a_batch_is_one_usage_line(tmp_path, content, message):
    bad = tmp_path / "bad.csv"
    bad.write_text(content)
    proc = _cli(str(bad))
    assert proc.returncode == 2
    assert message in proc.stderr and "Traceback" not in proc.stderr
    assert proc.stderr.strip().splitlines()[-1].startswith("plot_gait_batch.py: error:")
    assert not bad.with_suffix(".png").exists()


def test_a_missing_csv_is_a_usage_error(tmp_path):
    proc = _cli(str(tmp_path / "none.csv"))
    assert proc.returncode == 2 and "no such file" in proc.stderr


def test_turns_off_the_axis_and_short_runs_are_drawn(plot_mod, tmp_path):
    """A turn beyond the axis (an arrow with its value) and a run without ``--full-turn``
    (no ``run_turn_deg``: its ``rotation_deg`` at the end of the batch run) still plot."""
    cols = ["benchmark", "object", "model", "size_cm", "rotation_deg", "run_turn_deg",
            "run_end", "rest_turn_deg", "rest_turn_reserve_deg"]  # fmt: skip
    rows = [
        ["batch", "square 8cm sharp", "circle", "4", "-20", "-588", "failed: x", "35", "35"],
        ["batch", "circle r=5cm", "true", "5", "104", "", "", "360", "360"],
    ]
    path = tmp_path / "b.csv"
    path.write_text("\n".join(",".join(r) for r in [cols, *rows]) + "\n")
    objects = plot_mod.read_batch(path)
    assert [o["name"] for o in objects] == ["circle r=5cm", "square 8cm sharp"]
    assert objects[0]["runs"] == [("true", 104.0, False)]
    assert objects[1]["runs"] == [("circle", -588.0, False)]
    out = plot_mod.plot(objects, tmp_path / "b.png")
    assert out.stat().st_size > 10_000


def test_a_folder_a_binary_file_or_an_unwritable_out_is_one_usage_line(tmp_path):
    """A folder or a binary file given as the CSV, or an ``--out`` under a plain file:
    exit 2, one line, no traceback."""
    binary = tmp_path / "b.csv"
    binary.write_bytes(b"\xff\xfe\x00\x81" * 64)
    blocker = tmp_path / "file"
    blocker.write_text("")
    cases = [
        ((str(tmp_path),), "no such file"),
        ((str(binary),), "not a CSV report"),
        ((str(REPORT), "--out", str(blocker / "x.png")), "--out:"),
    ]
    for args, message in cases:
        proc = _cli(*args)
        assert proc.returncode == 2, args
        assert message in proc.stderr and "Traceback" not in proc.stderr, proc.stderr
