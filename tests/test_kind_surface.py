"""Tests of the ``surface`` scenario kind and its bundled scenarios."""

import json
from pathlib import Path

import numpy as np
import pytest

from planner.errors import ScenarioError
from planner.runner import execute
from planner.scenario import load_scenario

SCENARIOS = Path(__file__).parent.parent / "scenarios"


def run(path, tmp_path, quick=True, overrides=()):
    out = tmp_path / "run"
    execute(load_scenario(path, overrides), out_dir=out, quick=quick)
    result = json.loads((out / "result.json").read_text())
    return result, out


def test_bump_features_reproduces_fig_3_7(tmp_path):
    result, out = run(SCENARIOS / "bump_features.yaml", tmp_path)
    m = result["metrics"]
    assert result["status"] == "ok"
    assert m["slice_pattern"] == "-+-" and m["slice_macro_kinds"] == ["bump"]
    assert m["macro_kinds"] == ["bump"] and m["map_positive"] == 1 and m["map_negative"] == 1
    feats = json.loads((out / "features.json").read_text())["slice"]["features"]
    # analytic boundaries of eq. 3.17 (a = 15, r_f = 1): |u| = 0.0905 (+), 0.2987-0.6865 (-)
    assert feats[1]["u_end"] == pytest.approx(0.0905, abs=0.01)
    assert feats[2]["u_start"] == pytest.approx(0.2987, abs=0.01)
    assert feats[2]["u_end"] == pytest.approx(0.6865, abs=0.01)
    assert feats[1]["peak_curvature"] == pytest.approx(30.0, rel=1e-3)
    arrays = np.load(out / "trajectory.npz")
    assert arrays["map_k1"].shape == arrays["map_positive"].shape
    assert {p.name for p in (out / "plots").iterdir()} >= {
        "k1_slice.png",
        "feature_map.png",
        "surface.png",
        "offsets.png",
    }


def test_wire_on_plane_is_a_ridge(tmp_path):
    result, _ = run(SCENARIOS / "wire_on_plane_features.yaml", tmp_path)
    m = result["metrics"]
    assert m["slice_pattern"] == "-+-" and m["macro_kinds"] == ["ridge"]
    assert m["k1_max"] == pytest.approx(1 / 0.000325, rel=1e-6)
    assert m["graph"] is False


def test_ravine_multiscale(tmp_path):
    result, _ = run(SCENARIOS / "ravine_multiscale.yaml", tmp_path)
    m = result["metrics"]
    assert m["slice_pattern"] == "+-+" and m["macro_kinds"] == ["ravine"]
    assert 0 < m["unobservable_fraction_of_interior"] < 1 and m["interference_cells"] > 0
    assert 0 < m["interior_fraction"] < 1
    assert len(m["multiscale_regions"]) == 2


def test_height_field_file(tmp_path):
    x = np.linspace(-1, 1, 61)
    gx, gy = np.meshgrid(x, x, indexing="ij")
    np.savez(tmp_path / "hf.npz", x=x, y=x, z=1 / (1 + 15 * (gx**2 + gy**2)))
    (tmp_path / "hf.yaml").write_text(
        "kind: surface\ntip_radius: 1.0\nsurface: {type: height_field, file: hf.npz}\n"
        "grid_size: 61\n"
    )
    out = tmp_path / "out"
    execute(load_scenario(tmp_path / "hf.yaml"), out_dir=out, quick=True, base_dir=tmp_path)
    m = json.loads((out / "result.json").read_text())["metrics"]
    assert m["macro_kinds"] == ["bump"]
    (tmp_path / "missing.yaml").write_text(
        "kind: surface\ntip_radius: 1.0\nsurface: {type: height_field, file: nope.npz}\n"
    )
    with pytest.raises(ScenarioError, match="nope.npz"):
        execute(
            load_scenario(tmp_path / "missing.yaml"),
            out_dir=tmp_path / "o2",
            quick=True,
            base_dir=tmp_path,
        )
    assert not (tmp_path / "o2").exists()


def test_bad_input_is_reported(tmp_path):
    (tmp_path / "bad.yaml").write_text(
        "kind: surface\ntip_radius: -1\nsurface: {type: bump, a: -3, colour: red}\n"
    )
    with pytest.raises(ScenarioError) as info:
        load_scenario(tmp_path / "bad.yaml")
    text = str(info.value)
    assert "tip_radius" in text and "surface.a" in text and "colour" in text
    (tmp_path / "bad2.yaml").write_text("kind: surface\ntip_radius: 1\nsurface: {type: blob}\n")
    with pytest.raises(ScenarioError, match="surface"):
        load_scenario(tmp_path / "bad2.yaml")


@pytest.mark.parametrize(
    ("override", "where"),
    [
        ("multiscale_radii=[0.001]", "--set:1:0: multiscale_radii: expected radii >= tip_radius"),
        ("multiscale_radii=[2.0, -1]", "--set:1:0: multiscale_radii[1]:"),
        ("surface.a=-2", "--set:1:0: surface.a:"),
        ("grid_size=3", "--set:1:0: grid_size:"),
        ("surface.type=blob", "--set:1:0: surface.type: unknown type 'blob'"),
    ],
)
def test_bad_value_is_exit_2_one_line_nothing_written(cli, tmp_path, override, where):
    """Every value rule is a Config rule: `validate` catches it, `run` writes nothing."""
    scenario = str(SCENARIOS / "bump_features.yaml")
    proc = cli("validate", scenario, "--set", override)
    assert proc.returncode == 2 and proc.stderr.splitlines() == [proc.stderr.strip()]
    assert proc.stderr.startswith(where), proc.stderr
    out = tmp_path / "run"
    proc = cli("run", scenario, "--quick", "--no-plots", "--out", str(out), "--set", override)
    assert proc.returncode == 2 and proc.stderr.startswith(where), proc.stderr
    assert len(proc.stderr.splitlines()) == 1 and "Traceback" not in proc.stderr
    assert proc.stdout == "" and not out.exists()
