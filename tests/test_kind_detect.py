"""The ``detect`` scenario kind: bundled scenarios run (quick) with their key outputs."""

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import run_cli

from planner.errors import ScenarioError
from planner.geometry.shapes import ridge, step, wire_on_plane
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


STEP = {"profile": {"type": "step", "height": 0.002}}


def test_config_errors(tmp_path):
    base = {"name": "x", "kind": "detect", "tip_radius": 0.01}
    with pytest.raises(ScenarioError, match="exactly one"):
        scenario_from_dict(base)
    with pytest.raises(ScenarioError, match="exactly one"):
        scenario_from_dict({**base, "simulation": STEP, "data_file": "a.csv"})
    with pytest.raises(ScenarioError, match="multiscale_radii"):
        scenario_from_dict({**base, "simulation": STEP, "multiscale_radii": [0.005]})
    with pytest.raises(ScenarioError, match="simulation.profile: required"):
        scenario_from_dict({**base, "simulation": {}})
    with pytest.raises(ScenarioError, match="unknown key"):
        scenario_from_dict({**base, "simulation": {**STEP, "shape": "wire"}})
    with pytest.raises(ScenarioError, match="material_side"):
        scenario_from_dict({**base, "simulation": STEP, "material_side": "below"})
    with pytest.raises(ScenarioError, match="samples per tip radius"):
        scenario_from_dict({**base, "simulation": {**STEP, "spacing": 0.005}})
    with pytest.raises(ScenarioError, match="smoothing_scale"):
        scenario_from_dict({**base, "simulation": STEP, "smoothing_scale": 0.05})
    bad = tmp_path / "bad.csv"
    bad.write_text("t,cx\n1,2\n")
    cfg = scenario_from_dict({**base, "data_file": str(bad)})
    with pytest.raises(ScenarioError, match="cy: required column"):
        execute(cfg, out_dir=tmp_path / "run", quick=True)
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize(
    "override,key",
    [
        ("multiscale_radii=[0.001]", "multiscale_radii"),
        ("simulation.spacing=0.01", "simulation"),
        ("material_side=up", "material_side"),
        ("tip_radius=-0.01", "tip_radius"),
    ],
)
def test_bad_value_is_exit_2_one_line_nothing_written(override, key, tmp_path):
    out = tmp_path / "out"
    proc = run_cli(
        "run",
        str(SCEN / "step_detect_multiscale.yaml"),
        "--quick",
        "--out",
        str(out),
        "--set",
        override,
    )
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and key in lines[0] and "Traceback" not in proc.stderr
    assert not out.exists()


def test_sparse_data_file_is_bad_input(tmp_path):
    # a log sampled far too coarsely for the tip radius is bad input (exit 2), not a failed run
    t = np.arange(30) * 0.1
    rows = "\n".join(f"{ti},{ti * 0.1},0" for ti in t)
    (tmp_path / "coarse.csv").write_text("t,cx,cy\n" + rows + "\n")
    cfg = scenario_from_dict(
        {"name": "x", "kind": "detect", "tip_radius": 0.01, "data_file": "coarse.csv"}
    )
    with pytest.raises(ScenarioError, match="data_file: centers: expected at least 5 samples"):
        execute(cfg, out_dir=tmp_path / "run", quick=True, base_dir=tmp_path)
    assert not (tmp_path / "run").exists()


def test_reversed_csv_log_gives_the_same_features(tmp_path):
    # regression: a right-to-left recording of the bundled log is read alike (the material
    # side comes from the normals; centres-only reversal: tests/test_detection.py)
    lines = (SCEN / "data" / "wire_trace.csv").read_text().splitlines()
    rows = [ln.split(",") for ln in lines if ln[:1].isdigit()]
    t = [r[0] for r in rows]
    rev = [[t[i]] + r[1:] for i, r in enumerate(reversed(rows))]
    hdr = next(ln for ln in lines if ln.startswith("t"))
    (tmp_path / "rev.csv").write_text(hdr + "\n" + "\n".join(map(",".join, rev)) + "\n")
    base = {"name": "x", "kind": "detect", "tip_radius": 0.01, "algorithms": [2, 3]}
    fwd = execute(
        scenario_from_dict({**base, "data_file": str(SCEN / "data" / "wire_trace.csv")}),
        out_dir=tmp_path / "f",
        quick=True,
        plots=False,
    ).result.metrics
    back = execute(
        scenario_from_dict({**base, "data_file": str(tmp_path / "rev.csv")}),
        out_dir=tmp_path / "b",
        quick=True,
        plots=False,
    ).result.metrics
    assert back["alg3_macro"] == fwd["alg3_macro"] == ["bump"]
    assert back["alg3_signs"] == fwd["alg3_signs"][::-1]
    assert back["alg2_signs"] == fwd["alg2_signs"][::-1]


