"""detect_features against the geometry package's exact profiles and their ground truth
(``Profile.curvature_features``), traced with ``curves.traced_curve`` (independent of the
detection package's own synthetic traces)."""

import numpy as np
import pytest

from planner.detection import detect_features, macro_features
from planner.geometry import curves, shapes

R = 0.01


@pytest.mark.parametrize(
    "name,make,kind",
    [
        ("wire45", lambda: shapes.wire_on_plane(0.65e-3, angle=np.pi / 4), "bump"),
        ("step_up", lambda: shapes.step(2e-3), "step"),
        ("step_down", lambda: shapes.step(-2e-3), "step"),
        ("ridge", lambda: shapes.ridge(4e-3, 2e-3), "ridge"),
        ("bump_arc", lambda: shapes.bump(1e-3, 3e-3), "bump"),
    ],
)
@pytest.mark.parametrize("noise", [0.0, 1e-4])
def test_signs_and_positions_match_profile_truth(name, make, kind, noise):
    prof = make()
    pts = curves.resample_equal_arclength(curves.traced_curve(prof, R).points, 5e-5)
    pts = pts + np.random.default_rng(1).normal(0, noise, pts.shape)
    feats = detect_features(pts, R)
    truth = prof.curvature_features(R)
    assert [f.sign for f in feats] == [f.sign for f in truth]
    for f, t in zip(feats, truth, strict=True):
        assert np.linalg.norm(f.position - np.asarray(t.position)) < R / 2
    assert [m.kind for m in macro_features(feats, R)] == [kind]
