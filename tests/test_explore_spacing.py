"""Features closer than a fingertip diameter: a ``features_too_close`` event (§4.2.1) from
``explore_surface`` itself, carried once by the ``explore`` kind's run."""

from __future__ import annotations

import json

from conftest import run_cli

from planner.exploration.surface import explore_surface
from planner.exploration.surface.spacing import spacing_warnings
from planner.kinds import _explore_report
from planner.sim.spatial.plate import Plate, PlateFeature

REGION = ((-0.016, 0.016), (-0.01, 0.01))  # [m]
CLOSE = Plate(
    (
        PlateFeature("bump", 0.002, 0.003, (-0.003, 0.0)),
        PlateFeature("bump", 0.002, 0.003, (0.004, 0.0)),
    )
)
FAR = Plate(
    (
        PlateFeature("bump", 0.002, 0.003, (-0.03, 0.0)),
        PlateFeature("bump", 0.002, 0.003, (0.03, 0.0)),
    )
)

SCENARIO = """\
name: close_bumps
kind: explore
seed: 0
plate:
  features:
    - {kind: bump, height: 0.002, width: 0.003, position: [-0.003, 0.0]}
    - {kind: bump, height: 0.002, width: 0.003, position: [0.004, 0.0]}
region: [[-0.016, 0.016], [-0.01, 0.01]]
strategy: raster
duration: 0.3
quick_duration: 0.2
"""


def _too_close(events) -> list:
    return [e for e in events if e.kind == "features_too_close"]


def test_library_result_carries_features_too_close_at_t0():
    res = explore_surface(CLOSE, region=REGION, duration=0.3)
    assert res.status == "ok", res.reason
    (e,) = _too_close(res.events)
    assert e.t == 0.0
    assert e.message == spacing_warnings(CLOSE, REGION, 0.008)[0]
    assert "features 0 (bump) and 1 (bump)" in e.message
    assert res.events[0] is e  # sorted by time: first


def test_well_separated_features_give_no_event():
    region = ((-0.04, 0.04), (-0.01, 0.01))
    assert spacing_warnings(FAR, region, 0.008) == []
    res = explore_surface(FAR, region=region, duration=0.05)
    assert _too_close(res.events) == []


def test_kind_report_re_exports_spacing_warnings():
    assert _explore_report.spacing_warnings is spacing_warnings


def test_cli_run_reports_features_too_close_exactly_once(tmp_path):
    scenario = tmp_path / "close_bumps.yaml"
    scenario.write_text(SCENARIO)
    out = tmp_path / "run"
    proc = run_cli("run", str(scenario), "--quick", "--no-plots", "-v", "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    doc = json.loads((out / "result.json").read_text())
    close = [e for e in doc["events"] if e["kind"] == "features_too_close"]
    assert len(close) == 1 and close[0]["t"] == 0.0
    assert proc.stderr.count("warning: features 0 (bump) and 1 (bump)") == 1, proc.stderr


def test_gap_is_measured_between_footprints():
    """Bumps 12 mm apart (centres) leave a small gap between their quarter-height footprints;
    7 mm apart their footprints meet, which the message calls an overlap (not "0.0 mm")."""
    near = Plate(
        (
            PlateFeature("bump", 0.002, 0.003, (-0.006, 0.0)),
            PlateFeature("bump", 0.002, 0.003, (0.006, 0.0)),
        )
    )
    (gap,) = spacing_warnings(near, REGION, 0.0075)
    mm = float(gap.split(" are ")[1].split(" mm")[0])
    assert 0.0 < mm < 12.0
    (touch,) = spacing_warnings(CLOSE, REGION, 0.0075)
    assert "overlap" in touch and "mm apart" not in touch
