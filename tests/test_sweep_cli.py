"""``hapex sweep`` through a subprocess: bad input -> exit 2 with FILE:LINE: key.path and
nothing written; the bundled studies run (--quick) and resume."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time

import pandas as pd
import pytest
from conftest import ROOT

SWEEPS = sorted((ROOT / "scenarios" / "sweeps").glob("*.yaml"))


def write(tmp_path, text: str):
    path = tmp_path / "s.yaml"
    path.write_text(textwrap.dedent(text))
    return path


def test_bad_sweep_file_exits_2_and_writes_nothing(cli, tmp_path):
    path = write(
        tmp_path,
        """\
        base: {kind: detect, tip_radius: 0.01, simulation: {profile: {type: wire, diameter: 7e-4}}}
        grid:
          tip_radius: [0.01]
        seeds: -1
        rnadom: {}
        """,
    )
    out = tmp_path / "out"
    proc = cli("sweep", str(path), "--out", str(out))
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert any(line.startswith(f"{path}:4: seeds: ") for line in lines), lines
    assert any(line.startswith(f"{path}:5: rnadom: unknown key") for line in lines), lines
    assert "Traceback" not in proc.stderr and not out.exists()


def test_one_bad_combination_exits_2_naming_it(cli, tmp_path):
    path = write(
        tmp_path,
        """\
        base: {kind: detect, tip_radius: 0.01, simulation: {profile: {type: wire, diameter: 7e-4}}}
        grid:
          simulation.profile.angle_deg: [0, 45, 120]
        """,
    )
    out = tmp_path / "out"
    proc = cli("sweep", str(path), "--out", str(out))
    assert proc.returncode == 2
    (line,) = proc.stderr.strip().splitlines()
    assert line.startswith(f"{path}:3: grid.simulation.profile.angle_deg: combination ")
    assert "simulation.profile.angle_deg=120" in line and "less than or equal to 89" in line
    assert not out.exists()


@pytest.mark.parametrize(
    "args, message",
    [
        (["--jobs", "0"], "--jobs: 0: must be >= 1"),
        (["--dask-local", "2", "--jobs", "2"], "--jobs is for local runs"),
        (["--dask-local", "2", "--scheduler", "tcp://x:8786"], "not allowed with argument"),
    ],
)
def test_bad_options_exit_2(cli, tmp_path, args, message):
    path = ROOT / "scenarios" / "sweeps" / "detection_noise.yaml"
    proc = cli("sweep", str(path), "--out", str(tmp_path / "o"), *args)
    assert proc.returncode == 2 and message in proc.stderr, proc.stderr
    assert not (tmp_path / "o").exists()


def test_out_folder_of_something_else_exits_2(cli, tmp_path):
    (tmp_path / "o").mkdir()
    (tmp_path / "o" / "thesis.tex").write_text("mine")
    path = ROOT / "scenarios" / "sweeps" / "detection_noise.yaml"
    proc = cli("sweep", str(path), "--quick", "--out", str(tmp_path / "o"))
    assert proc.returncode == 2 and "not a hapex sweep" in proc.stderr
    assert [p.name for p in (tmp_path / "o").iterdir()] == ["thesis.tex"]


def test_malformed_scheduler_address_exits_2_naming_it_and_writes_nothing(cli, tmp_path):
    pytest.importorskip("distributed")
    path = ROOT / "scenarios" / "sweeps" / "detection_noise.yaml"
    out = tmp_path / "o"
    proc = cli("sweep", str(path), "--quick", "--out", str(out), "--scheduler", "notanaddress")
    assert proc.returncode == 2, proc.stderr
    (line,) = proc.stderr.strip().splitlines()
    assert line.startswith("--scheduler: notanaddress: not a Dask scheduler")
    assert not out.exists()


def test_unreachable_scheduler_exits_2_before_writing_anything(tmp_path, monkeypatch, capsys):
    pytest.importorskip("distributed")
    from planner import cli
    from planner.sweep import backends

    monkeypatch.setattr(backends, "SCHEDULER_TIMEOUT", "0.5s")  # nothing listens on port 9
    path = ROOT / "scenarios" / "sweeps" / "detection_noise.yaml"
    out = tmp_path / "o"
    code = cli.main(
        ["sweep", str(path), "--quick", "--out", str(out), "--scheduler", "tcp://127.0.0.1:9"]
    )
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and line.startswith("--scheduler: tcp://127.0.0.1:9: ")
    assert not out.exists()


@pytest.mark.parametrize("below", ["sub", "sub/deeper"])
def test_out_below_a_regular_file_exits_2_and_writes_nothing(cli, tmp_path, below):
    (tmp_path / "afile").write_text("keep")
    path = ROOT / "scenarios" / "sweeps" / "detection_noise.yaml"
    out = tmp_path / "afile" / below
    proc = cli("sweep", str(path), "--quick", "--jobs", "1", "--out", str(out))
    assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr
    (line,) = proc.stderr.strip().splitlines()
    assert line == f"--out: {out}: {tmp_path / 'afile'} is a file, not a directory"
    assert (tmp_path / "afile").read_text() == "keep"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"]


@pytest.mark.parametrize("path", SWEEPS, ids=[p.stem for p in SWEEPS])
def test_bundled_sweeps_run_quick_and_resume(cli, tmp_path, path):
    out = tmp_path / "out"
    proc = cli("sweep", str(path), "--quick", "--jobs", "1", "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr
    study = json.loads((out / "sweep.json").read_text())
    df = pd.read_parquet(out / "results.parquet")
    assert len(df) == study["runs"] and df["run_id"].is_unique
    assert df["reason"].fillna("").ne("").eq(df["status"] == "failed").all()
    assert (out / "report.md").read_text().startswith(f"# Sweep {path.stem}")
    again = cli("sweep", str(path), "--quick", "--jobs", "1", "--out", str(out))
    assert again.returncode == 0
    assert f"{study['runs']} complete, 0 to run" in again.stdout


def test_dry_run_lists_every_run_and_writes_nothing(cli, tmp_path):
    from planner.sweep import load_sweep, plan

    path = ROOT / "scenarios" / "sweeps" / "gait_feasibility.yaml"
    proc = cli("sweep", str(path), "--dry-run", "--out", str(tmp_path / "o"))
    assert proc.returncode == 0, proc.stderr
    runs = plan(load_sweep(path))
    lines = proc.stdout.strip().splitlines()
    assert lines[:-1] == [f"{r.run_id}  {r.label}" for r in runs]
    assert lines[-1] == f"gait_feasibility: {len(runs)} runs, all valid"
    assert not (tmp_path / "o").exists()


def test_bundled_sweeps_are_not_scenarios(cli):
    # tests/test_bundled_scenarios.py and `hapex list` look at scenarios/*.yaml only
    assert SWEEPS and not set(SWEEPS) & set((ROOT / "scenarios").glob("*.yaml"))
    proc = cli("list", "scenarios")
    assert proc.returncode == 0
    assert not any(p.stem in proc.stdout for p in SWEEPS)


def test_ctrl_c_stops_cleanly_and_says_how_to_resume(cli, tmp_path):
    path = write(
        tmp_path,
        """\
        base:
          kind: detect
          tip_radius: 0.01
          algorithms: [3]
          simulation: {profile: {type: wire, diameter: 0.00065, length: 0.005}, spacing: 1.0e-4}
        seeds: 40
        """,
    )
    out = tmp_path / "out"
    args = [sys.executable, "-m", "planner.cli", "sweep", str(path), "--jobs", "1"]
    proc = subprocess.Popen(
        [*args, "--out", str(out)],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=dict(os.environ, MPLBACKEND="Agg"),
    )
    deadline = time.monotonic() + 120
    while not any((out / "runs").glob("[0-9a-f]*")) and time.monotonic() < deadline:
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 130, stderr
    assert "Traceback" not in stderr
    assert f"runs complete in {out}; complete runs are kept." in stderr
    assert f"Resume with: hapex sweep {path} --out {out} --jobs 1" in stderr
    done = pd.read_parquet(out / "results.parquet")
    assert 1 <= len(done) < 40
    again = cli("sweep", str(path), "--jobs", "1", "--out", str(out), "--no-report")
    assert again.returncode == 0, again.stderr
    assert f"40 runs, {len(done)} complete, {40 - len(done)} to run" in again.stdout
    table = pd.read_parquet(out / "results.parquet")
    assert len(table) == 40 and table["run_id"].is_unique


@pytest.mark.parametrize(
    "options",
    [
        [],
        ["--quick", "--jobs", "2", "--retry-failed", "--no-report"],
        ["--scheduler", "tcp://h:8786", "--retry-failed"],
        ["--dask-local", "3", "--no-report", "--quick"],
    ],
)
def test_resume_command_keeps_every_option_that_changes_what_runs(tmp_path, options):
    from planner.cli import _parser
    from planner.sweep.command import resume_command

    out = tmp_path / "o"
    args = _parser().parse_args(["sweep", "s.yaml", "--out", str(out), *options, "-v"])
    again = resume_command(args, out)
    assert again[:5] == ["hapex", "sweep", "s.yaml", "--out", str(out)]
    # the same options (in any order), the verbosity aside: the command runs the same study
    resumed = _parser().parse_args(again[1:])
    for key in ("sweep", "out", "quick", "jobs", "scheduler", "dask_local", "retry_failed"):
        assert getattr(resumed, key) == getattr(args, key), key
    assert resumed.no_report == args.no_report and not resumed.dry_run
