"""The ``contact_sim`` scenario kind through the CLI: runs, metrics, bad input."""

from __future__ import annotations

import json
import math

import pytest

from tests.conftest import ROOT


def test_incline_box_runs_static(cli, tmp_path):
    out = tmp_path / "run"
    res = cli("run", str(ROOT / "scenarios/incline_box.yaml"), "--quick", "--out", str(out))
    assert res.returncode == 0, res.stderr
    result = json.loads((out / "result.json").read_text())
    assert result["status"] == "ok"
    m = result["metrics"]
    assert max(abs(v) for v in m["box.displacement_m"]) <= 1e-9
    assert m["max_penetration_m"] <= 1e-6
    assert (out / "plots" / "trajectories.png").exists()
    assert (out / "trajectory.npz").exists()


def test_sliding_box_override_matches_closed_form(cli, tmp_path):
    out = tmp_path / "run"
    res = cli(
        "run",
        str(ROOT / "scenarios/incline_box.yaml"),
        "--quick",
        "--no-plots",
        "--set",
        "fixed.0.friction=0.1",
        "--set",
        "bodies.0.friction=0.1",
        "--out",
        str(out),
    )
    assert res.returncode == 0, res.stderr
    m = json.loads((out / "result.json").read_text())["metrics"]
    a = math.hypot(*m["box.mean_acceleration_m_s2"])
    g, al = 9.81, math.radians(20)
    assert a == pytest.approx(g * (math.sin(al) - 0.1 * math.cos(al)), rel=5e-3)


BAD = """name: bad
kind: contact_sim
dt: 0.0
duration: 1.0
fixed:
  - name: floor
    profile: {type: plane, length: 1.0}
    friction: -0.1
bodies:
  - name: b
    profile: {type: circle, radius: 0.02}
    position: [0, 0.05]
    mass: -1
"""

OVERLAP = """name: overlap
kind: contact_sim
duration: 1.0
fixed:
  - name: floor
    profile: {type: plane, length: 1.0}
bodies:
  - name: b
    profile: {type: circle, radius: 0.02}
    position: [0, 0.01]
    mass: 1
"""


def test_bad_input_exits_2_with_key_paths(cli, tmp_path):
    f = tmp_path / "bad.yaml"
    f.write_text(BAD)
    res = cli("run", str(f), "--out", str(tmp_path / "o"))
    assert res.returncode == 2
    for key in ("dt", "fixed[0].friction", "bodies[0].mass"):
        assert f": {key}:" in res.stderr
    assert not (tmp_path / "o").exists()
    f.write_text(OVERLAP)
    res = cli("validate", str(f))
    assert res.stderr.strip() == (
        f"{f}:8: bodies[0]: 1 pair starts in penetration, 'floor' and 'b' overlapping by "
        "0.01 m; move the bodies apart"
    )
    f.write_text(OVERLAP.replace("position: [0, 0.01]", "position: [0, 0.03]"))
    assert cli("validate", str(f)).returncode == 0


def test_scene_params_are_checked(cli, tmp_path):
    f = tmp_path / "s.yaml"
    f.write_text("name: s\nkind: contact_sim\nscene:\n  preset: pinch\n  params: {squeez: 1}\n")
    res = cli("validate", str(f))
    assert res.returncode == 2 and "squeez" in res.stderr


def test_every_bad_scene_param_is_reported_at_its_key(cli, tmp_path):
    f = tmp_path / "s.yaml"
    f.write_text(
        "name: s\nkind: contact_sim\nscene:\n  preset: pinch\n  params:\n"
        "    squeeze: -1.0\n    mass: 0.1\n    radius: .nan\n    friction: 0\n"
    )
    res = cli("validate", str(f))
    assert res.returncode == 2 and "Traceback" not in res.stderr
    # -1 said ">= 0" while 0 was then refused with "must be > 0" (until 2026-11-25)
    assert res.stderr.splitlines() == [
        f"{f}:6: scene.params.squeeze: Input should be greater than 0",
        f"{f}:8: scene.params.radius: Input should be a finite number",
    ]
    f.write_text("name: s\nkind: contact_sim\nscene:\n  preset: pinch\n  params: {mass: 0}\n")
    res = cli("validate", str(f))
    assert res.stderr.strip() == f"{f}:5: scene.params.mass: Input should be greater than 0"
    f.write_text("name: s\nkind: contact_sim\nscene:\n  preset: pinch\n  params: {friction: -1}\n")
    res = cli("validate", str(f))
    assert res.stderr.strip() == (
        f"{f}:5: scene.params.friction: Input should be greater than or equal to 0"
    )
    res = cli("validate", str(f), "--set", "scene.params.mass=0.1", "--set", "scene.params.x=1")
    assert res.returncode == 2
    assert "scene.params: unknown parameter x of the pinch scene; valid: friction," in res.stderr


