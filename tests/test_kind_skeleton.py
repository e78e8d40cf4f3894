"""Scenario kind ``skeleton``: bundled scenarios, data files, validation errors."""

import json
from pathlib import Path

import numpy as np
import pytest

from planner.errors import ScenarioError
from planner.runner import execute
from planner.scenario import load_scenario
from planner.skeleton.datafile import load_boundaries

ROOT = Path(__file__).resolve().parents[1]
SCEN = ROOT / "scenarios"


def run(name, tmp_path, plots=False, **kw):
    cfg = load_scenario(SCEN / f"{name}.yaml", **kw)
    out = execute(cfg, out_dir=tmp_path / name, quick=True, plots=plots, base_dir=SCEN)
    return out.result, out.out_dir


def test_ridge_skeleton(tmp_path):
    res, out = run("ridge_skeleton", tmp_path, plots=True)
    m = res.metrics
    assert res.status == "ok"
    assert m["ridge.branch_points"] == 0 and m["ridge.end_points"] == 2
    assert m["ridge.length_m"] == pytest.approx(0.04, rel=0.05)  # centre line 40 mm
    assert m["ridge.hausdorff_to_truth_m"] < 3 * 0.0008  # quick: spacing doubled to 0.8 mm
    assert m["ridge.regeneration_area_ratio"] < 0.05
    assert (out / "plots" / "dvma_ridge.png").is_file()
    geo = json.loads((out / "skeletons.geojson").read_text())
    assert geo["type"] == "FeatureCollection"


def test_curved_ridge_skeleton(tmp_path):
    res, out = run("curved_ridge_skeleton", tmp_path)
    m = res.metrics
    assert res.status == "ok"
    assert m["curved.end_points"] == 2 and m["curved.branch_points"] == 0
    arc = 0.025 * np.deg2rad(140.0)
    assert m["curved.length_m"] == pytest.approx(arc, rel=0.05)
    assert m["sharp_turn.end_points"] >= 2
    assert m["region_area_total_m2"] == pytest.approx(m["domain_area_m2"], rel=1e-9)


def test_feature_map(tmp_path):
    res, out = run("feature_map", tmp_path)
    m = res.metrics
    assert res.status == "ok" and m["n_features"] == 4
    assert m["ring_c.has_loop"] and m["ring_c.end_points"] == 0
    assert m["branch_d.branch_points"] == 1 and m["branch_d.end_points"] == 3
    assert m["region_area_total_m2"] == pytest.approx(m["domain_area_m2"], rel=1e-9)
    assert m["path_min_clearance_m"] >= 0.004  # tip_radius
    assert m["clearance_m"] > 0.004 and m["impassable_pairs"] == []
    data = np.load(out / "trajectory.npz")
    assert data["global_edges"].shape[1] == 2 and data["path"].shape[1] == 2
    assert data["pair_clearance"].shape == (4, 4)


def test_skeleton_from_csv(tmp_path):
    res, _ = run("skeleton_from_csv", tmp_path)
    m = res.metrics
    assert res.status == "ok" and m["n_features"] == 3
    for f in ("ridge_1", "bump_2", "ridge_3"):
        assert m[f"{f}.end_points"] == 2 and m[f"{f}.branch_points"] == 0


def test_overrides_and_generators(tmp_path):
    res, _ = run(
        "feature_map",
        tmp_path,
        overrides=[
            "global_map.generators=skeleton",
            "global_map.start=null",
            "global_map.goal=null",
        ],
    )
    assert res.status == "ok" and "path_length_m" not in res.metrics


def write(tmp_path, text, name="s.yaml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_validation_errors(tmp_path):
    p = write(tmp_path, "kind: skeleton\nfeatures:\n  - {name: a, shape: blob, spacing: -1}\n")
    with pytest.raises(ScenarioError) as err:
        load_scenario(p)
    text = str(err.value)
    assert "features[0].shape" in text and "features[0].spacing" in text
    p = write(tmp_path, "kind: skeleton\ndata_file: x.csv\nfeatures:\n  - {name: a, shape: ring}\n")
    with pytest.raises(ScenarioError, match="either features"):
        load_scenario(p)
    p = write(
        tmp_path,
        "kind: skeleton\nfeatures:\n  - {name: a, shape: ring}\nglobal_map: {start: [0, 0]}\n",
    )
    with pytest.raises(ScenarioError, match="both start and goal"):
        load_scenario(p)


def test_bad_csv_reports_every_problem(tmp_path):
    csv = write(tmp_path, "feature_id,x,y\na,0,0\na,zero,1\nb,1\nb,2,nan\n", "bad.csv")
    with pytest.raises(ScenarioError) as err:
        load_boundaries(csv)
    lines = sorted(i.line for i in err.value.issues)
    assert lines == [3, 4, 5]
    with pytest.raises(ScenarioError, match="missing column"):
        load_boundaries(write(tmp_path, "id,x,y\n1,2,3\n", "h.csv"))
    with pytest.raises(ScenarioError, match="unknown data file type"):
        load_boundaries(write(tmp_path, "x", "d.txt"))


def test_npz_data_and_failed_feature(tmp_path):
    t = np.linspace(0, 2 * np.pi, 80, endpoint=False)
    x = np.concatenate([0.01 * np.cos(t), [0.05, 0.051, 0.052]])
    y = np.concatenate([0.005 * np.sin(t), [0.0, 0.0, 0.0]])
    fid = np.array(["disk"] * 80 + ["line"] * 3)
    np.savez(tmp_path / "b.npz", feature_id=fid, x=x, y=y)
    ids, bnd = load_boundaries(tmp_path / "b.npz")
    assert ids == ["disk", "line"] and bnd[0].shape == (80, 2)
    p = write(tmp_path, "kind: skeleton\ndata_file: b.npz\noutput: {plots: false}\n")
    out = execute(load_scenario(p), out_dir=tmp_path / "run", quick=True, base_dir=tmp_path)
    assert out.result.status == "failed" and "line" in out.result.reason


@pytest.mark.parametrize(
    "override,key",
    [
        ("pruning.min_angle_deg=200", "pruning.min_angle_deg"),
        ("features.3.traced=along", "features"),
        ("global_map.tip_radius=0", "global_map.tip_radius"),
    ],
)
def test_bad_value_is_exit_2_one_line_nothing_written(override, key, tmp_path, cli):
    out = tmp_path / "out"
    proc = cli(
        "run", str(SCEN / "feature_map.yaml"), "--quick", "--out", str(out), "--set", override
    )
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and key in lines[0] and "Traceback" not in proc.stderr
    assert not out.exists()


def test_pruning_settings_check_themselves():
    from planner.errors import InvalidParameter
    from planner.skeleton import SkeletonSettings

    assert SkeletonSettings.of(min_angle_deg=30.0).min_angle_deg == 30.0
    for bad, match in [
        ({"min_angle_deg": 180.0}, "min_angle_deg"),
        ({"max_edge_length": -1.0}, "max_edge_length"),
        ({"link_factor": 0.0}, "link_factor"),
        ({"branching": "yes"}, "branching"),
    ]:
        with pytest.raises(InvalidParameter, match=match):
            SkeletonSettings(**bad)
    with pytest.raises(InvalidParameter, match="unknown setting"):
        SkeletonSettings.of(smoothness=1)
