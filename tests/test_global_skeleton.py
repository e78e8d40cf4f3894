"""Global skeleton, regions, clearance, navigation and export (planner.skeleton)."""

import json

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import cKDTree
from shapely.geometry import shape

from planner.errors import InfeasibleProblem, InvalidParameter
from planner.skeleton import (
    feature_skeleton,
    global_skeleton,
    negative_medial_axis,
    region_report,
    safest_path,
    to_geojson,
    write_npz,
)
from planner.skeleton import shapes as sh


def ridge_box(y0, width, spacing=0.0005, length=0.05):
    return sh.sample_outline(shapely.box(0, y0, length, y0 + width), spacing)


def assert_partition(gs):
    areas = gs.region_areas
    assert np.all(areas > 0)
    assert areas.sum() == pytest.approx(gs.domain.area, rel=1e-9)
    assert shapely.union_all(gs.regions).area == pytest.approx(gs.domain.area, rel=1e-9)
    for i in range(gs.n_features):
        for j in range(i + 1, gs.n_features):
            assert gs.regions[i].intersection(gs.regions[j]).area < 1e-9 * gs.domain.area


@pytest.mark.parametrize("gap", [0.004, 0.01, 0.023])
@pytest.mark.parametrize("generators", ["boundary", "skeleton"])
def test_two_parallel_ridges(gap, generators):
    w = 0.008
    a, b = ridge_box(0.0, w), ridge_box(w + gap, w)
    gs = global_skeleton([a, b], generators=generators)
    mid = w + gap / 2
    assert np.allclose(gs.points[:, 1], mid, atol=1e-9)
    assert gs.clearance == pytest.approx(gap / 2, rel=1e-9)
    assert gs.pair_clearance[0, 1] == pytest.approx(gap / 2, rel=1e-9)
    assert_partition(gs)
    for i, pts in enumerate((a, b)):  # each region holds its own feature
        assert shapely.contains_xy(gs.regions[i].buffer(1e-9), pts[:, 0], pts[:, 1]).all()
    assert gs.can_pass(0, 1, 0.99 * gap / 2) and not gs.can_pass(0, 1, 1.01 * gap / 2)


def test_unequal_widths_boundary_generators_stay_between_boundaries():
    a, b = ridge_box(0.0, 0.02), ridge_box(0.03, 0.002)
    gs = global_skeleton([a, b])
    inner = (gs.points[:, 0] > 0) & (gs.points[:, 0] < 0.05)
    assert np.allclose(gs.points[inner, 1], 0.025, atol=1e-9)
    assert gs.clearance == pytest.approx(0.005)
    assert gs.edge_clearance.min() == pytest.approx(gs.clearance, rel=1e-6)


@settings(max_examples=10, deadline=None)
@given(
    st.lists(
        st.tuples(st.floats(-0.05, 0.05), st.floats(-0.05, 0.05), st.floats(0.002, 0.006)),
        min_size=2,
        max_size=4,
    )
)
def test_random_disks_partition_and_clearance(disks):
    # keep disks apart by at least 2 mm
    chosen = []
    for x, y, r in disks:
        if all(np.hypot(x - u, y - v) > r + q + 0.002 for u, v, q in chosen):
            chosen.append((x, y, r))
    if len(chosen) < 2:
        return
    bnd = [
        sh.sample_outline(shapely.Point(x, y).buffer(r, quad_segs=64), 0.0005) for x, y, r in chosen
    ]
    gs = global_skeleton(bnd)
    assert_partition(gs)
    brute = min(
        cKDTree(bnd[j]).query(bnd[i])[0].min()
        for i in range(len(bnd))
        for j in range(i + 1, len(bnd))
    )
    assert gs.clearance == pytest.approx(brute / 2, rel=1e-12)
    # every global skeleton point is equidistant from two features
    d = np.array([cKDTree(b).query(gs.points)[0] for b in bnd])
    d.sort(axis=0)
    interior = gs.radii > 0
    assert np.allclose(d[0, interior], d[1, interior], rtol=1e-6, atol=1e-9)


