"""explore_surface (thesis ch. 4) on the SpatialWorld: bad input, closed-loop runs, the kind."""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import ROOT, run_cli

from planner.errors import InvalidParameter
from planner.exploration import explore_surface
from planner.exploration.surface.identify import END_FRACTION
from planner.exploration.surface.metrics import exploration_metrics
from planner.exploration.surface.plates import truth_features
from planner.exploration.surface.strategies import random_walk, raster
from planner.kinds._explore_report import spacing_warnings
from planner.sim.spatial.plate import Plate, PlateFeature

R = 0.008


def _bump_plate(h=2e-3, w=3e-3, pos=(0.0, 0.0)):
    return Plate((PlateFeature("bump", h, w, pos, 0.0),))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"region": ((-0.2, 0.2), (-0.2, 0.2))}, "region"),
        ({"strategy": "bug2", "goal": (0.2, 0.0)}, "goal"),
        ({"strategy": "bug2"}, "goal"),
        ({"normal_force": 50.0}, "normal_force"),
        ({"strategy": "spiral"}, "strategy"),
        ({"region": ((0.01, -0.01), (0.0, 0.01))}, "region"),
        ({"strategy": "random_walk", "identify": "raster"}, "identify"),
        ({"identify": "template"}, "identify"),
        ({"seed": -3}, "^seed: expected an integer >= 0"),
        ({"seed": 2.5}, "^seed: expected an integer >= 0"),
        ({"seed": float("nan")}, "^seed: expected an integer >= 0"),
        ({"line_spacin": 0.01}, "^line_spacin: not an option of explore_surface.*line_spacing"),
        ({"sensors": "noisy"}, "^sensors: expected None or a planner.sim.SensorSettings"),
        ({"sensors": 3}, "^sensors: expected None or a planner.sim.SensorSettings"),
        ({"region": ((-0.3, 0.3), (-0.01, 0.01))}, "^region: the point .* outside"),
    ],
)
def test_bad_input_is_invalid_parameter(kwargs, match):
    with pytest.raises(InvalidParameter, match=match):
        explore_surface(_bump_plate(), duration=0.1, **kwargs)


def test_features_closer_than_a_fingertip_diameter_are_warned():
    close = Plate((PlateFeature("bump", 2e-3, 3e-3, (-0.004, 0.0)), _bump_plate().features[0]))
    far = Plate((PlateFeature("bump", 2e-3, 3e-3, (-0.03, 0.0)), _bump_plate().features[0]))
    reg = np.array([[-0.04, 0.02], [-0.02, 0.02]])
    assert spacing_warnings(close, reg, R) != []
    assert spacing_warnings(far, reg, R) == []


def test_strategies_stay_in_the_region():
    reg = np.array([[-0.02, 0.02], [-0.01, 0.01]])
    segs = list(raster(reg, 0.006, 0.004))
    assert len(segs) == 3 and np.allclose(segs[1][0], [0.016, 0.0])
    walk = random_walk(reg, (0.0, 0.0), np.random.default_rng(0), 0.03, 0.004)
    for _ in range(50):
        a, b = next(walk)
        assert np.all(b >= reg[:, 0] + 0.004 - 1e-12) and np.all(b <= reg[:, 1] - 0.004 + 1e-12)


def test_short_closed_loop_search_keeps_contact_and_force():
    """The hybrid law presses with f_des along the OWTS normal while the raster slides."""
    res = explore_surface(
        Plate(()), region=((-0.01, 0.01), (-0.004, 0.004)), duration=0.8, speed=0.02, seed=3
    )
    assert res.status == "ok", res.reason
    searching = res.phase == res.phases.index("search")
    assert searching.sum() > 300
    fn = res.log.normal_force.sum(axis=1)[1 : len(res.t) + 1][searching]  # row 0: initial
    assert np.sqrt(np.mean((fn - 0.3) ** 2)) < 0.05
    assert np.all(np.abs(res.path[searching, 2] - R) < 2e-4)  # rides on the plane
    assert not res.features


def test_end_to_end_bump_identified_traced_closed():
    """Search meets the bump, the flow chart says bump, the loop closes on the outline."""
    plate = _bump_plate()
    region = np.array([[-0.016, 0.016], [-0.016, 0.016]])
    res = explore_surface(plate, region=region, duration=30.0, speed=0.03, line_spacing=0.05)
    assert res.status == "ok", res.reason
    assert len(res.features) == 1
    f = res.features[0]
    assert f.kind == "bump" and f.confidence > 0.5, f.evidence
    assert f.closed, f.evidence
    m = exploration_metrics(res, plate, region, R, 0.3)
    assert m["boundary_deviation_mean_mm"] < 0.5
    assert m["skeleton_hausdorff_mm"] <= 1.0  # issue 12's target; the bump's axis is a point
    truth = truth_features(plate, region, R)
    assert truth[0].closed


