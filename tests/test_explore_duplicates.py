"""A feature is traced once (its known area covers the whole traced outline) and the type
accuracy counts a duplicate report as an extra detection, never as an extra correct one."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from planner.exploration import explore_surface
from planner.exploration.surface.metrics import exploration_metrics, type_accuracy
from planner.sim.spatial.plate import Plate, PlateFeature

KINDS = ("bump", "pit", "ridge", "ravine", "step", "cusp")


def _truth(*kinds):
    return [SimpleNamespace(kind=k) for k in kinds]


@pytest.mark.parametrize(
    ("kinds", "match", "truth", "expected"),
    [
        (["ridge"], [0], ["ridge"], (1.0, 0)),
        (["step", "ridge"], [0, 0], ["ridge"], (0.5, 1)),  # audit finding 3
        (["step", "step"], [0, 0], ["step"], (0.5, 1)),  # audit finding 4: was 2.0
        (["step"], [0], ["ridge"], (0.0, 0)),
        (["bump", "pit", "bump"], [0, None, 1], ["bump", "pit"], (0.5, 0)),
        (["bump"], [None], ["bump"], (math.nan, 0)),
    ],
)
def test_type_accuracy_closed_forms(kinds, match, truth, expected):
    acc, dup = type_accuracy(kinds, match, _truth(*truth))
    assert dup == expected[1]
    assert acc == pytest.approx(expected[0], nan_ok=True)


@given(
    st.lists(st.sampled_from(KINDS), min_size=1, max_size=4),
    st.lists(st.tuples(st.sampled_from(KINDS), st.integers(-1, 3)), max_size=10),
)
def test_type_accuracy_is_a_share(true_kinds, found):
    match = [j if 0 <= j < len(true_kinds) else None for _, j in found]
    acc, dup = type_accuracy([k for k, _ in found], match, _truth(*true_kinds))
    matched = [j for j in match if j is not None]
    assert dup == len(matched) - len(set(matched))
    if matched:
        assert 0.0 <= acc <= 1.0
    else:
        assert math.isnan(acc)


def test_a_step_traced_from_end_to_end_is_not_traced_again():
    """Audit finding 4: the first trace ran the step's whole length but kept 9 samples near
    one end; the known area (their hull) did not cover the step and the last raster line
    traced it again - two features, type_accuracy 2.0."""
    plate = Plate((PlateFeature("step", 0.002, 0.001, (0.0, 0.003), math.radians(200)),))
    region = np.array([[-0.02, 0.02], [-0.02, 0.02]])
    res = explore_surface(plate, speed=0.03, duration=60)
    assert res.status == "ok"
    assert [f.kind for f in res.features] == ["step"]
    m = exploration_metrics(res, plate, region, 0.008, 0.3)
    assert m["features_found"] == 1 and m["duplicate_detections"] == 0
    assert m["type_accuracy"] == 1.0
