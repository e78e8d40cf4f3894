"""Feature skeletons (planner.skeleton.feature): closed forms, noise, invariance, errors."""

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import cKDTree

from planner.errors import InvalidParameter
from planner.skeleton import (
    feature_skeleton,
    pseudo_skeleton,
    reconstruct,
    regeneration_error,
)
from planner.skeleton import shapes as sh
from planner.skeleton.region import estimate_noise


def hausdorff(a, b):
    return max(cKDTree(b).query(a)[0].max(), cKDTree(a).query(b)[0].max())


W, H = 0.04, 0.01  # rectangle [m]
A, B = 0.02, 0.008  # ellipse semi-axes [m]


@pytest.mark.parametrize("spacing", [0.00025, 0.0005, 0.001])
@pytest.mark.parametrize("noise_frac", [0.0, 0.05])
def test_rectangle_skeleton_matches_closed_form(spacing, noise_frac):
    rng = np.random.default_rng(3)
    pts = sh.rectangle_outline(W, H, spacing)
    pts = pts + rng.normal(0, noise_frac * spacing, pts.shape)
    sk = feature_skeleton(pts, spacing)
    assert len(sk.branch_points) == 2 and len(sk.end_points) == 4  # no spurious branches
    assert hausdorff(sk.points, sh.rectangle_medial_axis(W, H)) <= 2.5 * spacing
    # the central segment carries radius H/2 (a vertex between samples s apart: + s^2/(4H))
    mid = np.abs(sk.points[:, 0]) < W / 2 - H
    tol = spacing**2 / (4 * H) + 4 * noise_frac * spacing + 1e-12
    assert np.allclose(sk.radii[mid], H / 2, atol=tol)


@pytest.mark.parametrize("spacing", [0.0002, 0.0005, 0.001, 0.002])
@pytest.mark.parametrize("noise_frac", [0.0, 0.05, 0.15])
def test_ellipse_skeleton_is_one_arc_near_true_axis(spacing, noise_frac):
    rng = np.random.default_rng(7)
    pts = sh.ellipse_outline(A, B, spacing)
    pts = pts + rng.normal(0, noise_frac * spacing, pts.shape)
    sk = feature_skeleton(pts, spacing)
    assert len(sk.branch_points) == 0 and len(sk.end_points) == 2
    assert sk.n_components == 1
    assert hausdorff(sk.points, sh.ellipse_medial_axis(A, B)) <= 2.5 * spacing


def test_ring_gives_closed_loop():
    rng = np.random.default_rng(0)
    R, w, s = 0.02, 0.004, 0.0004
    pts = sh.sample_outline(sh.ring_polygon(R, w), s, 0.1 * s, rng)
    sk = feature_skeleton(pts)
    assert sk.has_loop and len(sk.end_points) == 0 and len(sk.branch_points) == 0
    r = np.hypot(*sk.points.T)
    assert np.all(np.abs(r - R) < s)
    assert abs(np.median(sk.radii) - w / 2) < 0.1 * w
    assert abs(sk.length - 2 * np.pi * R) < 0.05 * 2 * np.pi * R


def test_unordered_and_open_traces():
    rng = np.random.default_rng(1)
    pts = sh.ellipse_outline(A, B, 0.0005)
    ref = feature_skeleton(pts)
    shuffled = feature_skeleton(pts[rng.permutation(len(pts))])
    assert len(shuffled.end_points) == 2 and len(shuffled.branch_points) == 0
    assert hausdorff(shuffled.points, ref.points) < 1e-12
    opened = feature_skeleton(pts[:-8])  # the trace stopped before closing
    assert len(opened.end_points) == 2
    assert hausdorff(opened.points, sh.ellipse_medial_axis(A, B)) <= 3 * 0.0005


def test_spacing_and_noise_estimates():
    rng = np.random.default_rng(2)
    s, sigma = 0.0005, 0.00004
    pts = sh.ellipse_outline(A, B, s)
    pts = pts + rng.normal(0, sigma, pts.shape)
    sk = feature_skeleton(pts)
    assert abs(sk.spacing - s) < 0.1 * s
    assert 0.6 * sigma < sk.noise < 1.5 * sigma


@settings(max_examples=30, deadline=None)
@given(
    period=st.floats(2.5, 6.5),
    amplitude=st.floats(5e-6, 5e-5),
    phase=st.floats(0.0, 1.0),
    radius=st.floats(0.002, 0.008),
)
def test_noise_estimate_sees_a_sawtooth(period, amplitude, phase, radius):
    """Positions read through quantized encoders drift off the outline and jump back: a
    sawtooth of amplitude ``A`` (standard deviation ``A / sqrt(12)``) that the second
    difference of three neighbours sees only at the jumps. The estimate is at least ``A / 4``
    (the DVMA's edge-length threshold ``4 sigma r / s`` then covers the jump's ``A r / s``)
    and at most twice the standard deviation (``period``: samples per tooth)."""
    s = 8e-5
    n = int(2 * np.pi * radius / s)
    t = np.arange(n) * 2 * np.pi / n
    e = amplitude * (np.mod(np.arange(n) / period + phase, 1.0) - 0.5)
    pts = (radius + e)[:, None] * np.column_stack([np.cos(t), np.sin(t)])
    sigma = estimate_noise(pts, [np.arange(n)])
    assert amplitude / 4 <= sigma <= 2 * amplitude / np.sqrt(12)


def test_radii_are_distances_to_nearest_sample():
    rng = np.random.default_rng(4)
    pts = sh.ellipse_outline(A, B, 0.0005) + rng.normal(0, 2e-5, (1, 2))
    sk = feature_skeleton(pts)
    d, _ = cKDTree(pts).query(sk.points)
    assert np.allclose(sk.radii, d, rtol=1e-9, atol=1e-12)