def test_a_short_tuple_is_too_few_items_not_a_missing_key(cli, tmp_path):
    f = tmp_path / "s.yaml"
    f.write_text(OVERLAP.replace("position: [0, 0.01]", "position: [0.03]") + "gravity: [0.0]\n")
    res = cli("validate", str(f))
    assert res.returncode == 2
    assert res.stderr.splitlines() == [
        f"{f}:10: bodies[0].position: expected 2 items, got 1",
        f"{f}:12: gravity: expected 2 items, got 1",
    ]
    f.write_text(OVERLAP.replace("position: [0, 0.01]", "position: [0, 0.03]"))
    res = cli("run", str(f), "--out", str(tmp_path / "o"), "--set", "bodies.0.velocity=[0.5]")
    assert res.returncode == 2 and not (tmp_path / "o").exists()
    assert res.stderr.strip().endswith("bodies[0].velocity: expected 3 items, got 1")


def test_penetration_counts_pairs_and_scene_rules_name_the_scene(cli, tmp_path):
    f = tmp_path / "s.yaml"
    box = "  - name: b\n    profile: {type: rounded_rectangle, width: 0.02, height: 0.01}\n"
    f.write_text(
        OVERLAP.replace("  - name: b\n    profile: {type: circle, radius: 0.02}\n", box).replace(
            "position: [0, 0.01]", "position: [0, 0.004]"
        )
    )
    res = cli("validate", str(f))
    # a box sunk flat into the floor touches it at two points: still one pair
    assert res.returncode == 2 and "1 pair starts in penetration, 'floor' and 'b'" in res.stderr
    f.write_text(OVERLAP.replace("position: [0, 0.01]", "position: [0, 0.03]") + SCENE)
    res = cli("validate", str(f))
    assert res.stderr.strip() == f"{f}:12: scene: give either a scene or fixed/bodies, not both"


SCENE = "scene:\n  preset: pinch\n"


def test_scene_presets_apply_the_given_gravity_and_record_it(cli, tmp_path):
    """``gravity: [0, -1]`` with the pinch preset ran under -9.81 (each fingertip carried
    0.515 N of friction, about m g / 2 with g = 9.81) while scenario.yaml recorded [0, -1]."""
    import numpy as np
    import yaml

    f = tmp_path / "pinch.yaml"
    f.write_text((ROOT / "scenarios/pinch_hold.yaml").read_text() + "gravity: [0.0, -1.0]\n")
    out = tmp_path / "run"
    res = cli("run", str(f), "--no-plots", "--out", str(out))
    assert res.returncode == 0, res.stderr
    assert yaml.safe_load((out / "scenario.yaml").read_text())["gravity"] == [0.0, -1.0]
    ft = np.load(out / "trajectory.npz")["tangential_force"][-1]
    # the two fingertips carry the disc's weight m g = 0.1 N (0.98 N under 9.81)
    assert np.abs(ft).sum() == pytest.approx(0.1, rel=0.3)


def test_the_spatial_scene_takes_a_3_vector_and_refuses_a_2_vector(cli, tmp_path):
    from planner.kinds.contact_sim import _build
    from planner.scenario import load_scenario

    f = tmp_path / "ridge.yaml"
    ridge = (ROOT / "scenarios/ridge_slide_3gm.yaml").read_text()
    f.write_text(ridge + "gravity: [0.0, -9.81]\n")
    res = cli("validate", str(f))
    assert res.returncode == 2
    line = len(ridge.splitlines()) + 1
    assert res.stderr.strip() == (
        f"{f}:{line}: gravity: expected 3 items, got 2: "
        "the ridge_3gm scene is spatial, (gx, gy, gz) [m/s^2]"
    )
    f.write_text(ridge + "gravity: [0.0, 0.0, -4.0]\n")
    world = _build(load_scenario(f), quick=True)[0]
    assert world.gravity.tolist() == [0.0, 0.0, -4.0]
    f.write_text(ridge)  # the default is recorded as the spatial gravity the run uses
    assert load_scenario(f).gravity == (0.0, 0.0, -9.81)


def test_a_planar_world_refuses_a_3_vector_gravity(cli, tmp_path):
    f = tmp_path / "s.yaml"
    f.write_text(
        OVERLAP.replace("position: [0, 0.01]", "position: [0, 0.03]") + "gravity: [0, 0, -9.81]\n"
    )
    res = cli("validate", str(f))
    assert res.returncode == 2
    assert res.stderr.strip() == f"{f}:12: gravity: expected 2 items, got 3"


BODIES = """name: bodies
kind: contact_sim
duration: 1.0
fixed:
  - name: floor
    profile: {type: plane, length: 1.0}
  - name: floor
    profile: {type: plane, length: 1.0}
bodies:
  - name: floor
    profile: {type: circle, radius: 0.01}
    position: [0, 0.05]
    mass: 1
  - name: lid
    profile: {type: plane, length: 0.02}
    position: [0.5, 0.05]
    mass: 1
"""


