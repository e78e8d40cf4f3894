"""Scenario kind grasp_map: every bundled grasp_map scenario runs (quick) with its key outputs."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from planner.errors import ScenarioError
from planner.runner import execute
from planner.scenario import load_scenario, scenario_from_dict

ROOT = Path(__file__).resolve().parents[1] / "scenarios"


@pytest.mark.parametrize(
    "name", ["circle_grasp_map", "square_grasp_map", "ellipse_grasp_map", "hexagon_grasp_map"]
)
def test_bundled_scenarios_find_a_gait(name, tmp_path):
    out = execute(load_scenario(ROOT / f"{name}.yaml"), out_dir=tmp_path / "run", quick=True)
    res = out.result
    assert res.status == "ok", res.reason
    m = res.metrics
    assert m["gait_feasible"] and m["gait_turns"] >= 1
    assert m["rotation_per_cycle_deg"] < 0  # clockwise
    assert m["coverage"] == pytest.approx(1.0)
    assert 0 < m["closure_fraction"] < 1
    run = tmp_path / "run"
    gait = json.loads((run / "gait.json").read_text())
    assert gait["feasible"] and gait["phases"][0]["phase"] == 1
    arrays = np.load(run / "trajectory.npz")
    n = m["resolution"]
    assert arrays["force_closure_left_right"].shape == (n, n)
    assert np.array_equal(arrays["force_closure_left_right"], arrays["force_closure_left_right"].T)
    assert arrays["reachable_left"].any() and arrays["reachable_right"].any()
    assert (run / "plots" / "grasp_map.png").exists()


def test_circle_map_matches_fig_2_4_rule(tmp_path):
    out = execute(load_scenario(ROOT / "circle_grasp_map.yaml"), out_dir=tmp_path / "r", quick=True)
    # mu = 1: force closure iff the angular separation exceeds 90 deg -> half of the map
    assert out.result.metrics["closure_fraction"] == pytest.approx(0.5, abs=0.02)


def test_long_thin_object_fails_with_reason(tmp_path):
    out = execute(
        load_scenario(ROOT / "long_thin_object.yaml"), out_dir=tmp_path / "run", quick=True
    )
    assert out.result.status == "failed"
    assert "no grasp gait" in out.result.reason
    assert "workspace" in out.result.reason or "force closure" in out.result.reason
    assert not out.result.metrics["gait_feasible"]


def test_bad_object_keys_are_rejected():
    with pytest.raises(ScenarioError, match="needs key"):
        scenario_from_dict(
            {"name": "x", "kind": "grasp_map", "object": {"type": "ellipse", "a": 0.05}}
        )
    with pytest.raises(ScenarioError, match="greater than or equal"):
        scenario_from_dict(
            {
                "name": "x",
                "kind": "grasp_map",
                "mu": -1,
                "object": {"type": "circle", "radius": 0.05},
            }
        )


@pytest.mark.parametrize(
    ("override", "key"),
    [
        ("mu=-1", "mu"),
        ("object.type=star", "object.type"),
        ("resolution=2", "resolution"),
        ("object.radius=-0.05", "object.radius"),
        ("direction=up", "direction"),
        ("min_epsilon=1.5", "min_epsilon"),
    ],
)
def test_bad_value_is_exit_2_one_line_nothing_written(cli, tmp_path, override, key):
    out = tmp_path / "out"
    r = cli("run", "scenarios/circle_grasp_map.yaml", "--set", override, "--out", str(out))
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and key in lines[0], r.stderr
    assert not out.exists()


def test_non_star_shaped_polygon_is_exit_2(cli, tmp_path):
    # a U-shaped polygon is not star-shaped about its origin: caught by the Config validator
    u = (
        "[[-0.03,-0.03],[0.03,-0.03],[0.03,0.03],[0.02,0.03],"
        "[0.02,-0.02],[-0.02,-0.02],[-0.02,0.03],[-0.03,0.03]]"
    )
    r = cli(
        "validate",
        "scenarios/hexagon_grasp_map.yaml",
        "--set",
        f"object.points={u}",
    )
    assert r.returncode == 2, r.stdout + r.stderr
    assert "star-shaped" in r.stderr