def test_multiscale_and_csv_figures(tmp_path):
    res, out = _run("step_detect_multiscale", tmp_path)
    assert (out / "plots" / "multiscale.png").is_file()
    assert res.metrics["multiscale_15mm_macro"] == ["step"]


# --- simulation.profile: any open profile of the catalogue, truth from the profile ----------

THESIS = {"spacing": 2e-5, "center_sigma": 1e-4, "contact_sigma": 2.5e-4, "normal_sigma_deg": 1.0}


@pytest.mark.parametrize(
    "profile,exact,macro",
    [
        (
            {"type": "wire", "diameter": 0.65e-3, "angle_deg": 45},
            wire_on_plane(0.65e-3, np.pi / 4),
            "bump",
        ),
        ({"type": "step", "height": 2e-3}, step(2e-3), "step"),
        ({"type": "ridge", "width": 4e-3, "height": 2e-3}, ridge(4e-3, 2e-3), "ridge"),
    ],
    ids=["wire", "step", "ridge"],
)
def test_profile_simulation_alg3_scores_f1_one(profile, exact, macro, tmp_path):
    cfg = scenario_from_dict(
        {
            "name": "p",
            "kind": "detect",
            "seed": 1,
            "tip_radius": 0.01,
            "algorithms": [3],
            "simulation": {"profile": profile, **THESIS},
        }
    )
    out = execute(cfg, out_dir=tmp_path / "run", quick=True, plots=False)
    m = out.result.metrics
    truth = exact.curvature_features(0.01)
    assert m["truth_signs"] == "".join("+" if f.sign > 0 else "-" for f in truth)
    with np.load(tmp_path / "run" / "trajectory.npz") as z:
        assert np.allclose(z["truth_positions"], [f.position for f in truth], atol=1e-12)
    assert m["alg3_signs"] == m["truth_signs"] and m["alg3_macro"] == [macro]
    assert m["alg3_f1"] == 1.0 and m["alg3_localization_m"] < 0.5e-3


def test_profile_detect_bundled(tmp_path):
    res, out = _run("profile_detect", tmp_path)
    m = res.metrics
    assert m["truth_signs"] == "-++-" and m["alg3_signs"] == "-++-"
    assert m["alg3_f1"] == 1.0 and m["alg3_macro"] == ["ridge"]
    assert m["best_algorithm"] == 3 and "-" not in m["alg4_signs"]  # alg. 4: no concave
    assert (out / "plots" / "trace.png").is_file()


def test_profile_config_errors():
    base = {"name": "x", "kind": "detect", "tip_radius": 0.01}
    with pytest.raises(ScenarioError, match=r"simulation.profile: .*closed profile \('circle'\)"):
        scenario_from_dict({**base, "simulation": {"profile": {"type": "circle", "radius": 0.02}}})
    with pytest.raises(ScenarioError, match="simulation.angle_deg: unknown key"):
        scenario_from_dict({**base, "simulation": {"profile": {"type": "plane"}, "angle_deg": 30}})
    with pytest.raises(ScenarioError, match="simulation.profile: .*corner radii"):
        spec = {"type": "ridge", "width": 4e-3, "height": 2e-3, "corner_radius": 5e-3}
        scenario_from_dict({**base, "simulation": {"profile": spec}})
    # the noise and sampling keys go with either surface
    cfg = scenario_from_dict({**base, "simulation": {"profile": {"type": "plane"}, **THESIS}})
    assert cfg.simulation.profile.type == "plane" and cfg.simulation.spacing == 2e-5
