"""Tests of the executed grasp gait (planner.exploration.planar) and the ``gait`` kind."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from planner.errors import InvalidParameter
from planner.exploration.planar import circle_with_ridge, explore_object
from planner.exploration.planar.objects import mean_radius, rest_height
from planner.geometry import shapes


def test_circle_with_ridge_geometry():
    p = circle_with_ridge(0.05, 0.004, 0.003, angle=1.0)
    assert p.closed
    # perimeter: circle minus the base plus the top arc and two sides (~3 mm each)
    assert p.length == pytest.approx(2 * math.pi * 0.05 + 2 * 0.003, abs=2e-4)
    assert rest_height(p) == pytest.approx(0.05, abs=1e-6)
    assert mean_radius(shapes.circle(0.04)) == pytest.approx(0.04, rel=1e-3)
    pts, _ = p.point_at_polar_angle([1.0, 1.0 + math.pi])
    assert np.linalg.norm(pts[0]) == pytest.approx(0.053, abs=1e-6)
    assert np.linalg.norm(pts[1]) == pytest.approx(0.05, abs=1e-6)


def test_bad_inputs_raise():
    with pytest.raises(InvalidParameter, match="mu"):
        explore_object(shapes.circle(0.05), mu=0.0)
    with pytest.raises(InvalidParameter, match="closed"):
        explore_object(shapes.plane())
    with pytest.raises(InvalidParameter, match="does not fit"):
        explore_object(shapes.circle(0.02), duration=0.1)


@pytest.fixture(scope="module")
def short_run():
    return explore_object(circle_with_ridge(angle=math.radians(170)), duration=0.3, seed=1)


def test_short_run_grasps_and_rotates_clockwise(short_run):
    res = short_run
    assert res.status == "ok"
    assert res.phases[0].kind == 1
    assert res.phases[0].planned_rotation < 0  # the NLP plans a clockwise rotation
    assert res.rotation < 0  # and the object turns clockwise
    assert 0 < res.coverage < 1
    tr = res.trace
    late = tr["t"] > 0.15
    # the internal-force servo settles near its command (sensed by the strain gauges)
    assert np.median(np.abs(tr["f_int"][late] - tr["f_des"][late])) < 0.2
    # the sensed rotation (tactile + encoders, eq. 2.4) follows the true one
    assert tr["theta"][-1] == pytest.approx(res.rotation, abs=math.radians(3))


def test_gait_kind_cli_runs_quick(cli, tmp_path):
    out = tmp_path / "run"
    proc = cli("run", "scenarios/ball_with_ridge.yaml", "--quick", "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    doc = json.loads((out / "result.json").read_text())
    assert doc["kind"] == "gait" and doc["status"] == "ok"
    m = doc["metrics"]
    for key in ("phases", "rotation_deg", "coverage", "min_epsilon", "real_time_factor",
                "nlp_solve_median_ms", "internal_force_rms_error_N"):  # fmt: skip
        assert key in m
    for plot in ("snapshots", "forces", "contacts", "timeline"):
        assert (out / "plots" / f"{plot}.png").exists()


def test_gait_kind_bad_input_exits_2(cli, tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("kind: gait\nobject:\n  shape: circle\n  radius: 0.05\nmu: -1\n")
    proc = cli("run", str(bad), "--out", str(tmp_path / "o"))
    assert proc.returncode == 2
    assert "mu" in proc.stderr
    assert not (tmp_path / "o").exists()
    small = tmp_path / "small.yaml"
    small.write_text("kind: gait\nobject:\n  shape: circle\n  radius: 0.02\n")
    proc = cli("validate", str(small))
    assert proc.returncode == 2
    assert "does not fit" in proc.stderr
