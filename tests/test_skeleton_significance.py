"""Significance pruning of the medial axis (planner.skeleton.significance): closed forms."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.skeleton import feature_skeleton
from planner.skeleton.significance import peel_insignificant


def _ellipse(a: float, b: float, n: int = 800) -> np.ndarray:
    t = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    return np.column_stack([a * np.cos(t), b * np.sin(t)])


def _stadium(half: float, rho: float, step: float = 5e-5) -> np.ndarray:
    """Outline of the points within ``rho`` of the segment (-half, 0)-(half, 0) [m]."""
    n_line = int(2 * half / step)
    n_cap = int(np.pi * rho / step)
    x = np.linspace(-half, half, n_line, endpoint=False)
    t = np.linspace(-np.pi / 2, np.pi / 2, n_cap, endpoint=False)
    return np.vstack(
        [
            np.column_stack([x, -rho + 0 * x]),
            np.column_stack([half + rho * np.cos(t), rho * np.sin(t)]),
            np.column_stack([-x, rho + 0 * x]),
            np.column_stack([-half - rho * np.cos(t), -rho * np.sin(t)]),
        ]
    )


def test_path_with_constant_radius_loses_exactly_the_trimmed_length():
    """Disks of equal radius along a line: peeling a length L moves the union by L."""
    pts = np.column_stack([np.linspace(0.0, 0.01, 101), np.zeros(101)])
    edges = np.column_stack([np.arange(100), np.arange(1, 101)])
    keep = peel_insignificant(pts, edges, np.full(101, 0.003), 0.00105)
    kept = pts[keep, 0]
    assert kept.min() == pytest.approx(0.001, abs=1e-9)
    assert kept.max() == pytest.approx(0.009, abs=1e-9)


def test_spur_of_a_small_dent_is_peeled_the_axis_is_not():
    """A side branch whose disks the main axis covers to within the tolerance goes."""
    main = np.column_stack([np.linspace(0.0, 0.01, 101), np.zeros(101)])
    spur = np.column_stack([np.full(10, 0.005), np.linspace(1e-4, 1e-3, 10)])
    pts = np.vstack([main, spur])
    radii = np.concatenate([np.full(101, 0.003), 0.003 - np.linspace(1e-4, 1e-3, 10) * 0.9])
    edges = np.vstack(
        [
            np.column_stack([np.arange(100), np.arange(1, 101)]),
            [[50, 101]],
            np.column_stack([np.arange(101, 110), np.arange(102, 111)]),
        ]
    )
    keep = peel_insignificant(pts, edges, radii, 2e-4)
    assert not keep[101:].any()  # spur significance 0.1 * 1 mm = 0.1 mm < 0.2 mm
    assert keep[2:99].all()  # the axis is only trimmed at its ends, by <= 0.2 mm


@pytest.mark.parametrize(("a", "b"), [(0.005, 0.0049), (0.006, 0.0058), (0.004, 0.0037)])
def test_near_circular_ellipse_collapses_when_tolerance_exceeds_a_minus_b(a, b):
    """An ellipse's axis is the segment |x| <= a - b^2/a; all of it lies within a - b of the
    centre disk (closed form), so a tolerance above a - b leaves the centre only."""
    sk_full = feature_skeleton(_ellipse(a, b))
    half = a - b * b / a
    assert np.abs(sk_full.points[:, 0]).max() == pytest.approx(half, rel=0.25)
    sk = feature_skeleton(_ellipse(a, b), min_significance=1.2 * (a - b))
    assert np.abs(sk.points[:, 0]).max() < 0.25 * half + 1e-5
    sk_keep = feature_skeleton(_ellipse(a, b), min_significance=0.2 * (a - b))
    assert np.abs(sk_keep.points[:, 0]).max() > 0.5 * half


@settings(max_examples=15, deadline=None)
@given(
    radius=st.floats(0.003, 0.008),
    noise=st.floats(1e-5, 4e-5),
    seed=st.integers(0, 1000),
)
def test_noisy_circle_skeleton_stays_at_the_centre(radius, noise, seed):
    """The pruned DVMA of a noisy circle wanders; with the significance stage at 4 sigma it
    stays within a few sigma of the centre (the medial axis of a circle is its centre)."""
    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0, 2 * np.pi, 1200))
    r = radius + rng.normal(0, noise, t.size)
    pts = np.column_stack([r * np.cos(t), r * np.sin(t)])
    sk = feature_skeleton(pts, min_significance=4 * noise + 2e-5)
    assert np.hypot(*sk.points.T).max() < 8 * noise + 1e-4


def test_stadium_axis_is_kept_within_the_tolerance():
    """A stadium's axis is its segment (closed form); pruning shortens it by at most the
    tolerance at each end and removes every fork into the end caps."""
    half, rho, tol = 0.006, 0.003, 2e-4
    rng = np.random.default_rng(1)
    pts = _stadium(half, rho)
    pts = pts + rng.normal(0, 1.5e-5, pts.shape)
    sk = feature_skeleton(pts, min_significance=tol)
    assert np.abs(sk.points[:, 1]).max() < 0.1 * rho  # no branch into the caps
    assert sk.points[:, 0].min() < -half + tol + 1e-4
    assert sk.points[:, 0].max() > half - tol - 1e-4
    assert len(sk.end_points) == 2


def test_default_is_off_and_bad_tolerance_is_rejected():
    pts = _ellipse(0.005, 0.0045)
    assert "significance" not in feature_skeleton(pts).stage_edges
    with pytest.raises(InvalidParameter, match="min_significance"):
        feature_skeleton(pts, min_significance=-1e-4)
