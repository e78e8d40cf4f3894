"""Tests of 2-D curvature-feature maps, macro classification (Table 3.1) and multiscale."""

import numpy as np
import pytest

from planner.errors import InvalidParameter
from planner.geometry.features import curvature_feature_map, multiscale_feature_maps
from planner.geometry.surfaces import grid_principal_curvatures

X = np.linspace(-1, 1, 161)
GX, GY = np.meshgrid(X, X, indexing="ij")

CASES = {
    "bump": (1 / (1 + 15 * (GX**2 + GY**2)), 1.0),
    "pit": (-1 / (1 + 15 * (GX**2 + GY**2)), 1.0),
    "ridge": (0.3 * np.exp(-(GX**2) / (2 * 0.1**2)), 0.2),
    "ravine": (-0.3 * np.exp(-(GX**2) / (2 * 0.1**2)), 0.2),
    "step": (0.2 * (1 + np.tanh(GX / 0.1)) / 2, 0.5),
    "cusp": (-(np.sqrt(GX**2 + 0.02**2) - 0.02), 0.2),
}


@pytest.mark.parametrize("kind", sorted(CASES))
def test_table_3_1_classification(kind):
    z, rf = CASES[kind]
    k1, k2 = grid_principal_curvatures(X, X, z)
    fm = curvature_feature_map(X, X, k1, k2, rf)
    assert [m.kind for m in fm.macros] == [kind]


def test_bump_regions_match_fig_3_7():
    z, rf = CASES["bump"]
    k1, k2 = grid_principal_curvatures(X, X, z)
    fm = curvature_feature_map(X, X, k1, k2, rf)
    pos = [r for r in fm.regions if r.sign > 0]
    neg = [r for r in fm.regions if r.sign < 0]
    assert len(pos) == 1 and len(neg) == 1  # a + cap inside a - ring
    assert pos[0].peak_curvature == pytest.approx(30.0, rel=0.05)
    np.testing.assert_allclose(pos[0].centroid, 0.0, atol=1e-9)
    # the + region is where the larger-magnitude principal curvature of eq. 3.17 exceeds 1
    u = np.linspace(0, 1, 100_001)
    d = 1 + 15 * u**2
    c = np.sqrt(1 + 4 * 225 * u**2 / d**4)
    kr = 2 * 15 * d * (1 - 45 * u**2) / (c * (d**4 + 900 * u**2))
    kc = 30 / (c * d**2)
    k_big = np.where(np.abs(kr) >= np.abs(kc), kr, kc)
    u_cap = u[np.argmax(k_big <= 1.0)]
    assert pos[0].area == pytest.approx(np.pi * u_cap**2, rel=0.05)
    assert neg[0].second_curvature > 0  # the ring is a saddle: k2 > 0
    assert (
        fm.macro_labels.max() == 1
        and (fm.macro_labels > 0).sum() == ((fm.positive > 0) | (fm.negative > 0)).sum()
    )


def test_far_apart_features_are_separate_macros():
    z = 0.2 * np.exp(-((GX + 0.6) ** 2) / (2 * 0.05**2)) + 0.2 * np.exp(
        -((GX - 0.6) ** 2) / (2 * 0.05**2)
    )
    k1, k2 = grid_principal_curvatures(X, X, z)
    assert [m.kind for m in curvature_feature_map(X, X, k1, k2, 0.1).macros] == ["ridge", "ridge"]
    # with a big tip the two ridges are within r_f of each other: one macro, no Table 3.1 name
    (macro,) = curvature_feature_map(X, X, k1, k2, 1.0).macros
    assert macro.kind == "unknown" and len(macro.members) == 6


def test_directions_are_reported():
    z, rf = CASES["ridge"]
    k1, k2 = grid_principal_curvatures(X, X, z)
    p1 = np.broadcast_to([1.0, 0.0, 0.0], k1.shape + (3,))
    p2 = np.broadcast_to([0.0, 1.0, 0.0], k1.shape + (3,))
    fm = curvature_feature_map(X, X, k1, k2, rf, p1=p1, p2=p2)
    np.testing.assert_allclose(fm.regions[0].direction, [1.0, 0.0, 0.0])


def test_multiscale_hides_narrow_features_from_big_tips():
    z = -0.3 * np.exp(-(GX**2) / (2 * 0.03**2))  # a groove narrower than the tip
    small, big = multiscale_feature_maps(X, X, z, 0.05, [0.05, 0.5])
    assert any(r.sign < 0 for r in small.regions)
    assert len(big.regions) <= len(small.regions) + 2
    with pytest.raises(InvalidParameter, match=">= tip_radius"):
        multiscale_feature_maps(X, X, z, 0.1, [0.05])


@pytest.mark.parametrize(
    ("args", "match"),
    [
        ((X, X, np.zeros((3, 3)), np.zeros((3, 3)), 1.0), "shape"),
        ((X, X, np.zeros((161, 161)), np.zeros((161, 161)), 0.0), "tip_radius"),
        ((X, X, np.full((161, 161), np.nan), np.zeros((161, 161)), 1.0), "finite"),
    ],
)
def test_bad_input(args, match):
    with pytest.raises(InvalidParameter, match=match):
        curvature_feature_map(*args)
