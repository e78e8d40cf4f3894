"""The ``detect`` scenario kind: bundled scenarios run (quick) with their key outputs."""

import json
from pathlib import Path

import numpy as np
import pytest

from planner.errors import ScenarioError
from planner.runner import execute
from planner.scenario import load_scenario, scenario_from_dict

SCEN = Path(__file__).resolve().parents[1] / "scenarios"


def _run(name, tmp_path, **kw):
    cfg = load_scenario(SCEN / f"{name}.yaml")
    out = execute(cfg, out_dir=tmp_path / name, quick=True, base_dir=SCEN, **kw)
    return out.result, tmp_path / name


def test_wire_detect_alg3(tmp_path):
    res, out = _run("wire_detect_alg3", tmp_path)
    m = res.metrics
    assert res.status == "ok"
    assert m["alg3_signs"] == "-+-" and m["alg3_macro"] == ["bump"]
    assert m["alg3_f1"] == 1.0 and m["alg3_localization_m"] < 0.4e-3
    assert (out / "plots" / "trace.png").is_file() and (out / "plots" / "curvature.png").is_file()
    rep = json.loads((out / "features.json").read_text())
    assert [f["sign"] for f in rep["alg3"]["features"]] == [-1, 1, -1]
    with np.load(out / "trajectory.npz") as z:
        assert z["alg3_features"].shape == (3, 5)


def test_wire_detect_compare_reproduces_section_3_4_2(tmp_path):
    res, _ = _run("wire_detect_compare", tmp_path, plots=False)
    m = res.metrics
    assert m["best_algorithm"] == 3
    assert "-" not in m["alg1_signs"] and "-" not in m["alg4_signs"]
    assert "+" not in m["alg2_signs"] and "-" in m["alg2_signs"]
    assert m["alg3_f1"] > max(m["alg1_f1"], m["alg2_f1"], m["alg4_f1"])


def test_step_multiscale(tmp_path):
    res, _ = _run("step_detect_multiscale", tmp_path, plots=False)
    assert res.metrics["alg3_macro"] == ["step"]
    assert res.metrics["multiscale_15mm_signs"] == "-+"
    assert res.metrics["multiscale_25mm_signs"] == "-+"


def test_csv_data_file(tmp_path):
    res, _ = _run("csv_wire_detect", tmp_path, plots=False)
    assert res.metrics["alg3_signs"] == "-+-"
    assert res.metrics["n_samples"] > 500
    assert "alg3_f1" not in res.metrics  # no ground truth for a user's log
    # App. B.1 on the longest feature-free stretch: the log was made with 0.1 mm noise
    for axis in "xy":
        assert res.metrics[f"noise_{axis}_sigma_m"] == pytest.approx(1e-4, rel=0.3)
        assert res.metrics[f"noise_{axis}_chi2"] >= 0
        assert isinstance(res.metrics[f"noise_{axis}_normal"], bool)


def test_config_errors(tmp_path):
    base = {"name": "x", "kind": "detect", "tip_radius": 0.01}
    with pytest.raises(ScenarioError, match="exactly one"):
        scenario_from_dict(base)
    with pytest.raises(ScenarioError, match="exactly one"):
        scenario_from_dict({**base, "simulation": {}, "data_file": "a.csv"})
    with pytest.raises(ScenarioError, match="multiscale_radii"):
        scenario_from_dict({**base, "simulation": {}, "multiscale_radii": [0.005]})
    with pytest.raises(ScenarioError, match="unknown key"):
        scenario_from_dict({**base, "simulation": {"shape": "wire", "diameter": 1}})
    bad = tmp_path / "bad.csv"
    bad.write_text("t,cx\n1,2\n")
    cfg = scenario_from_dict({**base, "data_file": str(bad)})
    with pytest.raises(ScenarioError, match="cy: required column"):
        execute(cfg, out_dir=tmp_path / "run", quick=True)
    assert not (tmp_path / "run").exists()
