"""benchmarks/bench_gait.py: its counting (an object's verdict over sensor-noise seeds), its
argument checks (usage errors exit 2 before any work) and its task list."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from conftest import benchmark_module

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


@pytest.fixture(scope="module")
def bench():
    return benchmark_module("bench_gait")


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


def test_verdicts_of_a_run(bench):
    """Full turn from 359 deg; below --min-rotation a run is "turning" only when two of its
    phase-1 rotations turned >= 5 deg each and it kept >= CYCLE_NET_DEG of them (a
    hexagon's phases 2/3 gave back all but 0.8-2.8 deg of such cycles)."""
    v = bench.run_verdict
    assert v("failed", 400.0, [30.0, 30.0], 40.0) == "failed"
    assert v("ok", 359.5, [], 40.0) == "full turn"
    assert v("ok", 41.0, [41.0], 40.0) == "turning"
    assert v("ok", 12.0, [6.0, 7.0], 40.0) == "turning"
    assert v("ok", 2.8, [6.0, 7.0], 40.0) == "stalled"
    assert v("ok", 39.0, [39.0], 40.0) == "stalled"
    assert v("ok", 12.0, [6.0, 4.9], 40.0) == "stalled"
    assert bench.CYCLE_NET_DEG == 10.0


def test_the_runs_settings_keep_the_gait_defaults_but_for_what_is_given(bench):
    from planner.exploration.planar import GaitSettings

    assert bench.gait_settings(1.0) == GaitSettings(mu=1.0)
    assert bench.gait_settings(0.8, 0.0) == GaitSettings(mu=0.8, gravity=0.0)


def test_a_tie_is_not_a_success(bench):
    rows = [_row("a", "ellipses", "circle", 0, "turning"),
            _row("a", "ellipses", "circle", 1, "failed")]  # fmt: skip
    assert "succeeds on objects 0/1, runs 1/2" in bench.summary(rows)[2]


def test_full_turns_given_more_time_are_counted_too(bench):
    """With ``--full-turn`` the notes count, per model and family, the runs that turned
    the object 360 deg in the longer run (majority over seeds, as the verdicts)."""
    rows = [
        _row("a", "squares", "circle", 0, "turning", full_turn_s=41.2, run_end="full turn"),
        _row("a", "squares", "circle", 1, "turning", full_turn_s="", run_end="failed: x"),
        _row("a", "squares", "circle", 2, "full turn", full_turn_s=9.5, run_end="full turn"),
        _row("b", "squares", "circle", 0, "failed", full_turn_s="", run_end="failed: y"),
    ]
    lines = bench.summary(rows)
    assert (
        "full turn (360 deg) given more time, nominal circle model: objects 1/2, runs 2/4" in lines
    )
    squares = next(x for x in lines if x.startswith("squares:"))
    assert "full turn given more time on objects 1/2, runs 2/4 (circle)" in squares
    plain = bench.summary([_row("c", "circles", "circle", 0, "turning")])
    assert not any("given more time" in x for x in plain)


def test_a_longer_run_gives_the_verdict_of_the_short_one(bench):
    """The batch's verdict columns of a run continued past ``--duration`` are those of a
    run of ``--duration`` (the gait is deterministic for a seed): same rotation at the
    duration, same status, and the longer run's own end in ``run_end``."""
    from planner.geometry import shapes

    obj = bench.BatchObject("circle r=4cm", "circle", 4, shapes.circle(0.04))
    short = bench.run_object(obj, 1.5, 40.0, 1.0, map_space=False)
    longer = bench.run_object(obj, 1.5, 40.0, 1.0, map_space=False, full_turn=3.0)
    for key in ("verdict", "status", "reason", "rotation_deg"):
        assert longer[key] == short[key], key
    assert short["reason"] == "duration 1.5 s reached" and "run_end" not in short
    assert longer["sim_s"] == pytest.approx(3.0, abs=0.01)
    assert longer["run_turn_deg"] > longer["rotation_deg"] > 0
    assert longer["run_end"] == "ok: duration 3 s reached" and longer["full_turn_s"] == ""


def test_map_space_with_the_planning_friction_explains_a_disagreement(bench):
    """plan_gait has the full friction, the executor plans with a reserve and a stability
    threshold: a run that fails where plan_gait finds a gait names how far map space with
    those turns the object from rest, and the family line counts those turns."""
    base = {"verdict": "failed", "plan_gait": "gait", "reason": "no stable grasp",
            "rest_turn_deg": 360}  # fmt: skip
    short = bench.explain({**base, "rest_turn_reserve_deg": 90})
    assert short.startswith("disagree: plan_gait finds a gait with the full friction;")
    assert "planning friction and threshold map space turns it 90 deg from rest" in short
    assert short.endswith("the executor: no stable grasp")
    full = bench.explain({**base, "rest_turn_reserve_deg": 360})
    assert full == "disagree: plan_gait finds a gait; the executor: no stable grasp"
    assert bench.explain({**base, "rest_turn_reserve_deg": ""}) == full  # map space failed
    extra = {"plan_gait": "gait", "rest_turn_deg": 360}
    rows = [_row(o, "squares", "true", 0, "failed", rest_turn_reserve_deg=x, **extra)
            for o, x in (("a", 90), ("b", 360), ("c", 20))]  # fmt: skip
    squares = next(x for x in bench.summary(rows) if x.startswith("squares:"))
    tail = ("map space from rest turns 3/3 a full turn, with the executor's planning "
            "friction and threshold 1/3 (the others 20, 90 deg)")  # fmt: skip
    assert squares.endswith(tail)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--nominal", "sphere"], "--nominal: 'sphere': expected a comma-separated list"),
        (["--seeds", "0"], "--seeds: 0: expected at least 1"),
        (["--full-turn", "-1"], "--full-turn: -1: expected >= 0 simulated s"),
        (["--left-tip", "-0.02"], "--left-tip: -0.02: expected a radius >= 0 [m]"),
        (["--gravity", "-1"], "--gravity: expected a number in [0, 100] [m/s^2], got -1.0"),
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


def test_turn_series_reads_the_clockwise_turn_at_any_time(bench):
    """``TurnSeries``: the object's pose angle unwrapped over +-pi, clockwise positive from
    the start, held at the last sample after the end; the full turn's time in the columns."""
    from types import SimpleNamespace

    import numpy as np

    t = np.linspace(0.0, 4.0, 401)
    angle = np.angle(np.exp(-1j * (0.3 + np.radians(100.0) * t)))  # wrapped, clockwise
    poses = {"object": np.column_stack([np.zeros_like(t), np.zeros_like(t), angle])}
    res = SimpleNamespace(log=SimpleNamespace(t=t, poses=poses), status="ok", reason="r")
    turns = bench.TurnSeries.of(res)
    assert turns.at(0.0) == pytest.approx(0.0, abs=1e-9)
    assert turns.at(2.5) == pytest.approx(250.0, abs=1e-6)
    assert turns.at(9.0) == pytest.approx(400.0, abs=1e-6)
    cols = bench.long_columns(res, turns)
    assert cols == {"full_turn_s": 3.6, "run_end": "full turn", "run_turn_deg": 400.0}


def test_the_batch_hand_takes_a_round_left_tip(bench):
    """``--left-tip R``: the gait's hand with a round left tip of radius R, nothing else
    changed."""
    from dataclasses import replace

    pad, tip = bench.batch_hand(0.9), bench.batch_hand(0.9, 0.02)
    assert (tip.params.left.tip, tip.params.left.tip_radius) == ("round", 0.02)
    assert tip.params == replace(pad.params, left=replace(pad.params.left, tip="round",
                                                          tip_radius=0.02))  # fmt: skip
