"""identify="raster" (thesis §4.4.1, the pattern-matching alternative): a matched feature is
traced where it lies (audit finding 6)."""

from __future__ import annotations

import math

import numpy as np

from planner.exploration.surface import explore_surface
from planner.exploration.surface.metrics import exploration_metrics
from planner.sim.spatial.plate import Plate, PlateFeature

R = 0.008  # [m] the default fingertip radius
REGION = np.array([[-0.02, 0.02], [-0.02, 0.02]])  # the default region [m]


def test_a_raster_matched_cusp_is_traced_along_its_crest():
    """A 2 mm cusp (w 6 mm, across -20 deg): the finger reached the start of its outline
    search downhill on the flank, from the raster's last line, and ran on past it; the
    centre sank by half the rise at once, the crest search took the start for the far flank
    and a level line 10 mm down the flank was traced (boundary 8.4 mm off). Starting from
    rest, it climbs over the crest and traces the outline along it."""
    cusp = PlateFeature("cusp", 0.002, 0.006, (0.004, 0.0), math.radians(-20.0))
    plate = Plate((cusp,))
    res = explore_surface(plate, speed=0.03, duration=60.0, identify="raster", line_spacing=0.006)
    assert res.status == "ok", res.reason
    assert [f.kind for f in res.features] == ["cusp"], [f.evidence for f in res.features]
    m = exploration_metrics(res, plate, REGION, R, 0.3)
    # issue 12's targets: the outline within 0.5 mm, the (pseudo-)skeleton within 1 mm
    assert m["boundary_deviation_mean_mm"] <= 0.5
    assert m["skeleton_hausdorff_mm"] <= 1.0