def test_body_problems_are_reported_at_the_body_s_key(cli, tmp_path):
    """A duplicate name, an open profile and a start in penetration were all reported at
    ``bodies`` (the line of the list), not at the body's own key."""
    f = tmp_path / "s.yaml"
    f.write_text(BODIES)
    res = cli("validate", str(f))
    assert res.returncode == 2
    assert res.stderr.splitlines() == [
        f"{f}:7: fixed[1].name: 'floor' is already the name of fixed[0]"
    ]
    f.write_text(
        BODIES.replace("  - name: floor\n    profile: {type: plane, length: 1.0}\n", "", 1)
    )
    res = cli("validate", str(f))
    assert res.stderr.splitlines() == [
        f"{f}:8: bodies[0].name: 'floor' is already the name of fixed[0]",
        f"{f}:13: bodies[1].profile: a free body needs a closed profile, got an open 'plane'",
    ]
    two = OVERLAP.replace("position: [0, 0.01]", "position: [0, 0.03]") + (
        "  - name: c\n    profile: {type: circle, radius: 0.02}\n"
        "    position: [0.01, 0.03]\n    mass: 1\n"
    )
    f.write_text(two)
    res = cli("validate", str(f))
    assert res.stderr.strip() == (
        f"{f}:12: bodies[1]: 1 pair starts in penetration, 'b' and 'c' overlapping by "
        "0.03 m; move the bodies apart"
    )


def test_metrics_keep_metres_and_radians_apart(cli, tmp_path):
    """``disc.displacement_m`` had the turned angle [rad] as its third item (55.98 for the
    rolling disc); rolling without slip, the arclength equals r times the angle turned."""
    out = tmp_path / "run"
    res = cli(
        "run", str(ROOT / "scenarios/rolling_disc.yaml"), "--quick", "--no-plots", "--out", str(out)
    )
    assert res.returncode == 0, res.stderr
    m = json.loads((out / "result.json").read_text())["metrics"]
    assert len(m["disc.displacement_m"]) == 2 and len(m["disc.final_velocity_m_s"]) == 2
    s = math.hypot(*m["disc.displacement_m"])
    assert s > 0.05 and m["disc.rotation_rad"] * 0.02 == pytest.approx(s, rel=1e-6)
    v = math.hypot(*m["disc.final_velocity_m_s"])
    assert m["disc.final_angular_velocity_rad_s"] * 0.02 == pytest.approx(v, rel=1e-6)
    a = math.hypot(*m["disc.mean_acceleration_m_s2"])
    assert a == pytest.approx(2 / 3 * 9.81 * math.sin(math.radians(20)), rel=1e-3)
    assert m["disc.mean_angular_acceleration_rad_s2"] * 0.02 == pytest.approx(a, rel=1e-6)
    units = ("_m", "_rad", "_s", "_m_s", "_rad_s", "_m_s2", "_rad_s2", "_n")
    body_keys = [k for k in m if k.startswith("disc.")]
    assert len(body_keys) == 6 and all(k.endswith(units) for k in body_keys)


def test_spatial_rotation_is_the_angle_between_the_quaternions():
    import numpy as np

    from planner.kinds.contact_sim import _rotation_rad

    a = 0.3
    p0 = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
    p1 = np.array([1.0, 2.0, 3.0, math.cos(a / 2), 0.0, 0.0, math.sin(a / 2)])
    assert _rotation_rad(p0, p1) == pytest.approx(a, rel=1e-12)
    assert _rotation_rad(p0, np.concatenate([p1[:3], -p1[3:]])) == pytest.approx(a, rel=1e-12)


def test_the_angle_key_says_degrees_and_the_old_pose_key_keeps_its_meaning(cli, tmp_path):
    """``pose: [x, y, angle]`` took degrees without saying so (DESIGN.md: a key that takes
    degrees says so in its name); ``position`` [m] and ``angle_deg`` replace it, and older
    files that give ``pose`` keep their placements (degrees) - beside a new key it is
    refused."""
    from planner.kinds.contact_sim import _build
    from planner.scenario import load_scenario

    world = _build(load_scenario(ROOT / "scenarios/incline_box.yaml"), quick=True)[0]
    assert world.pose("box")[2] == pytest.approx(math.radians(20.0), rel=1e-15)
    old = tmp_path / "old.yaml"
    old.write_text(OVERLAP.replace("position: [0, 0.01]", "pose: [0, 0.03, 90]"))
    now = tmp_path / "now.yaml"
    now.write_text(OVERLAP.replace("position: [0, 0.01]", "position: [0, 0.03]\n    angle_deg: 90"))
    a, b = (_build(load_scenario(f), quick=True)[0] for f in (old, now))
    assert list(a.pose("b")) == list(b.pose("b"))
    assert a.pose("b")[2] == pytest.approx(math.pi / 2, rel=1e-15)
    both = tmp_path / "both.yaml"
    both.write_text(OVERLAP.replace("position: [0, 0.01]", "pose: [0, 0.03, 90]\n    angle_deg: 9"))
    res = cli("validate", str(both))
    assert res.returncode == 2
    assert (
        res.stderr.strip() == f"{both}:10: bodies[0].pose: give either pose or angle_deg, not both"
    )
    bad = tmp_path / "bad.yaml"
    bad.write_text(OVERLAP.replace("position: [0, 0.01]", "pose: [0, 0.03]"))
    res = cli("validate", str(bad))
    assert (
        res.returncode == 2
        and f"{bad}:10: bodies[0].pose: expected [x, y, angle in degrees]" in res.stderr
    )