def test_branching_and_non_branching():
    rng = np.random.default_rng(5)
    arms = [
        np.array([[0, 0], [0.02 * np.cos(a), 0.02 * np.sin(a)]]) for a in np.deg2rad([0, 120, 240])
    ]
    pts = sh.sample_outline(sh.ridge_polygon(arms, 0.005), 0.0004, 3e-5, rng)
    sk = feature_skeleton(pts)
    assert len(sk.branch_points) == 1 and len(sk.end_points) == 3
    main = feature_skeleton(pts, branching=False)
    assert len(main.branch_points) == 0 and len(main.end_points) == 2
    assert main.length < sk.length


def test_regeneration_error_small_and_reconstruction_covers_region():
    sk = feature_skeleton(sh.ellipse_outline(A, B, 0.0003))
    err = regeneration_error(sk)
    assert err.area_ratio < 0.01 and err.hausdorff < 0.001
    rec = reconstruct(sk)
    assert abs(rec.area - np.pi * A * B) < 0.01 * np.pi * A * B


@settings(max_examples=15, deadline=None)
@given(angle=st.floats(0, 2 * np.pi), tx=st.floats(-1, 1), ty=st.floats(-1, 1))
def test_rigid_motion_invariance(angle, tx, ty):
    rng = np.random.default_rng(11)
    pts = sh.ellipse_outline(A, B, 0.0008)
    pts = pts + rng.normal(0, 3e-5, pts.shape)
    c, s = np.cos(angle), np.sin(angle)
    R = np.array([[c, -s], [s, c]])
    t = np.array([tx, ty])
    ref = feature_skeleton(pts, 0.0008, noise=3e-5)
    moved = feature_skeleton(pts @ R.T + t, 0.0008, noise=3e-5)
    assert moved.length == pytest.approx(ref.length, rel=1e-6)
    assert len(moved.points) == len(ref.points)
    assert hausdorff(moved.points, ref.points @ R.T + t) < 1e-8
    assert np.allclose(np.sort(moved.radii), np.sort(ref.radii), atol=1e-9)


def test_pseudo_skeleton_is_the_traced_path():
    path = np.column_stack([np.linspace(0, 0.03, 31), 0.002 * np.sin(np.linspace(0, 3, 31))])
    sk = pseudo_skeleton(np.vstack([path[:5], path[4:5], path[5:]]))  # a repeated sample
    assert len(sk.points) == 31 and len(sk.edges) == 30
    assert np.all(sk.radii == 0) and len(sk.end_points) == 2
    assert sk.length == pytest.approx(np.hypot(*np.diff(path, axis=0).T).sum())


@pytest.mark.parametrize(
    "bad, match",
    [
        (np.zeros((10, 3)), r"boundary: expected shape \(N, 2\)"),
        (np.array([[0, 0], [1, 0], [0, 1], [np.nan, 1], [1, 1]]), "finite"),
        (np.array([[0, 0], [1, 0], [0, 1]]), "at least 4"),
        (np.column_stack([np.linspace(0, 1, 20), np.zeros(20)]), "enclose no area|Voronoi"),
        ("abc", "convert|shape"),
    ],
)
def test_bad_boundaries_raise(bad, match):
    with pytest.raises(InvalidParameter, match=match):
        feature_skeleton(bad)


def test_bad_settings_raise():
    pts = sh.ellipse_outline(A, B, 0.001)
    with pytest.raises(InvalidParameter, match="unknown setting"):
        feature_skeleton(pts, prune=3)
    with pytest.raises(InvalidParameter, match="spacing"):
        feature_skeleton(pts, -1.0)
    with pytest.raises(InvalidParameter, match="min_angle_deg"):
        feature_skeleton(pts, min_angle_deg=200)
    with pytest.raises(InvalidParameter, match="min_branch_length"):
        feature_skeleton(pts, min_branch_length=float("nan"))


def test_non_uniform_sampling_and_wrong_spacing_hint():
    # finger speed varies: steps between 0.3 and 1.5 mm along the outline
    t = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    ring = shapely.Polygon(np.column_stack([A * np.cos(t), B * np.sin(t)])).exterior
    pos = [0.0]
    while pos[-1] < ring.length - 0.0015:
        pos.append(pos[-1] + 0.0009 + 0.0006 * np.sin(6 * np.pi * pos[-1] / ring.length))
    pts = shapely.get_coordinates(shapely.line_interpolate_point(ring, np.array(pos)))
    truth = sh.ellipse_medial_axis(A, B)
    for hint in (None, 0.0002, 0.003):  # estimated, too small, too large
        sk = feature_skeleton(pts, hint)
        assert sk.n_components == 1 and len(sk.end_points) == 2
        assert len(sk.branch_points) == 0
        assert hausdorff(sk.points, truth) < 0.002


def test_disk_like_feature_gives_its_centre():
    square = np.array([[0.0, 0.0], [0.01, 0.0], [0.01, 0.01], [0.0, 0.01]])
    sk = feature_skeleton(square)
    assert sk.points == pytest.approx(np.array([[0.005, 0.005]]))
    assert sk.edges.shape == (0, 2) and sk.radii == pytest.approx([0.005 * np.sqrt(2)])


def test_keep_largest_connected_skeleton():
    big = sh.ellipse_outline(A, B, 0.0005)
    small = sh.ellipse_outline(0.008, 0.003, 0.0005) + [0.0, 0.02]
    both = np.vstack([big, small])  # two traced contours given as one feature
    sk = feature_skeleton(both)
    assert sk.n_components == 1 and np.all(sk.points[:, 1] < 0.01)  # the big one
    sk_all = feature_skeleton(both, keep_largest=False)
    assert sk_all.n_components == 2 and sk_all.length > sk.length
