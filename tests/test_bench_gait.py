"""benchmarks/bench_gait.py: its counting (an object's verdict over sensor-noise seeds), its
argument checks (usage errors exit 2 before any work) and its task list."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


@pytest.fixture(scope="module")
def bench():
    sys.path.insert(0, str(BENCH))
    try:
        import bench_gait
    finally:
        sys.path.remove(str(BENCH))
    return bench_gait


def _row(obj: str, family: str, model: str, seed: int, verdict: str, **kw) -> dict:
    return {"benchmark": "batch", "object": obj, "family": family, "model": model,
            "seed": seed, "verdict": verdict, **kw}  # fmt: skip


def test_an_object_succeeds_when_most_of_its_seeds_do(bench):
    """Objects are counted by majority over their seeds, runs one by one, per model and
    family; map space (plan_gait) once per object."""
    rows = []
    # a: 2 of 3 seeds turn (succeeds), b: 1 of 3 (does not), c: all fail
    for seed, v in enumerate(["full turn", "turning", "failed"]):
        rows.append(_row("a", "circles", "circle", seed, v, plan_gait="gait"))
    for seed, v in enumerate(["failed", "stalled", "turning"]):
        rows.append(_row("b", "circles", "circle", seed, v, plan_gait="gait"))
    for seed in range(3):
        rows.append(_row("c", "squares", "circle", seed, "failed", plan_gait="no gait"))
        rows.append(_row("c", "squares", "true", seed, "turning" if seed else "failed"))
    lines = bench.summary(rows)
    assert lines[0].startswith("runs: 12 (3 sensor-noise seed(s) per object and model)")
    assert "nominal circle model succeeds on objects 1/3, runs 3/9" in lines[2]
    assert "true (posed) outline model succeeds on objects 1/1, runs 2/3" in lines[3]
    circles = next(x for x in lines if x.startswith("circles:"))
    assert "objects 1/2, runs 3/6 (circle)" in circles
    assert "plan_gait on 2/2" in circles  # once per object, not once per run
    squares = next(x for x in lines if x.startswith("squares:"))
    assert "objects 0/1, runs 0/3 (circle); objects 1/1, runs 2/3 (true)" in squares


def test_a_tie_is_not_a_success(bench):
    rows = [_row("a", "ellipses", "circle", 0, "turning"),
            _row("a", "ellipses", "circle", 1, "failed")]  # fmt: skip
    assert "succeeds on objects 0/1, runs 1/2" in bench.summary(rows)[2]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--nominal", "sphere"], "--nominal: 'sphere': expected a comma-separated list"),
        (["--seeds", "0"], "--seeds: 0: expected at least 1"),
    ],
)
def test_bad_arguments_are_usage_errors(args, message):
    """Exit 2 with one line naming the argument, before any object runs (and no report)."""
    out = subprocess.run(
        [sys.executable, str(BENCH / "bench_gait.py"), "--no-nlp", *args],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert out.returncode == 2
    assert message in out.stderr
    assert "Traceback" not in out.stderr
    assert out.stdout == ""
