"""The ``filter_study`` scenario kind (App. B.4)."""

from pathlib import Path

from planner.runner import execute
from planner.scenario import load_scenario

SCEN = Path(__file__).resolve().parents[1] / "scenarios"


def test_filter_study_quick(tmp_path):
    cfg = load_scenario(SCEN / "filter_study.yaml")
    out = execute(cfg, out_dir=tmp_path / "fs", quick=True)
    m = out.result.metrics
    assert out.result.status == "ok"
    assert m["n_true_features"] == 3
    assert m["best_filter"] in ("gaussian", "average", "wiener")
    assert m["gaussian_best_errors"] < m["none_best_errors"]
    assert m["gaussian_best_errors"] <= m["median_best_errors"]
    table = (tmp_path / "fs" / "filter_study.csv").read_text().splitlines()
    assert table[0] == "filter,window,sigma,fp,fn,errors"
    assert len(table) == m["n_settings"] + 1
    assert (tmp_path / "fs" / "plots" / "filter_errors.png").is_file()
