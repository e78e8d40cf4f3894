"""The raster strategy's lines (thesis §4.2): never farther apart than ``line_spacing``,
which (with the run's duration) is bounded so the raster and the record fit in memory."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.exploration import explore_surface
from planner.exploration.surface.result import (
    MAX_DURATION,
    MIN_LINE_SPACING,
    check_duration,
    check_line_spacing,
)
from planner.exploration.surface.strategies import raster
from planner.sim.spatial.plate import Plate, PlateFeature

R = 0.008
DEFAULT = np.array([[-0.02, 0.02], [-0.02, 0.02]])


def _lines(region, spacing, margin):
    return np.array([a[1] for a, _ in raster(np.asarray(region), spacing, margin)])


def test_default_region_and_spacing_closed_form():
    """L = 40 - 2 * 4 = 32 mm at 12 mm: ceil(32/12) + 1 = 4 lines 32/3 mm apart (floor gave
    3 lines 16 mm apart)."""
    v = _lines(DEFAULT, 1.5 * R, 0.5 * R)
    np.testing.assert_allclose(v, [-0.016, -0.016 + 0.032 / 3, 0.016 - 0.032 / 3, 0.016])


@pytest.mark.parametrize(
    ("length", "spacing", "n"), [(0.032, 0.008, 5), (0.032, 0.016, 3), (0.032, 0.032, 1)]
)
def test_a_whole_number_of_spacings_gets_no_extra_line(length, spacing, n):
    region = [[-0.02, 0.02], [-length / 2, length / 2]]
    v = _lines(region, spacing, 0.0)
    assert len(v) == n
    np.testing.assert_allclose(np.diff(v), spacing)


@given(
    length=st.floats(1e-4, 0.1),
    spacing=st.floats(1e-3, 0.05),
    margin=st.floats(0.0, 0.01),
)
def test_lines_are_at_most_spacing_apart_and_fewest(length, spacing, margin):
    region = [[-0.02, 0.02], [0.0, length + 2 * margin]]
    v = _lines(region, spacing, margin)
    assert v.min() >= margin - 1e-12 and v.max() <= length + margin + 1e-12
    if length <= spacing:  # one line in the middle: every point within spacing / 2
        np.testing.assert_allclose(v, [margin + length / 2], atol=1e-12)
        return
    np.testing.assert_allclose([v[0], v[-1]], [margin, margin + length], atol=1e-12)
    gap = float(np.max(np.abs(np.diff(v))))
    assert gap <= spacing * (1 + 1e-9)
    if len(v) > 2:  # one line fewer would leave them farther apart than the spacing
        assert length / (len(v) - 2) > spacing * (1 - 1e-9)


def test_a_bump_between_the_old_lines_is_found():
    """Audit finding 2: a 2 mm bump 6 mm off the v = 0 line of the old 16 mm raster."""
    plate = Plate((PlateFeature("bump", 0.002, 0.003, (0.003, 0.006)),))
    res = explore_surface(plate, speed=0.03, duration=60)
    assert res.status == "ok"
    assert [f.kind for f in res.features] == ["bump"]


def test_ridge_plate_with_a_12_mm_fingertip_is_found():
    """r_f = 12 mm asks for 18 mm: the old two lines 28 mm apart passed either side of the
    bundled ridge_plate ridge."""
    v = _lines(DEFAULT, 1.5 * 0.012, 0.5 * 0.012)
    assert np.diff(v).max() <= 0.018
    ridge = PlateFeature("ridge", 0.002, 0.0018, path=((-0.010, -0.003), (0.010, 0.004)))
    res = explore_surface(Plate((ridge,)), speed=0.03, tip_radius=0.012, duration=60)
    assert res.status == "ok"
    assert [f.kind for f in res.features] == ["ridge"]


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"line_spacing": 1e-12}, r"^line_spacing: expected >= 0.05 r_f = 0.40 mm.*got 1e-12 m"),
        ({"line_spacing": 3.9e-4}, r"^line_spacing: expected >= 0.05 r_f = 0.40 mm"),
        ({"duration": 1e7}, r"^duration: expected at most 600 s \(the recorder.*got 10000000.0 s"),
        ({"duration": 600.5}, r"^duration: expected at most 600 s"),
    ],
)
def test_a_raster_or_a_record_too_large_is_refused(kwargs, match):
    """Audit finding 7: these asked numpy for 3e10 raster lines or 1e10 recorder rows."""
    plate = Plate((PlateFeature("bump", 0.002, 0.003),))
    with pytest.raises(InvalidParameter, match=match):
        explore_surface(plate, **kwargs)


def test_the_bounds_themselves_are_accepted():
    assert check_line_spacing(MIN_LINE_SPACING * R, R) == MIN_LINE_SPACING * R
    assert check_duration(MAX_DURATION) == MAX_DURATION
