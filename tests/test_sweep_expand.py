"""Sweep files and their expansion: grid x zip x random x seeds, validation of the file and of
every combination (FILE:LINE: key.path: message), stable run ids."""

from __future__ import annotations

import itertools
import math
import subprocess
import sys
import textwrap

import pytest
from conftest import ROOT

from planner.errors import ScenarioError
from planner.sweep import expand, load_sweep, plan, run_id, sweep_from_dict
from planner.sweep.spec import Distribution

DETECT = {
    "kind": "detect",
    "tip_radius": 0.01,
    "algorithms": [3],
    "simulation": {
        "profile": {"type": "wire", "diameter": 0.00065, "length": 0.005},
        "spacing": 1.0e-4,
    },
}


def sweep(**keys):
    return sweep_from_dict({"name": "t", "base": DETECT, **keys})


def write(tmp_path, text: str, name: str = "s.yaml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def issues(exc_info) -> list[str]:
    return [str(i) for i in exc_info.value.issues]


def test_grid_random_seeds_is_the_product():
    s = sweep(
        grid={"tip_radius": [0.005, 0.01, 0.02], "simulation.profile.angle_deg": [0.0, 45.0]},
        random={
            "samples": 4,
            "seed": 3,
            "params": {
                "simulation.center_sigma": {"loguniform": [1e-5, 1e-3]},
                "simulation.speed": {"uniform": [0.01, 0.05]},
                "algorithms": {"choice": [[2], [3]]},
            },
        },
        seeds=2,
    )
    runs = plan(s)
    assert len(runs) == 3 * 2 * 4 * 2
    combos = {(r.params["tip_radius"], r.params["simulation.profile.angle_deg"]) for r in runs}
    assert combos == set(itertools.product([0.005, 0.01, 0.02], [0.0, 45.0]))
    assert {r.seed for r in runs} == {0, 1}
    for r in runs:  # the values reach the validated scenario through the --set key paths
        sim = r.config.simulation
        assert sim.center_sigma == r.params["simulation.center_sigma"]
        assert 1e-5 <= sim.center_sigma < 1e-3 and 0.01 <= sim.speed < 0.05
        assert list(r.config.algorithms) in ([2], [3])
        assert r.config.tip_radius == r.params["tip_radius"] and r.config.seed == r.seed
    # the same random points are crossed with every grid cell and seed
    points = {(r.params["simulation.center_sigma"], r.params["simulation.speed"]) for r in runs}
    assert len(points) == 4
    assert [r.run_id for r in plan(s)] == [r.run_id for r in runs]  # reproducible


def test_random_sampler_seed_changes_points():
    def pts(seed):
        s = sweep(
            random={
                "samples": 3,
                "seed": seed,
                "params": {"tip_radius": {"uniform": [0.005, 0.02]}},
            }
        )
        return [r.params["tip_radius"] for r in plan(s)]

    assert pts(0) == pts(0) and pts(0) != pts(1)


def test_loguniform_is_uniform_in_log():
    import numpy as np

    d = Distribution(loguniform=(1e-4, 1e-2))
    x = np.log10(d.sample(np.random.default_rng(0), 4000))
    assert x.min() >= -4 and x.max() < -2
    assert abs(np.mean(x) + 3) < 0.05 and abs(np.mean(x < -3) - 0.5) < 0.03


def test_zip_varies_together_and_crosses_the_grid():
    s = sweep(
        grid={"tip_radius": [0.005, 0.01]},
        zip={
            "simulation.center_sigma": [1e-4, 2e-4, 4e-4],
            "simulation.contact_sigma": [2e-4, 4e-4, 8e-4],
        },
    )
    runs = plan(s)
    assert len(runs) == 6
    for r in runs:
        sim = r.config.simulation
        assert math.isclose(sim.contact_sigma, 2 * sim.center_sigma)
    assert [r.seed for r in runs] == [0] * 6  # no seeds: the base scenario's seed


def test_seed_list_and_expand_returns_scenarios():
    scen = expand(sweep(seeds=[4, 9]))
    assert [c.seed for c in scen] == [4, 9] and all(c.kind == "detect" for c in scen)


def test_run_ids_are_stable_hashes_of_the_resolved_scenario():
    a = plan(sweep(grid={"tip_radius": [0.01]}))[0]
    # the same resolved scenario written another way (defaults spelled out, other key order,
    # another name and description) has the same id
    other = dict(reversed(list(DETECT.items())), tolerance=None, name="x", description="y")
    b = plan(sweep_from_dict({"name": "u", "base": other}))[0]
    assert a.run_id == b.run_id == run_id(a.config)
    assert len(a.run_id) == 12 and int(a.run_id, 16) >= 0
    assert plan(sweep(seeds=[1]))[0].run_id != a.run_id  # the seed is part of it
    assert run_id(a.config, quick=True) != a.run_id  # so is --quick
    # and it does not depend on the process (no hash randomisation, no memory addresses)
    code = (
        "from planner.sweep import sweep_from_dict, plan; import json, sys;"
        "print(plan(sweep_from_dict(json.loads(sys.argv[1])))[0].run_id)"
    )
    import json

    out = subprocess.run(
        [sys.executable, "-c", code, json.dumps({"name": "t", "base": DETECT})],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    )
    assert out.stdout.strip() == a.run_id


def test_duplicate_combinations_are_merged():
    runs = plan(sweep(grid={"tip_radius": [0.01, 0.01, 0.02]}))
    assert len(runs) == 2 and len({r.run_id for r in runs}) == 2


def test_every_combination_is_validated_before_running(tmp_path):
    path = write(
        tmp_path,
        """\
        base:
          kind: detect
          tip_radius: 0.01
          simulation: {profile: {type: wire, diameter: 0.00065}}
        grid:
          tip_radius: [0.005, -0.01, 2.0]
          simulation.profile.diameter: [0.00065]
        seeds: 2
        """,
    )
    with pytest.raises(ScenarioError) as exc:
        plan(load_sweep(path))
    lines = issues(exc)
    # two bad values x two seeds, each named, at the line of the grid key
    assert len(lines) == 4, lines
    assert all(line.startswith(f"{path}:6: grid.tip_radius: combination (") for line in lines)
    named = "tip_radius=-0.01, simulation.profile.diameter=0.00065, seed=1"
    assert any(named in line for line in lines)
    assert any("tip_radius=2.0" in line and "less than or equal to 1" in line for line in lines)


def test_a_bad_combination_in_the_base_file_is_located_there(tmp_path):
    base = write(
        tmp_path,
        """\
        kind: detect
        tip_radius: 0.002
        multiscale_radii: [0.004]
        simulation:
          profile: {type: wire, diameter: 0.00065}
          spacing: 1.0e-4
        """,
        "base.yaml",
    )
    path = write(tmp_path, "base: base.yaml\ngrid:\n  tip_radius: [0.002, 0.01]\n")
    assert load_sweep(path).base_dir == tmp_path
    with pytest.raises(ScenarioError) as exc:
        plan(load_sweep(path))
    lines = issues(exc)
    assert len(lines) == 1, lines
    (line,) = lines
    assert line.startswith(f"{base}:")  # a rule of the base file, reported in the base file
    assert "multiscale_radii [0.004] must each be in [tip_radius, 1]" in line
    assert "(combination tip_radius=0.01)" in line


@pytest.mark.parametrize(
    "text, where, message",
    [
        ("base: {kind: detect}\ngrdi: {a: [1]}\n", ":2: grdi:", "unknown key"),
        ("grid: {tip_radius: [1]}\n", ":1: base:", "required key is missing"),
        ("base: {kind: detect}\ngrid: {tip_radius: []}\n", ":2: grid:", "have no values"),
        ("base: {kind: detect}\ngrid: {seed: [1, 2]}\n", ":2: grid.seed:", "seeds:"),
        ("base: {kind: detect}\ngrid:\n  'a b': [1]\n", ":3: grid.a b:", "is not a key path"),
        (
            "base: {kind: detect}\nset: {mu: 1}\ngrid:\n  mu: [1, 2]\n",
            ":4: grid.mu:",
            "already set by set",
        ),
        (
            "base: {kind: detect}\nzip:\n  - {a: [1, 2], b: [1]}\n",
            ":3: zip[0]:",
            "equal lengths",
        ),
        (
            "base: {kind: detect}\nrandom:\n  samples: 2\n  params:\n    a: {uniform: [2, 1]}\n",
            ":5: random.params.a:",
            "low < high",
        ),
        (
            "base: {kind: detect}\nrandom:\n  samples: 2\n  params:\n"
            "    a: {loguniform: [0, 1], choice: [1]}\n",
            ":5: random.params.a:",
            "exactly one of",
        ),
        ("base: {kind: detect}\nseeds: 0\n", ":2: seeds:", "between 1 and 100000"),
        ("base: {kind: detect}\nseeds: [1, 1]\n", ":2: seeds:", "distinct"),
        ("base: missing.yaml\n", ":1: base:", "file not found"),
        ("base: {kind: detect}\nquick:\n  grid: {seed: [1]}\n", ":3: quick.grid.seed:", ""),
    ],
)
def test_bad_sweep_files_are_located(tmp_path, text, where, message):
    path = write(tmp_path, text)
    with pytest.raises(ScenarioError) as exc:
        plan(load_sweep(path))
    assert any(line.startswith(f"{path}{where}") and message in line for line in issues(exc)), (
        issues(exc)
    )


def test_schema_and_key_path_problems_are_reported_together(tmp_path):
    # an unknown key and a bad seed count (the schema's) with reserved keys (checked on the
    # raw file): every one at once, in line order
    path = write(
        tmp_path,
        """\
        base: {kind: detect}
        gird: {}
        grid:
          seed: [1, 2]
        seeds: 0
        quick:
          grid: {name: [a]}
          seeds: -1
        """,
    )
    with pytest.raises(ScenarioError) as exc:
        load_sweep(path)
    found = [line.removeprefix(f"{path}:") for line in issues(exc)]
    assert [f.split(": ")[0:2] for f in found] == [
        ["2", "gird"],
        ["4", "grid.seed"],
        ["5", "seeds"],
        ["7", "quick.grid.name"],
        ["8", "quick.seeds"],
    ], found


def test_an_unknown_sweep_key_is_not_called_a_key_of_a_kind(tmp_path):
    path = write(tmp_path, "base: {kind: detect}\ngird: {}\n")
    with pytest.raises(ScenarioError) as exc:
        load_sweep(path)
    (line,) = issues(exc)
    assert line.startswith(f"{path}:2: gird: unknown key")
    assert "kind" not in line and "sweep file" in line


def test_inline_base_errors_point_into_the_sweep_file(tmp_path):
    path = write(tmp_path, "base:\n  kind: detect\n  tip_radius: 0.01\n  simulaton: {}\n")
    with pytest.raises(ScenarioError) as exc:
        plan(load_sweep(path))
    assert any(line.startswith(f"{path}:4: simulaton: unknown key") for line in issues(exc))


def test_quick_variant_replaces_its_keys(tmp_path):
    path = write(
        tmp_path,
        """\
        base: {kind: detect, tip_radius: 0.01, simulation: {profile: {type: wire, diameter: 7e-4}}}
        grid: {tip_radius: [0.005, 0.01, 0.02]}
        seeds: 3
        quick:
          grid: {tip_radius: [0.01]}
        """,
    )
    full, quick = plan(load_sweep(path)), plan(load_sweep(path, quick=True))
    assert (len(full), len(quick)) == (9, 3)
    assert all(r.quick for r in quick) and not any(r.quick for r in full)
    assert {r.run_id for r in quick}.isdisjoint(r.run_id for r in full)


@pytest.mark.parametrize("name", ["gait_feasibility", "detection_noise"])
def test_bundled_sweeps_expand(name):
    path = ROOT / "scenarios" / "sweeps" / f"{name}.yaml"
    full, quick = plan(load_sweep(path)), plan(load_sweep(path, quick=True))
    assert len(full) >= 24 and 2 <= len(quick) <= 8
    assert len({r.run_id for r in full}) == len(full)
