"""planner.detection.detect_features: the four algorithms of thesis Fig. 3.8."""

import numpy as np
import pytest
from feature_traces import feature_trace
from hypothesis import example, given, settings
from hypothesis import strategies as st

from planner.detection import (
    DetectionSettings,
    curvature_signal,
    detect_features,
    macro_features,
    score_features,
)
from planner.errors import InvalidParameter

R = 0.01


def _trace(kind="wire", size=0.65e-3, angle=np.pi / 4, seed=0, noise=1.0, r=R, **kw):
    return feature_trace(kind, size, angle=angle, seed=seed, noise=noise, r=r, **kw)


def _signs(fs):
    return "".join("+" if f.sign > 0 else "-" for f in fs)


def test_traced_curvature_maps_to_object_curvature():
    # A fingertip rolling over a convex circular object of radius Ro traces a circle of
    # radius Ro + r: k_t = 1/(Ro + r) and k_obj = k_t / (1 - r k_t) = 1/Ro.
    ro = 0.004
    th = np.linspace(np.pi * 0.9, np.pi * 0.1, 4000)  # clockwise: material on the right
    centers = (ro + R) * np.column_stack([np.cos(th), np.sin(th)])
    sig = curvature_signal(centers, R, 3)
    mid = sig.curvature[len(sig.curvature) // 4 : 3 * len(sig.curvature) // 4]
    assert np.allclose(mid, 1 / (ro + R), rtol=1e-3)
    k_obj = mid / (1 - R * mid)
    assert np.allclose(k_obj, 1 / ro, rtol=5e-3)


@settings(max_examples=15, deadline=None)
@given(ratio=st.floats(0.3, 3.0).filter(lambda x: abs(x - 1) > 0.15))
def test_convex_feature_iff_object_radius_below_tip_radius(ratio):
    # k_obj > 1/r_f  <=>  k_t > 1/(2 r_f): the threshold of algorithm 3
    ro = ratio * R
    th = np.linspace(np.pi * 0.75, np.pi * 0.25, 3000)
    centers = (ro + R) * np.column_stack([np.cos(th), np.sin(th)])
    feats = detect_features(centers, R, 3)
    convex = [f for f in feats if f.sign > 0]
    assert bool(convex) == (ro < R)


@pytest.mark.parametrize(
    "kind,size,expected",
    [
        ("wire", 0.65e-3, "-+-"),
        ("step", 2e-3, "-+"),
        ("step", -2e-3, "+-"),
        ("plane", 0.0, ""),
    ],
)
def test_algorithm3_sign_patterns(kind, size, expected):
    tr = _trace(kind, size)
    feats = detect_features(tr.centers, R)
    assert _signs(feats) == expected
    sc = score_features(feats, tr.truth.observable, R / 2)
    assert sc.fp == 0 and sc.fn == 0


def test_wire_localization_and_macro_bump():
    tr = _trace("wire", 0.65e-3, seed=3)
    feats = detect_features(tr.centers, R)
    sc = score_features(feats, tr.truth.observable, R / 2)
    assert sc.f1 == 1.0
    assert sc.localization < 0.4e-3
    conv = [f for f in feats if f.sign > 0][0]
    truth = [f for f in tr.truth.observable if f.sign > 0][0]
    assert np.linalg.norm(conv.position - truth.position) < 0.3e-3
    macros = macro_features(feats, R)
    assert [m.kind for m in macros] == ["bump"]
    for f in feats:
        assert 0 <= f.start <= f.peak <= f.end <= tr.truth.s[-1] + 1e-3


def test_thesis_findings_on_45_degree_wire():
    # §3.4.2: algorithm 3 best; 1 and 4 miss concave features; 2 misses convex ones.
    tr = _trace("wire", 0.65e-3, seed=11)
    got = {
        a: _signs(detect_features(tr.centers, R, a, normals=tr.normals, contacts=tr.contacts))
        for a in (1, 2, 3, 4)
    }
    assert got[3] == "-+-"
    assert "-" not in got[1] and "-" not in got[4]
    assert "+" not in got[2] and "-" in got[2]


def test_three_d_data_and_rigid_motion():
    tr = _trace("step", 2e-3, angle=0.3, seed=4)
    feats2 = detect_features(tr.centers, R)
    rot = np.array([[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.0, 0.8, -0.6]])
    c3 = np.column_stack([tr.centers, np.zeros(len(tr.centers))]) @ rot.T + [0.1, -0.2, 0.3]
    n3 = np.column_stack([tr.normals, np.zeros(len(tr.normals))]) @ rot.T
    feats3 = detect_features(c3, R, normals=n3)
    assert _signs(feats3) == _signs(feats2) == "-+"
    for f2, f3 in zip(feats2, feats3, strict=True):
        assert f3.position.shape == (3,)
        p2 = np.append(f2.position, 0.0) @ rot.T + [0.1, -0.2, 0.3]
        assert np.linalg.norm(p2 - f3.position) < 1e-4
        assert abs(f2.peak - f3.peak) < 1e-4


@settings(max_examples=10, deadline=None)
@given(angle=st.floats(-np.pi, np.pi), dx=st.floats(-1, 1), dy=st.floats(-1, 1))
def test_rotation_invariance_with_normals(angle, dx, dy):
    tr = _trace("wire", 1e-3, angle=0.0, seed=5)
    c, s = np.cos(angle), np.sin(angle)
    rot = np.array([[c, -s], [s, c]])
    feats = detect_features(tr.centers @ rot.T + [dx, dy], R, normals=tr.normals @ rot.T)
    assert _signs(feats) == "-+-"


def test_reversed_travel_uses_normals_for_the_material_side():
    tr = _trace("step", 2e-3, seed=6)
    feats = detect_features(tr.centers[::-1], R, normals=tr.normals[::-1])
    assert _signs(feats) == "+-"  # a step down when travelled backwards: concave foot last
    feats_wrong = detect_features(tr.centers[::-1], R, material_side="right")
    assert _signs(feats_wrong) == "-+"  # material assumed on the wrong side: signs flip


def test_bad_inputs():
    c = np.zeros((50, 2))
    c[:, 0] = np.linspace(0, 0.05, 50)
    with pytest.raises(InvalidParameter, match="shape"):
        detect_features(np.zeros((50, 4)), R)
    with pytest.raises(InvalidParameter, match="tip_radius"):
        detect_features(c, -1.0)
    with pytest.raises(InvalidParameter, match="algorithm"):
        detect_features(c, R, algorithm=5)
    with pytest.raises(InvalidParameter, match="unknown setting"):
        detect_features(c, R, smoothness=3)
    with pytest.raises(InvalidParameter, match="contacts: algorithm 1 needs"):
        detect_features(c, R, algorithm=1)
    with pytest.raises(InvalidParameter, match="normals"):
        detect_features(c, R, algorithm=2)
    bad = c.copy()
    bad[7, 1] = np.nan
    with pytest.raises(InvalidParameter, match="row 7"):
        detect_features(bad, R)
    with pytest.raises(InvalidParameter, match="rows"):
        detect_features(c, R, normals=np.ones((10, 2)))
    with pytest.raises(InvalidParameter, match="at least"):
        detect_features(c[:3], R)
    with pytest.raises(InvalidParameter, match="material_side"):
        detect_features(c, R, material_side="below")


# --- the material side read from the path; a trace recorded backwards --------------------


@pytest.mark.parametrize(
    "kind,size", [("step", 2e-3), ("step", -2e-3), ("wire", 1.5e-3), ("ridge", 2e-3)]
)
def test_reversed_trace_without_normals_gives_the_same_features(kind, size):
    # regression: with centres only, a right-to-left trace over a step and a bump was read
    # as ['step', 'pit'] (the material assumed on the right of travel)
    tr = _trace(kind, size, seed=6)
    fwd = detect_features(tr.centers, R)
    back = detect_features(tr.centers[::-1], R)
    assert [m.kind for m in macro_features(back, R)] == [m.kind for m in macro_features(fwd, R)]
    assert _signs(back) == _signs(fwd)[::-1]


def test_step_and_bump_read_backwards():
    step = _trace("step", 2e-3, angle=0.0, seed=1).centers
    bump = _trace("wire", 1.5e-3, angle=0.0, seed=2).centers
    both = np.concatenate([step, bump[1:] + step[-1] - bump[0]])
    kinds = [m.kind for m in macro_features(detect_features(both[::-1], R), R)]
    assert sorted(kinds) == ["bump", "step"]


@settings(max_examples=12, deadline=None, derandomize=True)
@given(
    kind=st.sampled_from(["step", "wire", "ridge"]),
    size=st.floats(1.5e-3, 3e-3),
    angle=st.floats(-0.6, 0.6),
    seed=st.integers(0, 1000),
)
@example(kind="wire", size=0.003, angle=0.0, seed=0)  # two humps: either may be the peak
@example(kind="ridge", size=0.003, angle=0.0, seed=241)  # a concave spike, in place
@example(kind="ridge", size=0.001953125, angle=0.5, seed=13)  # 1521 samples, blocks of 4
@example(kind="step", size=0.002, angle=-0.25, seed=321)  # a flat peak (an edge's arc)
def test_reversal_property_mirrors_arclengths(kind, size, angle, seed):
    """A trace read backwards gives the same features, mirrored: the same regions (noise
    and the block grid move their ends a little), the same surface points, and a peak
    inside the mirrored region. Where the peak's arclength mirrors is not a property: the
    signal can be flat across the region (the tip rolling around a step's edge traces an
    arc of radius r_f, curvature 1/r_f all along: the argmax of its noise moved 2.3 mm) or
    have two humps of one height (a wire: 112.3 and 111.7 1/m, 9.4 mm apart, taken in
    turn forwards and backwards); the surface point there is what locates the feature."""
    tr = _trace(kind, size, angle=angle, seed=seed, noise=0.5, spacing=4e-5)
    fwd = detect_features(tr.centers, R)
    back = detect_features(tr.centers[::-1], R)
    assert len(back) == len(fwd) > 0
    length = curvature_signal(tr.centers, R, 3).s[-1]  # detect_features' algorithm 3
    for f, b in zip(fwd, reversed(back), strict=True):
        assert b.sign == f.sign
        assert abs((length - b.end) - f.start) < R / 4
        assert abs((length - b.start) - f.end) < R / 4
        assert np.linalg.norm(b.position - f.position) < R / 4
        assert b.start <= b.peak <= b.end and f.start <= f.peak <= f.end


def test_infer_side_needs_evidence_on_a_smooth_path():
    from planner.detection.path import gaussian_derivatives
    from planner.detection.signals import infer_material_side

    x = np.linspace(0, 0.05, 2000)
    line = np.column_stack([x, 0.001 * np.sin(x / 0.01)])
    _, d1, d2 = gaussian_derivatives(line, 3.0)
    assert infer_material_side(d1, d2, R) is None  # nothing tells: the caller's default


# --- nonsense input is rejected with a reason ---------------------------------------------


def test_millimetres_passed_as_metres_are_rejected():
    tr = _trace("wire", 0.65e-3, seed=3)
    with pytest.raises(InvalidParameter, match="looks like millimetres"):
        detect_features(tr.centers * 1e3, R)


def test_too_few_samples_per_tip_radius_are_rejected():
    tr = _trace("wire", 0.65e-3, seed=3)
    few = tr.centers[:: len(tr.centers) // 10]
    with pytest.raises(InvalidParameter, match="samples per tip radius"):
        detect_features(few, R)


def test_settings_object_checks_itself():
    s = DetectionSettings(smoothing_scale=1e-3, material_side="left")
    assert DetectionSettings.of(s, merge_gap=0.0).material_side == "left"
    for bad, match in [
        ({"smoothing_scale": -1.0}, "smoothing_scale"),
        ({"material_side": "below"}, "material_side"),
        ({"upper": 0.0}, "upper"),
        ({"lower": 1.0}, "lower"),
        ({"normal_arclength": "time"}, "normal_arclength"),
    ]:
        with pytest.raises(InvalidParameter, match=match):
            DetectionSettings(**bad)
    tr = _trace("wire", 0.65e-3, seed=3)
    a = detect_features(tr.centers, R, settings=s.of(material_side="right"))
    b = detect_features(tr.centers, R, smoothing_scale=1e-3, material_side="right")
    assert _signs(a) == _signs(b) == "-+-"


@settings(max_examples=40, deadline=None, derandomize=True)
@given(n=st.integers(1, 200), block=st.integers(1, 12))
def test_block_means_keeps_whole_blocks_evenly_spaced(n, block):
    """The decimation keeps ``n // block`` whole blocks, the leftover split between the
    ends, at centre indices ``block`` apart; on a ramp each mean is its centre index. A
    shorter last block sat closer to its neighbour: a kink, read as a spurious feature at
    the end of a trace read backwards (the example above with seed 13)."""
    from planner.detection.path import block_means

    block = min(block, n)
    ramp = np.column_stack([np.arange(n, dtype=float), 2.0 * np.arange(n)])
    means, index = block_means(ramp, block)
    m = n // block
    assert means.shape == (m, 2) and index.shape == (m,)
    assert np.allclose(np.diff(index), block)
    assert np.allclose(means[:, 0], index) and np.allclose(means[:, 1], 2 * index)
    lead = index[0] - (block - 1) / 2
    trail = (n - 1) - (index[-1] + (block - 1) / 2)
    assert lead >= 0 and trail >= 0 and abs(lead - trail) <= 1 and lead + trail == n - m * block
