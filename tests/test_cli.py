"""The command line through a subprocess: exit codes, one line per error, nothing left."""

from __future__ import annotations

import json
import textwrap

import numpy as np
import pytest
from conftest import ROOT, run_cli

GOOD = textwrap.dedent("""\
    name: tiny_step
    kind: trace
    description: a small step
    seed: 7
    profile:
      type: step
      height: 0.004
      length: 0.03
    tip_radius: 0.005
    sampling:
      spacing: 2.0e-4
    noise:
      center_sigma: 1.0e-4
    """)


def write(tmp_path, text, name="s.yaml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def assert_bad_input(proc, *fragments):
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    for frag in fragments:
        assert any(frag in ln for ln in lines), (frag, proc.stderr)
    return lines


def test_version_and_help():
    proc = run_cli("--version")
    assert proc.returncode == 0 and proc.stdout.startswith("hapex ")
    assert run_cli("--help").returncode == 0


def test_run_writes_complete_run_directory(tmp_path):
    out = tmp_path / "run"
    proc = run_cli("run", str(write(tmp_path, GOOD)), "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    doc = json.loads((out / "result.json").read_text())
    assert doc["schema"] == 1 and doc["status"] == "ok" and doc["kind"] == "trace"
    assert doc["name"] == "tiny_step" and doc["seed"] == 7
    assert {"hapex", "pin", "casadi", "numpy", "numpy_simd"} <= set(doc["versions"])
    assert doc["timings_s"]["total"] > 0
    for rel in doc["files"].values():
        assert (out / rel).is_file(), rel
    assert (out / "scenario.yaml").is_file() and (out / "plots" / "trace.png").is_file()
    with np.load(out / "trajectory.npz") as z:
        assert z["interference_points"].shape == (1, 2)
    # no temporary siblings left behind
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []


def test_seed_and_set_overrides_are_resolved(tmp_path):
    out = tmp_path / "run"
    proc = run_cli(
        "run",
        str(write(tmp_path, GOOD)),
        "--out",
        str(out),
        "--seed",
        "11",
        "--set",
        "tip_radius=0.006",
        "--set",
        "profile.height=0.003",
        "--no-plots",
    )
    assert proc.returncode == 0, proc.stderr
    import yaml

    resolved = yaml.safe_load((out / "scenario.yaml").read_text())
    assert resolved["seed"] == 11 and resolved["tip_radius"] == 0.006
    assert resolved["profile"]["height"] == 0.003
    assert resolved["output"]["formats"] == ["png"]  # defaults filled in
    assert not (out / "plots").exists()


def test_same_seed_same_numbers(tmp_path):
    s = write(tmp_path, GOOD)
    for name in ("a", "b"):
        assert run_cli("run", str(s), "--out", str(tmp_path / name), "--no-plots").returncode == 0
    with (
        np.load(tmp_path / "a" / "trajectory.npz") as a,
        np.load(tmp_path / "b" / "trajectory.npz") as b,
    ):
        np.testing.assert_array_equal(a["centers"], b["centers"])


def test_all_errors_at_once_with_lines(tmp_path):
    bad = GOOD.replace("tip_radius: 0.005", "tip_radius: -0.005").replace(
        "  center_sigma: 1.0e-4", "  center_sigma: -1.0\n  colour: red"
    )
    s = write(tmp_path, bad)
    out = tmp_path / "out"
    proc = run_cli("run", str(s), "--out", str(out))
    lines = assert_bad_input(proc, "tip_radius", "noise.center_sigma", "noise.colour")
    assert len(lines) == 3
    assert any(ln.startswith(f"{s}:9: tip_radius:") for ln in lines), lines
    assert any(ln.startswith(f"{s}:14: noise.colour: unknown key") for ln in lines), lines
    assert not out.exists()


@pytest.mark.parametrize(
    "text, key",
    [
        ("kind: nope\n", "kind"),
        ("name: x\n", "kind"),
        (GOOD.replace("type: step", "type: stair"), "profile"),
        (GOOD.replace("spacing: 2.0e-4", "samples: 1"), "sampling.samples"),
        (GOOD.replace("height: 0.004", "height: 0"), "profile"),
        (GOOD.replace("seed: 7", "seed: -1"), "seed"),
        (GOOD.replace("tip_radius: 0.005", "tip_radius: abc"), "tip_radius"),
        (GOOD.replace("tip_radius: 0.005", "tip_radius: .inf"), "tip_radius"),
        (GOOD.replace("center_sigma: 1.0e-4", "center_sigma: .nan"), "noise.center_sigma"),
        (GOOD + "smoothing:\n  sigma_samples: 1.0e+9\n", "smoothing.sigma_samples"),
        ("- a\n- b\n", "(root)"),
        ("kind: [trace\n", "(root)"),
        ("", "(root)"),
    ],
)
def test_bad_scenarios(tmp_path, text, key):
    s = write(tmp_path, text)
    out = tmp_path / "out"
    proc = run_cli("run", str(s), "--out", str(out))
    lines = assert_bad_input(proc, f": {key}")
    assert all(ln.startswith(f"{s}:") for ln in lines)
    assert not out.exists()


def test_an_infinite_number_is_named_at_its_line(tmp_path):
    s = write(tmp_path, GOOD.replace("tip_radius: 0.005", "tip_radius: .inf"))
    lines = assert_bad_input(run_cli("run", str(s), "--out", str(tmp_path / "out")))
    assert lines == [f"{s}:9: tip_radius: Input should be a finite number"]


def test_missing_file_and_bad_set(tmp_path):
    proc = run_cli("run", str(tmp_path / "missing.yaml"))
    assert_bad_input(proc, "missing.yaml:0: (root): file not found")
    s = write(tmp_path, GOOD)
    out = tmp_path / "out"
    proc = run_cli("run", str(s), "--out", str(out), "--set", "tip_radiuss=1")
    assert_bad_input(proc, "--set:1:0: tip_radiuss: unknown key")
    proc = run_cli("run", str(s), "--out", str(out), "--set", "noequals")
    assert_bad_input(proc, "--set:1")
    proc = run_cli("run", str(s), "--out", str(out), "--set", "tip_radius.x=1")
    assert_bad_input(proc, "tip_radius")
    assert not out.exists()


def test_bad_options():
    assert_bad_input(run_cli("run"), "hapex: error")
    assert_bad_input(run_cli("frobnicate"), "hapex: error")
    assert_bad_input(run_cli("list", "everything"), "hapex: error")


def test_refuses_foreign_out_directory(tmp_path):
    out = tmp_path / "precious"
    out.mkdir()
    (out / "thesis.tex").write_text("keep me")
    proc = run_cli("run", str(write(tmp_path, GOOD)), "--out", str(out))
    assert_bad_input(proc, "not a hapex run directory")
    assert (out / "thesis.tex").read_text() == "keep me"


@pytest.mark.parametrize("below", ["sub", "sub/deeper"])
def test_out_below_a_regular_file_exits_2_before_running(tmp_path, below):
    (tmp_path / "afile").write_text("keep me")
    s = write(tmp_path, GOOD)
    out = tmp_path / "afile" / below
    proc = run_cli("run", str(s), "--out", str(out))
    (line,) = assert_bad_input(proc)
    assert line == f"--out: {out}: {tmp_path / 'afile'} is a file, not a directory"
    assert proc.stdout == ""  # refused before the scenario ran
    assert (tmp_path / "afile").read_text() == "keep me"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile", s.name]


def test_foreign_out_directory_is_refused_before_running(tmp_path):
    out = tmp_path / "precious"
    out.mkdir()
    (out / "thesis.tex").write_text("keep me")
    proc = run_cli("run", str(write(tmp_path, GOOD)), "--out", str(out))
    (line,) = assert_bad_input(proc)
    assert line.startswith(f"--out: {out}: directory is not empty and is not a hapex run")
    assert proc.stdout == ""


def test_rerun_replaces_previous_run(tmp_path):
    s = write(tmp_path, GOOD)
    out = tmp_path / "run"
    assert run_cli("run", str(s), "--out", str(out), "--no-plots").returncode == 0
    assert run_cli("run", str(s), "--out", str(out), "--no-plots", "--seed", "3").returncode == 0
    assert json.loads((out / "result.json").read_text())["seed"] == 3


def test_verbose_shows_traceback(tmp_path):
    proc = run_cli("run", str(write(tmp_path, "kind: nope\n")), "-v")
    assert proc.returncode == 2 and "Traceback" in proc.stderr


def test_validate_many_reports_each(tmp_path):
    good = write(tmp_path, GOOD, "good.yaml")
    bad = write(tmp_path, GOOD.replace("tip_radius: 0.005", "tip_radius: 0"), "bad.yaml")
    proc = run_cli("validate", str(good), str(bad))
    assert proc.returncode == 2
    assert "good.yaml: ok (trace)" in proc.stdout
    assert f"{bad}:9: tip_radius:" in proc.stderr
    assert run_cli("validate", str(good)).returncode == 0


def test_list_scenarios_kinds_robots():
    proc = run_cli("list")
    assert proc.returncode == 0
    names = {ln.split()[0] for ln in proc.stdout.splitlines()}
    bundled = {p.stem for p in (ROOT / "scenarios").glob("*.yaml")}
    assert bundled <= names
    kinds = run_cli("list", "kinds")
    assert kinds.returncode == 0 and "trace" in kinds.stdout
    robots = run_cli("list", "robots")
    assert robots.returncode == 0 and robots.stdout.strip()


def test_union_member_errors_name_the_key(tmp_path):
    s = write(tmp_path, GOOD.replace("height: 0.004", "height: 0"))
    proc = run_cli("validate", str(s))
    assert_bad_input(proc, f"{s}:5: profile: height must be non-zero")
    s = write(tmp_path, GOOD.replace("  height: 0.004\n", ""))
    proc = run_cli("validate", str(s))
    assert_bad_input(proc, "profile.height: required key is missing")


def test_set_reaches_list_items(tmp_path):
    s = ROOT / "scenarios" / "feature_map.yaml"
    assert run_cli("validate", str(s), "--set", "features.0.spacing=0.001").returncode == 0
    proc = run_cli("validate", str(s), "--set", "features.0.spacing=-1")
    assert_bad_input(proc, "--set:1:0: features[0].spacing:")
    proc = run_cli("validate", str(s), "--set", "features.99.spacing=0.001")
    assert_bad_input(proc, "features.99: is not an index")


def test_sampling_coarser_than_profile_is_bad_input(tmp_path):
    s = write(tmp_path, GOOD.replace("spacing: 2.0e-4", "spacing: 1.0"))
    out = tmp_path / "out"
    assert_bad_input(run_cli("run", str(s), "--out", str(out)), "fewer than 3 samples")
    assert not out.exists()


def test_bad_set_union_tag_is_blamed_on_set(tmp_path):
    s = write(tmp_path, GOOD)
    proc = run_cli("validate", str(s), "--set", "profile.type=stepp")
    lines = assert_bad_input(proc, "--set:1:0: profile.type: unknown type 'stepp'")
    assert len(lines) == 1 and str(s) not in proc.stderr
    # the same mistake in the file points at the file's line of the tag
    s = write(tmp_path, GOOD.replace("type: step", "type: stepp"))
    assert_bad_input(run_cli("validate", str(s)), f"{s}:6: profile.type: unknown type 'stepp'")


@pytest.mark.parametrize("args", [("list", "kinds"), ("list", "scenarios"), ("--help",)])
def test_closed_stdout_pipe_is_quiet(args):
    """``hapex list kinds | head -1``: the reader goes away; no BrokenPipeError traceback."""
    import os
    import subprocess
    import sys

    read_end, write_end = os.pipe()
    os.close(read_end)  # every write to stdout now fails with EPIPE, deterministically
    try:
        proc = subprocess.run(
            [sys.executable, "-m", "planner.cli", *args],
            cwd=ROOT,
            stdout=write_end,
            stderr=subprocess.PIPE,
            text=True,
            timeout=120,
            env=dict(os.environ, MPLBACKEND="Agg"),
        )
    finally:
        os.close(write_end)
    assert proc.stderr == ""
    # 128 + SIGPIPE, as the shell reports for `yes | head`; argparse swallows its own
    # write errors for --help and exits 0
    assert proc.returncode == (0 if args == ("--help",) else 141)


def test_bad_input_found_by_a_runner_is_exit_2_nothing_written(tmp_path, monkeypatch, capsys):
    """A value rule a Config missed, found while running: still exit 2, one line, no run dir."""
    import planner.scenario as scenario
    from planner.cli import main
    from planner.errors import InputIssue, ScenarioError

    spec = scenario.kinds()["trace"]

    def late(config, ctx):
        raise ScenarioError([InputIssue("(scenario)", 0, "sampling", "too coarse")])

    patched = dict(scenario.kinds(), trace=scenario.KindSpec("trace", spec.config, late, "x"))
    import planner.runner as runner

    monkeypatch.setattr(scenario, "kinds", lambda: patched)
    monkeypatch.setattr(runner, "kinds", lambda: patched)
    out = tmp_path / "run"
    code = main(["run", str(write(tmp_path, GOOD)), "--no-plots", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.strip() == "(scenario):0: sampling: too coarse"
    assert not out.exists()


def test_the_console_script_ignores_ctrl_c_once_the_command_is_done(monkeypatch):
    """``entry`` returns main's exit code and leaves SIGINT ignored for the interpreter's
    exit (a late Ctrl-C must not turn a finished command into a death by signal)."""
    import signal

    import planner.cli as cli

    calls = []

    def fake_main(argv=None):
        calls.append(signal.getsignal(signal.SIGINT))
        return 7

    monkeypatch.setattr(cli, "main", fake_main)
    before = signal.getsignal(signal.SIGINT)
    try:
        assert cli.entry() == 7
        assert calls == [before]  # the command itself runs with the normal handler
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, before)


def test_bad_input_found_late_is_put_at_its_key_and_line(tmp_path):
    """The spacing passes validation; the profile's length set on the command line makes
    it too fine only once the run builds the profile (the library's InvalidParameter)."""
    scenario = ROOT / "scenarios" / "wire_detect_compare.yaml"
    line = 1 + next(i for i, ln in enumerate(scenario.read_text().splitlines())
                    if ln.strip().startswith("spacing:"))  # fmt: skip
    out = tmp_path / "out"
    proc = run_cli("run", str(scenario), "--quick", "--out", str(out),
                   "--set", "simulation.profile.length=1e9")  # fmt: skip
    lines = assert_bad_input(proc)
    assert len(lines) == 1
    assert lines[0].startswith(f"{scenario}:{line}: simulation.spacing: expected at least")
    assert not out.exists()


def test_late_issue_names_one_key_or_the_root(tmp_path):
    from planner.scenario import late_issue

    s = write(tmp_path, GOOD)
    issue = late_issue(s, [], "tip_radius: expected < 1 [m], got 5")
    assert (issue.line, issue.path, issue.message) == (9, "tip_radius", "expected < 1 [m], got 5")
    issue = late_issue(s, ["noise.center_sigma=0.001"], "center_sigma: too big")
    assert (issue.source, issue.path) == ("--set:1", "noise.center_sigma")
    # a key left at its default: named from the resolved scenario, line unknown
    issue = late_issue(s, [], "speed: too fast", resolved={"sampling": {"speed": 0.03}})
    assert (issue.line, issue.path, issue.message) == (0, "sampling.speed", "too fast")
    # no such key, or not one key: the whole message at the root
    for msg in ("centers: spans 7e9 m", "a sentence without a name", "speed: too fast"):
        issue = late_issue(s, [], msg, resolved={"a": {"speed": 1}, "b": [{"speed": 2}]})
        assert (issue.line, issue.path, issue.message) == (0, "(root)", msg)
