"""Tests of the ``trace`` scenario kind: its bundled scenarios' metrics and its bad input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

SCENARIOS = Path(__file__).parent.parent / "scenarios"


@pytest.mark.parametrize(
    ("override", "where"),
    [
        ("tip_radius=0", "--set:1:0: tip_radius:"),
        ("sampling.spacing=1.0", "--set:1:0: sampling: a spacing of 1 m gives fewer than 3"),
        ("sampling.samples=1", "--set:1:0: sampling.samples:"),
        ("sampling.spacing=1e-9", "--set:1:0: sampling: a spacing of 1e-09 m gives more than"),
        ("noise.normal_sigma_deg=120", "--set:1:0: noise.normal_sigma_deg:"),
        ("profile.height=0", "--set:1:0: profile: height must be non-zero"),
        ("profile.type=stepp", "--set:1:0: profile.type: unknown type 'stepp'"),
        ("smoothing.sigma_samples=-1", "--set:1:0: smoothing.sigma_samples:"),
    ],
)
def test_bad_value_is_exit_2_one_line_nothing_written(cli, tmp_path, override, where):
    """Every value rule is a Config rule: `validate` catches it, `run` writes nothing."""
    scenario = str(SCENARIOS / "step_trace.yaml")
    proc = cli("validate", scenario, "--set", override)
    assert proc.returncode == 2 and proc.stderr.startswith(where), proc.stderr
    assert len(proc.stderr.splitlines()) == 1
    out = tmp_path / "run"
    proc = cli("run", scenario, "--quick", "--no-plots", "--out", str(out), "--set", override)
    assert proc.returncode == 2 and proc.stderr.startswith(where), proc.stderr
    assert len(proc.stderr.splitlines()) == 1 and "Traceback" not in proc.stderr
    assert proc.stdout == "" and not out.exists()


@pytest.fixture(scope="module")
def wire_run():
    from planner.runner import run_config
    from planner.scenario import load_scenario

    result, _ = run_config(
        load_scenario(SCENARIOS / "wire_on_incline.yaml"), plots=True, quick=True
    )
    return result


def test_end_caps_are_reported_apart(wire_run):
    """Fig. 3.12: the estimate is 0.1 mm good away from the trace's ends; the smoothing's
    end effect (an arc of radius r_f about the last centre) is reported on its own."""
    m = wire_run.metrics
    assert m["end_cap_samples"] == 32  # int(4 sigma + 0.5) for sigma = 8 samples
    assert m["max_error_without_end_caps_m"] < 0.6e-3
    assert m["rms_error_without_end_caps_m"] < 0.1e-3
    assert m["max_error_end_caps_m"] > 5 * m["max_error_without_end_caps_m"]
    assert "max_error_m" not in m and "rms_error_m" not in m


def test_end_cap_selection():
    from planner.kinds.trace import end_cap_samples, in_end_caps

    assert end_cap_samples(0) == 0 and end_cap_samples(2.5) == 10
    src = np.array([0, 1, 2, -1, 5, 7, 8, 9])
    np.testing.assert_array_equal(
        in_end_caps(src, 10, 2), [True, True, False, False, False, False, True, True]
    )
    assert not in_end_caps(src, 10, 0).any()


def test_wire_figure_names_its_thesis_figure_and_zooms_on_detected_features(wire_run):
    m = wire_run.metrics
    signs = [f["sign"] for f in m["detected_features"]]
    assert 1 in signs and -1 in signs
    wire = np.array([0.0, 0.0])  # the wire touches the plane at x0 = 0
    assert all(
        np.linalg.norm(np.array(f["position"]) - wire) < 1e-3 for f in m["detected_features"]
    )
    fig = wire_run.figures["trace"]
    assert "Fig. 3.12" in fig.get_suptitle() and "3.9" not in fig.get_suptitle()
    main, zoom = fig.axes
    labels = main.get_legend_handles_labels()[1]
    assert {"detected +", "detected -"} <= set(labels)
    x0, x1 = zoom.get_xlim()
    assert 0 < x1 - x0 < 5  # [mm]: the 0.65 mm wire is visible
