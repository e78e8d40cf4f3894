"""The ``contact_sim`` scenario kind through the CLI: runs, metrics, bad input."""

from __future__ import annotations

import json
import math

import pytest

from tests.conftest import ROOT


def test_incline_box_runs_static(cli, tmp_path):
    out = tmp_path / "run"
    res = cli("run", str(ROOT / "scenarios/incline_box.yaml"), "--quick", "--out", str(out))
    assert res.returncode == 0, res.stderr
    result = json.loads((out / "result.json").read_text())
    assert result["status"] == "ok"
    m = result["metrics"]
    assert max(abs(v) for v in m["box.displacement_m"][:2]) <= 1e-9
    assert m["max_penetration_m"] <= 1e-6
    assert (out / "plots" / "trajectories.png").exists()
    assert (out / "trajectory.npz").exists()


def test_sliding_box_override_matches_closed_form(cli, tmp_path):
    out = tmp_path / "run"
    res = cli(
        "run",
        str(ROOT / "scenarios/incline_box.yaml"),
        "--quick",
        "--no-plots",
        "--set",
        "fixed.0.friction=0.1",
        "--set",
        "bodies.0.friction=0.1",
        "--out",
        str(out),
    )
    assert res.returncode == 0, res.stderr
    m = json.loads((out / "result.json").read_text())["metrics"]
    a = math.hypot(*m["box.mean_acceleration"][:2])
    g, al = 9.81, math.radians(20)
    assert a == pytest.approx(g * (math.sin(al) - 0.1 * math.cos(al)), rel=5e-3)


BAD = """name: bad
kind: contact_sim
dt: 0.0
duration: 1.0
fixed:
  - name: floor
    profile: {type: plane, length: 1.0}
    friction: -0.1
bodies:
  - name: b
    profile: {type: circle, radius: 0.02}
    pose: [0, 0.05, 0]
    mass: -1
"""

OVERLAP = """name: overlap
kind: contact_sim
duration: 1.0
fixed:
  - name: floor
    profile: {type: plane, length: 1.0}
bodies:
  - name: b
    profile: {type: circle, radius: 0.02}
    pose: [0, 0.01, 0]
    mass: 1
"""


def test_bad_input_exits_2_with_key_paths(cli, tmp_path):
    f = tmp_path / "bad.yaml"
    f.write_text(BAD)
    res = cli("run", str(f), "--out", str(tmp_path / "o"))
    assert res.returncode == 2
    for key in ("dt", "fixed[0].friction", "bodies[0].mass"):
        assert f": {key}:" in res.stderr
    assert not (tmp_path / "o").exists()
    f.write_text(OVERLAP)
    res = cli("validate", str(f))
    assert res.returncode == 2 and "bodies:" in res.stderr and "penetration" in res.stderr
    f.write_text(OVERLAP.replace("pose: [0, 0.01, 0]", "pose: [0, 0.03, 0]"))
    assert cli("validate", str(f)).returncode == 0


def test_scene_params_are_checked(cli, tmp_path):
    f = tmp_path / "s.yaml"
    f.write_text("name: s\nkind: contact_sim\nscene:\n  preset: pinch\n  params: {squeez: 1}\n")
    res = cli("validate", str(f))
    assert res.returncode == 2 and "squeez" in res.stderr
