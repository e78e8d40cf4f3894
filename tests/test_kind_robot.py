"""The ``robot`` scenario kind and its bundled scenarios (run quick, outputs checked)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from planner.errors import ScenarioError
from planner.runner import execute
from planner.scenario import load_scenario


def _run(tmp_path, name, overrides=()):
    cfg = load_scenario(f"scenarios/{name}.yaml", overrides)
    execute(cfg, out_dir=tmp_path / "run", quick=True)
    result = json.loads((tmp_path / "run" / "result.json").read_text())
    npz = tmp_path / "run" / "trajectory.npz"
    return result, (np.load(npz) if npz.is_file() else None)


def test_hand_workspace_scenario(tmp_path):
    result, arrays = _run(tmp_path, "hand_workspace_robot")
    assert result["status"] == "ok"
    m = result["metrics"]
    # each finger reaches a contiguous arc on its own side of the 10 cm ball
    assert 0 <= m["reachable_angle_min_deg_right"] < m["reachable_angle_max_deg_right"] <= 100
    assert 100 <= m["reachable_angle_min_deg_left"] < m["reachable_angle_max_deg_left"] <= 180
    assert m["reachable_fraction_right"] > 0.1 and m["reachable_fraction_left"] > 0.05
    assert arrays["reachable_left"].shape == arrays["contact_angles"].shape
    assert arrays["q"].shape == (6,)
    assert (tmp_path / "run" / "plots" / "hand.png").is_file()


def test_three_gm_workspace_scenario(tmp_path):
    result, arrays = _run(tmp_path, "three_gm_workspace_robot")
    assert result["status"] == "ok"
    m = result["metrics"]
    assert m["workspace_volume_in3"] == pytest.approx(112.0)
    assert m["workspace_reachable_fraction"] == 1.0
    assert m["force_at_center_N"] == pytest.approx(9.0)
    assert m["workspace_max_condition"] < 7.0
    assert arrays["workspace_points"].shape[1] == 3
    assert (tmp_path / "run" / "plots" / "three_gm.png").is_file()


def test_configuration_outside_limits_rejected_at_load():
    # a value rule: caught by `hapex validate` (exit 2), not a failed run
    with pytest.raises(ScenarioError, match="outside the joint limits"):
        load_scenario("scenarios/three_gm_workspace_robot.yaml", ["configuration_deg=[170, 0, 0]"])
    with pytest.raises(ScenarioError, match="outside the joint limits"):
        load_scenario(
            "scenarios/hand_workspace_robot.yaml", ["configuration_deg=[0, 0, 0, 0, 0, 400]"]
        )


@pytest.mark.parametrize(
    ("scenario", "override", "key"),
    [
        ("three_gm_workspace_robot", "configuration_deg=[170, 0, 0]", "configuration_deg"),
        ("hand_workspace_robot", "hand.ball_diameter=-0.1", "hand.ball_diameter"),
        ("hand_workspace_robot", "hand.left_tip=pointy", "hand.left_tip"),
        ("three_gm_workspace_robot", "three_gm.grid=1", "three_gm.grid"),
    ],
)
def test_bad_value_is_exit_2_one_line_nothing_written(cli, tmp_path, scenario, override, key):
    out = tmp_path / "out"
    r = cli("run", f"scenarios/{scenario}.yaml", "--set", override, "--out", str(out))
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and key in lines[0], r.stderr
    assert not out.exists()


def test_bad_configuration_length_rejected_at_load():
    with pytest.raises(ScenarioError, match="configuration_deg must have 6 angles"):
        load_scenario("scenarios/hand_workspace_robot.yaml", ["configuration_deg=[1, 2, 3]"])
    with pytest.raises(ScenarioError, match="unknown key"):
        load_scenario("scenarios/hand_workspace_robot.yaml", ["hand.finger_count=3"])
