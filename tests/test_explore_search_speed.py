"""The online detector finds features at low search speeds (quantized encoders repeat
samples there): the default speed and 0.015 m/s, the cases of audit finding 1."""

from __future__ import annotations

import numpy as np

from planner.exploration import explore_surface
from planner.exploration.surface.result import ExplorationSettings
from planner.sim.spatial.plate import Plate, PlateFeature

BUMP = Plate((PlateFeature("bump", 0.004, 0.005, (0.0, 0.0)),))
#: the bundled ridge_plate's ridge
RIDGE = Plate((PlateFeature("ridge", 0.002, 0.0018, path=((-0.010, -0.003), (0.010, 0.004))),))


def test_default_speed_finds_a_bump_crossed_over_its_apex():
    assert ExplorationSettings().speed == 0.02
    res = explore_surface(BUMP, duration=60)
    # the v = 0 raster line crosses the bump's apex: the centre rises by 4 mm there
    assert np.ptp(res.path[:, 2]) > 3e-3
    assert res.status == "ok"
    assert [f.kind for f in res.features] == ["bump"]


def test_slow_search_finds_the_ridge_plate_ridge():
    res = explore_surface(RIDGE, speed=0.015, duration=60)
    assert res.status == "ok"
    assert [f.kind for f in res.features] == ["ridge"]
