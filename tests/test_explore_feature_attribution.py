"""Boundary samples belong to the feature they were traced for (tracing.trace_boundary).

A ridge found next to the region's edge begins its trace outside the region's end margin.
The first end was then reached before any sample was kept, and the finger went back to the
recorder row of the first trace step - not yet written, zeros: the plate's origin - traced
from there, wandered 20 mm to an already traced bump and filed the bump's outline under the
ridge. Now it goes back to where tracing began, and an end counts only farther out than that.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

from planner.exploration.surface import explore_surface
from planner.sim.spatial.plate import Plate, PlateFeature

REGION = ((-0.025, 0.025), (-0.025, 0.025))  # [m]
BUMP = PlateFeature("bump", 0.002, 0.003, (-0.012, -0.0075))
RIDGE = PlateFeature("ridge", 0.002, 0.0018, path=((-0.016, 0.019), (-0.002, 0.0225)))


@pytest.fixture(scope="module")
def run():
    return explore_surface(Plate((BUMP, RIDGE)), region=REGION, duration=120.0, speed=0.03)


def test_boundary_samples_lie_around_their_feature(run):
    assert run.status == "ok", run.reason
    traced = [f for f in run.features if len(f.boundary)]
    assert traced
    for f in traced:
        d = np.linalg.norm(f.boundary - f.centre, axis=1)
        assert np.median(d) < 0.012, (f.kind, f.centre, f.boundary.mean(axis=0))


def test_boundary_samples_are_recorded_while_their_feature_is_explored(run):
    """Each sample is a path point taken between its feature's detection and the next one."""
    times = [f.detected_at for f in run.features] + [run.t[-1] + 1.0]
    tree = cKDTree(run.path[:, :2])
    for i, f in enumerate(run.features):
        # the finger may have stood on a sample's point at other times too: any one will do
        for p, ks in zip(f.boundary, tree.query_ball_point(f.boundary, 1e-12), strict=True):
            t = run.t[ks]
            assert np.any((t > times[i]) & (t < times[i + 1])), (i, f.kind, p, t)


def test_the_bump_is_traced_closed_around_its_position(run):
    bumps = [f for f in run.features if np.hypot(*(f.centre - BUMP.position)) < 3e-3]
    assert len(bumps) == 1
    f = bumps[0]
    assert f.kind == "bump" and f.closed
    assert np.linalg.norm(f.boundary.mean(axis=0) - BUMP.position) < 1e-3


def test_no_trace_sample_near_the_plate_origin(run):
    """Nothing lies at the origin here: a trace there is one started from an unwritten row."""
    trace = run.phase == run.phases.index("trace")
    assert np.hypot(*run.path[trace, :2].T).min() > 5e-3


def test_a_ridge_whose_outline_begins_outside_the_region_is_still_traced(run):
    """The trace begins beyond the region's end margin (the ridge's far flank lies past the
    region's edge): an end counts only farther out than that, so the ridge is traced - it
    used to reach both ends at once with no sample and stay a 'bump' at its end cap."""
    assert sorted(f.kind for f in run.features) == ["bump", "ridge"]
    (ridge,) = [f for f in run.features if f.kind == "ridge"]
    crest = np.linspace(RIDGE.path[0], RIDGE.path[1], 50)
    d, _ = cKDTree(ridge.boundary).query(crest)
    assert len(ridge.boundary) > 100 and d.max() < 8e-3
