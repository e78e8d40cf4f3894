"""A gait scenario run can be repeated from Python: result.json's noise_seed."""

from __future__ import annotations

import math

import numpy as np

from planner.exploration import explore_object
from planner.runner import run_config
from planner.scenario import load_scenario


def test_noise_seed_reproduces_the_run_from_python():
    cfg = load_scenario("scenarios/ball_with_ridge.yaml", overrides=["seed=3", "duration=1.0"])
    res, _ = run_config(cfg, plots=False)
    seed = res.metrics["noise_seed"]
    assert isinstance(seed, int) and seed >= 0
    again = explore_object(
        cfg.object.profile(), hand=cfg.hand.hand(cfg.mu), mu=cfg.mu,
        nominal=cfg.nominal.profile(), seed=seed, duration=cfg.duration,
        settings=cfg.settings(), max_rotation=math.radians(cfg.max_rotation_deg),
    )  # fmt: skip
    assert math.degrees(again.rotation) == res.metrics["rotation_deg"]
    assert np.array_equal(again.log.arrays()["q"], res.arrays["log/q"])
    assert np.array_equal(np.asarray(again.trace["fnL"]), res.arrays["trace/fnL"])
