"""Holes in a traced closed outline (thesis §4.4.2, §4.5.2): a decision stop closes the
outline only once the finger has come back round, and the stretches it went round unsettled
(the inside of a bend) are filled from the traced path - the skeleton runs along the crest,
not into a gap."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from scipy.spatial import cKDTree

from planner.exploration import explore_surface
from planner.exploration.surface.runtime import PHASE
from planner.exploration.surface.tracing import (
    HOLE,
    SETTLED_LATERAL,
    SMOOTH,
    _covered,
    _fill_from_path,
)
from planner.sim.spatial.plate import Plate, PlateFeature


def _loop(n=3000, radius=5e-3):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    centres = np.column_stack([radius * np.cos(t), radius * np.sin(t), np.full_like(t, 8e-3)])
    phases = np.full(n, PHASE["trace"], np.int8)
    rec = SimpleNamespace(centre=centres, phase=phases, n=n)
    return SimpleNamespace(rec=rec), centres


def test_hole_traced_unsettled_is_filled_from_the_path_after_the_first_kept_sample():
    ex, centres = _loop()
    hole = set(range(1000, 1400))  # 4.2 mm traced with a lateral error above SETTLED_LATERAL
    before = set(range(0, 200))  # the approach transient, before the first kept sample
    kept = np.array([k for k in range(3000) if k not in hole | before])
    assert not _covered(ex, list(kept), 0)
    got, gap = _fill_from_path(ex, kept, int(kept[0]))
    assert set(got) >= set(kept)
    assert _covered(ex, list(got), int(kept[0]))
    added = np.setdiff1d(got, kept)
    assert added.min() >= kept[0]  # the transient before the first kept sample is not used
    d = cKDTree(centres[kept, :2]).query(centres[added, :2])[0]
    assert np.all(d > HOLE + SETTLED_LATERAL)  # only where the kept samples leave a hole
    assert gap == np.float64(d.max()) and 2e-3 < gap < 2.2e-3  # half the 4.2 mm hole


def test_lost_steps_and_stray_runs_are_not_filled():
    ex, _ = _loop()
    kept = np.array([k for k in range(3000) if not 1000 <= k < 1400])
    ex.rec.phase[1000:1400] = PHASE["reapproach"]  # the finger lost the outline there
    assert _fill_from_path(ex, kept, 0) == (kept, 0.0)
    ex.rec.phase[1200 : 1200 + SMOOTH // 2] = PHASE["trace"]  # a stray stretch, not a run
    assert _fill_from_path(ex, kept, 0)[1] == 0.0


@pytest.mark.xfail(
    strict=True,
    reason="mostly the default one-contact simulator: identified a closed ridge (boundary 0.16 mm "
    "off the true outline), its skeleton is 1.29 mm off the crest (1.05-4 mm as the trace "
    "varies; with line_spacing=0.016 too). Inside the V's bend the ball rests on both arms, "
    "but the SpatialWorld plate contact is one closest point, so past the true inner corner "
    "of the outline the ball sinks into the other arm (centre 0.12 mm below the resting "
    "height 0.7 mm past the corner, 0.75 mm 2.7 mm past it): the level line it traces on the "
    "simulated surface runs 2.7 mm straight on into the feature, kept as settled samples, and"
    " the medial axis bends towards that tongue. With SpatialWorld(all_contacts=True) "
    "(explore's all_contacts) the ball rests on both arms (sinking 0.74 mm -> 14 um at most) "
    "and the skeleton is still 1.18 mm off: the rest of the error is not explained yet",
)
def test_curved_ridge_skeleton_follows_the_crest_around_the_bend():
    """scenarios/curved_ridge.yaml (Fig. 4.13): the decision parameter stops the tracing
    with the inside of the bend traced unsettled (a 1.3 mm hole in the kept samples); the
    outline is closed, filled there, and its skeleton lies within 1 mm of the crest line
    (0.94 mm; 2.83 mm when the hole was left open)."""
    path = ((-0.012, -0.010), (0.006, -0.004), (-0.008, 0.010))
    plate = Plate((PlateFeature("ridge", 0.002, 0.0018, path=path),))
    region = ((-0.02, 0.02), (-0.02, 0.02))
    res = explore_surface(
        plate, region=region, strategy="raster", speed=0.03, duration=80.0, seed=0
    )
    assert [f.kind for f in res.features] == ["ridge"]
    f = res.features[0]
    assert f.closed
    assert any("filled from the traced path" in e for e in f.evidence), f.evidence
    crest = np.vstack([np.linspace(a, b, 200) for a, b in zip(path[:-1], path[1:], strict=True)])
    assert cKDTree(crest).query(f.skeleton.points)[0].max() <= 1e-3
