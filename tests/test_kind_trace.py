"""Tests of the ``trace`` scenario kind: its bundled scenarios' metrics and its bad input."""

from __future__ import annotations

from pathlib import Path

import pytest

SCENARIOS = Path(__file__).parent.parent / "scenarios"


@pytest.mark.parametrize(
    ("override", "where"),
    [
        ("tip_radius=0", "--set:1:0: tip_radius:"),
        ("sampling.spacing=1.0", "--set:1:0: sampling: a spacing of 1 m gives fewer than 3"),
        ("sampling.samples=1", "--set:1:0: sampling.samples:"),
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
