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
            {"name": "x", "kind": "grasp_map", "object": {"shape": "ellipse", "a": 0.05}}
        )
    with pytest.raises(ScenarioError, match="greater than or equal"):
        scenario_from_dict(
            {
                "name": "x",
                "kind": "grasp_map",
                "mu": -1,
                "object": {"shape": "circle", "radius": 0.05},
            }
        )