def test_regions_in_input_order_and_invariance_under_rigid_motion():
    bnd = [ridge_box(0.0, 0.008), ridge_box(0.02, 0.004), ridge_box(0.04, 0.008)]
    gs = global_skeleton(bnd)
    order = np.argsort([r.centroid.y for r in gs.regions])
    assert order.tolist() == [0, 1, 2]
    c, s = np.cos(0.7), np.sin(0.7)
    R = np.array([[c, -s], [s, c]])
    moved = global_skeleton([b @ R.T + 0.3 for b in bnd])
    assert moved.clearance == pytest.approx(gs.clearance, rel=1e-9)
    assert moved.pair_clearance == pytest.approx(gs.pair_clearance, rel=1e-9)


def test_safest_path_follows_the_skeleton_and_respects_the_tip():
    bnd = [ridge_box(0.0, 0.008), ridge_box(0.02, 0.008)]
    gs = global_skeleton(bnd)
    nav = safest_path(gs, [0.0, 0.014], [0.05, 0.014], tip_radius=0.005)
    assert np.allclose(nav.points[1:-1, 1], 0.014)
    assert nav.min_clearance == pytest.approx(0.006, rel=1e-6)
    assert nav.length >= 0.05
    with pytest.raises(InfeasibleProblem, match="tip_radius"):
        safest_path(gs, [0.0, 0.014], [0.05, 0.014], tip_radius=0.5)
    with pytest.raises(InvalidParameter, match="start"):
        safest_path(gs, [0.0, 0.014, 1.0, 2.0, 3.0], [0.05, 0.014])


def test_region_report_flags_large_regions():
    bnd = [ridge_box(0.0, 0.008), ridge_box(0.012, 0.008)]
    gs = global_skeleton(bnd, margin=0.001)
    rep = region_report(gs, tip_radius=0.004)
    assert [r.feature for r in rep] == [0, 1]
    assert all(r.feature_area == pytest.approx(0.05 * 0.008, rel=1e-6) for r in rep)
    assert not any(r.needs_exploration for r in rep)  # regions hug their features
    far = global_skeleton(bnd, margin=0.05)
    assert all(r.needs_exploration for r in region_report(far, tip_radius=0.004))


def test_negative_mat_keeps_same_feature_arcs():
    # a U-shaped feature: the negative MAT has an arc inside the U, the global skeleton not
    u = sh.ridge_polygon(np.array([[0, 0.03], [0, 0], [0.03, 0], [0.03, 0.03]]), 0.004)
    bnd = [sh.sample_outline(u, 0.0005), ridge_box(-0.03, 0.004, length=0.03)]
    nm = negative_medial_axis(bnd)
    inside_u = (nm.points[:, 0] > 0.005) & (nm.points[:, 0] < 0.025) & (nm.points[:, 1] > 0.005)
    assert inside_u.any()
    gs = global_skeleton(bnd)
    assert not (
        (gs.points[:, 0] > 0.005) & (gs.points[:, 0] < 0.025) & (gs.points[:, 1] > 0.005)
    ).any()


def test_exports(tmp_path):
    bnd = [ridge_box(0.0, 0.008), ridge_box(0.02, 0.008)]
    gs = global_skeleton(bnd)
    sks = [feature_skeleton(b) for b in bnd]
    doc = json.loads(json.dumps(to_geojson(sks, gs, ["a", "b"])))
    layers = [f["properties"]["layer"] for f in doc["features"]]
    assert layers.count("feature_skeleton") == 2 and layers.count("region") == 2
    assert layers.count("global_skeleton") == 1
    reg = [shape(f["geometry"]) for f in doc["features"] if f["properties"]["layer"] == "region"]
    assert reg[0].area == pytest.approx(gs.regions[0].area)
    path = write_npz(tmp_path / "skel.npz", sks, gs)
    data = np.load(path)
    assert np.array_equal(data["global_edges"], gs.edges)
    assert data["skeleton_1_radii"].shape == sks[1].radii.shape


def test_bad_inputs():
    a = ridge_box(0.0, 0.008)
    with pytest.raises(InvalidParameter, match="at least 2 features"):
        global_skeleton([a])
    with pytest.raises(InvalidParameter, match="list of"):
        global_skeleton(a)
    with pytest.raises(InvalidParameter, match="generators"):
        global_skeleton([a, a + 1], generators="voronoi")
    with pytest.raises(InvalidParameter, match=r"boundaries\[1\]"):
        global_skeleton([a, np.zeros((5, 3))])
    gs = global_skeleton([a, a + [0, 0.02]])
    with pytest.raises(InvalidParameter, match="feature index"):
        gs.can_pass(0, 5, 0.001)
