"""detect_features against the geometry package's exact profiles and their ground truth
(``Profile.curvature_features``): traced with ``curves.traced_curve`` (independent of the
detection package), and simulated with :func:`planner.geometry.measurement.simulate_trace`
(noise, observable truth)."""

import numpy as np
import pytest

from planner.detection import detect_features, macro_features, score_features
from planner.errors import InvalidParameter
from planner.geometry import curves, shapes
from planner.geometry.measurement import (
    THESIS_CENTER_SIGMA,
    THESIS_CONTACT_SIGMA,
    THESIS_NORMAL_SIGMA,
)
from planner.geometry.measurement import simulate_trace as simulate_profile

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


# --- simulate_trace: traces over catalogue profiles scored against their exact truth -------

THESIS_NOISE = {
    "center_sigma": THESIS_CENTER_SIGMA,
    "contact_sigma": THESIS_CONTACT_SIGMA,
    "normal_sigma": THESIS_NORMAL_SIGMA,
}


@pytest.mark.parametrize(
    "make,signs,kind",
    [
        (lambda: shapes.wire_on_plane(0.65e-3, angle=np.pi / 4), "-+-", "bump"),
        (lambda: shapes.step(2e-3), "-+", "step"),
        (lambda: shapes.step(-2e-3), "+-", "step"),
        (lambda: shapes.ridge(4e-3, 2e-3), "-++-", "ridge"),
        (lambda: shapes.ridge(4e-3, 2e-3, 1e-3), "-++-", "ridge"),
    ],
    ids=["wire45", "step_up", "step_down", "ridge", "rounded_ridge"],
)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_simulate_profile_alg3_f1_one_at_thesis_noise(make, signs, kind, seed):
    prof = make()
    tr = simulate_profile(prof, R, spacing=2e-5, rng=np.random.default_rng(seed), **THESIS_NOISE)
    exact = prof.curvature_features(R)
    assert [f.sign for f in tr.truth.features] == [f.sign for f in exact]
    assert [f.peak for f in tr.truth.features] == [f.peak for f in exact]
    assert "".join("+" if f.sign > 0 else "-" for f in tr.truth.observable) == signs
    feats = detect_features(tr.centers, R, algorithm=3)
    sc = score_features(feats, tr.truth.observable, R / 2)
    assert sc.f1 == 1.0, (feats, tr.truth.observable)
    assert sc.localization < 1e-3
    assert [m.kind for m in macro_features(feats, R)] == [kind]


def test_observable_index_is_where_the_contact_passes_the_feature():
    # step up, r_f = 10 mm: the foot (concave) is never touched, the fingertip bridges it at
    # the interference point; it then rolls over the top corner (convex) with the contact
    # point fixed on it: the index is the middle of that roll.
    tr = simulate_profile(shapes.step(2e-3), R, spacing=2e-5)
    foot, edge = tr.truth.observable_index
    on_edge = np.flatnonzero(np.linalg.norm(tr.truth.contacts - [0.0, 2e-3], axis=1) < 1e-6)
    assert foot == on_edge[0]  # the first sample past the unobservable foot
    assert abs(edge - (on_edge[0] + on_edge[-1]) / 2) <= 1
    # the interference point: the fingertip touches the plane and the edge at once
    assert np.linalg.norm(tr.truth.centers[foot] - [0.0, 2e-3]) == pytest.approx(R, abs=1e-6)
    assert tr.t[foot] == pytest.approx(tr.truth.s[foot] / 0.03)


@pytest.mark.parametrize("width,signs", [(4e-3, "+-+"), (30e-3, "+--+")])
def test_ravine_bottom_corners_merge_only_when_unobservable_together(width, signs):
    # a 4 mm groove: the fingertip (r_f 10 mm) bridges it, both bottom corners lie in one
    # gap of the contact locus and count once; a 30 mm one it touches in between.
    prof = shapes.ravine(width, 2e-3)
    tr = simulate_profile(prof, R, spacing=2e-5)
    assert "".join("+" if f.sign > 0 else "-" for f in prof.curvature_features(R)) == "+--+"
    assert "".join("+" if f.sign > 0 else "-" for f in tr.truth.observable) == signs
    assert np.all(np.diff(tr.truth.observable_index) >= 0)
    if width < 2 * R:
        assert tr.truth.observable[1].position == pytest.approx([0.0, -2e-3], abs=1e-12)


def test_simulate_profile_errors():
    closed = simulate_profile(shapes.circle(0.02), R, spacing=1e-4)
    assert closed.truth.observable == () and len(closed.truth.features) == 0
    with pytest.raises(InvalidParameter, match="tip_radius"):
        simulate_profile(shapes.step(2e-3), -R, spacing=2e-5)
    with pytest.raises(InvalidParameter, match="rng: expected a numpy Generator"):
        simulate_profile(shapes.step(2e-3), R, spacing=2e-5, center_sigma=1e-4)