def test_sharply_bent_ridge_is_a_ridge_not_a_step():
    """scenarios/curved_ridge.yaml (Fig. 4.13): the 4th raster line meets the V at its apex,
    and the across crossing from there runs over both arms. Stopped where it was planned it
    ended on the far arm's flank, the ball still on the crest 1.7 mm up: a level change (a
    step). Each end is run out until it lies on a plane, so both end levels are the plate's
    (the fingertip centre r_f above it, within the flow chart's level threshold): no level
    change, and the traced outline closes around the V - a ridge."""
    path = ((-0.012, -0.010), (0.006, -0.004), (-0.008, 0.010))
    plate = Plate((PlateFeature("ridge", 0.002, 0.0018, path=path),))
    region = np.array([[-0.02, 0.02], [-0.02, 0.02]])
    res = explore_surface(plate, region=region, duration=80.0, speed=0.03, seed=0)
    assert res.status == "ok", res.reason
    (f,) = res.features
    assert f.closed and f.kind == "ridge", f.evidence
    (across,) = [e for e in f.evidence if e.startswith("across:")]
    assert "level change" not in across, f.evidence
    w = res.path[res.phase == res.phases.index("across"), 2]
    k = int(len(w) * END_FRACTION)
    for end in (w[:k], w[-k:]):
        assert abs(float(np.mean(end)) - R) < 5e-4  # identify's level_threshold


def test_raster_identification_in_closed_loop():
    """identify="raster": the whole raster first, the curvature regions pattern-matched,
    then the matched feature traced like the flow chart's."""
    plate = _bump_plate(pos=(0.0, 0.001))
    region = np.array([[-0.014, 0.014], [-0.012, 0.012]])
    res = explore_surface(
        plate, region=region, duration=40.0, speed=0.03, identify="raster", line_spacing=0.006
    )
    assert res.status == "ok", res.reason
    assert [f.kind for f in res.features] == ["bump"], [f.evidence for f in res.features]
    f = res.features[0]
    assert any("raster match" in e for e in f.evidence)
    assert f.closed and len(f.boundary) > 100
    search = np.flatnonzero(res.phase == res.phases.index("search"))
    trace = np.flatnonzero(res.phase == res.phases.index("trace"))
    assert search.max() < trace.min()  # the raster is scanned before anything is traced
    m = exploration_metrics(res, plate, region, R, 0.3)
    # no across crossing here: the plate level is read on the bump's long tail, so the outline
    # is traced a little higher than rise above the asymptotic plate; at its own level it is
    # followed to within a tenth of a millimetre
    assert m["boundary_deviation_own_level_mm"] < 0.15
    assert m["boundary_deviation_mean_mm"] < 1.0 and m["skeleton_hausdorff_mm"] <= 1.0


def test_explore_kind_bad_region_exits_2(tmp_path):
    src = (ROOT / "scenarios" / "ridge_plate.yaml").read_text()
    bad = tmp_path / "bad.yaml"
    bad.write_text(
        src.replace("region: [[-0.02, 0.02], [-0.02, 0.02]]", "region: [[-0.2, 0.2], [-0.2, 0.2]]")
    )
    proc = run_cli("validate", str(bad))
    assert proc.returncode == 2
    assert "region" in proc.stderr and "reach" in proc.stderr and "Traceback" not in proc.stderr
    ident = tmp_path / "ident.yaml"
    ident.write_text(src.replace("strategy: raster", "strategy: random_walk\nidentify: raster"))
    proc = run_cli("validate", str(ident))
    assert proc.returncode == 2 and "identify" in proc.stderr, proc.stderr
    force = tmp_path / "force.yaml"
    force.write_text(src.replace("normal_force: 0.3", "normal_force: 15.0"))
    proc = run_cli("run", str(force), "--quick", "--out", str(tmp_path / "o"))
    assert proc.returncode == 2 and "normal_force" in proc.stderr
    assert not (tmp_path / "o").exists()


def test_explore_kind_quick_run_writes_metrics(tmp_path):
    out = tmp_path / "run"
    proc = run_cli(
        "run", str(ROOT / "scenarios" / "bug_to_goal.yaml"), "--quick", "--out", str(out)
    )
    assert proc.returncode == 0, proc.stderr
    doc = json.loads((out / "result.json").read_text())
    assert doc["metrics"]["features_present"] == 1
    assert doc["metrics"]["normal_force_rms_error_N"] < 0.05
    assert (out / "plots" / "top_view.png").is_file()


def test_open_ridge_traced_on_both_sides_reaches_at_most_its_two_ends():
    """Both sides of an open ridge are traced and each side's outline leaves the region at the
    ridge's two ends: ``ends_reached`` counts the feature's ends (the most one side reached),
    not the sum over the sides (which was 3 here)."""
    plate = Plate((PlateFeature("ridge", 0.003, 0.0033, (0.001, 0.0015), np.radians(40)),))
    reg = ((-0.018, 0.018), (-0.018, 0.018))
    res = explore_surface(plate, region=reg, line_spacing=0.05, seed=5, duration=40, speed=0.03)
    (f,) = res.features
    assert f.kind == "ridge" and not f.closed
    ends_events = [e for e in res.events if e.kind == "end_reached"]
    assert len(ends_events) > 2  # the sides together left the region more than twice
    assert f.ends_reached == 2
