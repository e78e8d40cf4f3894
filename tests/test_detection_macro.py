"""planner.detection.macro_features: grouping within r_f and Table 3.1 patterns."""

import numpy as np
import pytest

from planner.detection import CurvatureFeature, macro_features
from planner.errors import InvalidParameter

R = 0.01


def _feats(spec):
    """spec: [(sign, start, end)] along the path [m]."""
    return [
        CurvatureFeature(
            sign=s, start=a, end=b, peak=(a + b) / 2, position=np.array([(a + b) / 2, 0.0])
        )
        for s, a, b in spec
    ]


@pytest.mark.parametrize(
    "signs,kind",
    [
        ("-+-", "bump"),
        ("+-+", "pit"),
        ("-+", "step"),
        ("+-", "step"),
        ("+", "cusp"),
        ("-", "cusp"),
        ("-++-", "ridge"),
        ("+--+", "ravine"),
        ("-+-+-", "unknown"),
    ],
)
def test_table_3_1_patterns(signs, kind):
    spec = [(1 if c == "+" else -1, 0.002 * i, 0.002 * i + 0.001) for i, c in enumerate(signs)]
    macros = macro_features(_feats(spec), R)
    assert len(macros) == 1
    assert macros[0].kind == kind
    assert macros[0].signs == signs
    assert macros[0].start == 0.0
    assert len(macros[0].features) == len(signs)


def test_grouping_gap_is_tip_radius():
    near = _feats([(-1, 0.0, 0.001), (1, 0.001 + 0.9 * R, 0.002 + 0.9 * R)])
    far = _feats([(-1, 0.0, 0.001), (1, 0.001 + 1.1 * R, 0.002 + 1.1 * R)])
    assert [m.kind for m in macro_features(near, R)] == ["step"]
    assert [m.kind for m in macro_features(far, R)] == ["cusp", "cusp"]


def test_position_is_mean_of_members_and_order_is_path_order():
    fs = _feats([(1, 0.004, 0.005), (-1, 0.0, 0.001), (-1, 0.008, 0.009)])
    (m,) = macro_features(fs, R)
    assert m.kind == "bump"
    assert np.allclose(m.position, [np.mean([0.0045, 0.0005, 0.0085]), 0.0])


def test_empty_and_bad_inputs():
    assert macro_features([], R) == []
    with pytest.raises(InvalidParameter, match="tip_radius"):
        macro_features(_feats([(1, 0, 0.001)]), 0.0)
    with pytest.raises(InvalidParameter, match="curvature feature"):
        macro_features([object()], R)
