"""planner.checks: every validator returns the converted value or one clear InvalidParameter."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner import checks
from planner.errors import InvalidParameter


def test_positive_converts_and_names_unit():
    assert checks.positive("tip_radius", "0.008", "m") == pytest.approx(0.008)
    with pytest.raises(InvalidParameter, match=r"tip_radius: expected a finite number > 0 \[m\]"):
        checks.positive("tip_radius", -0.008, "m")
    with pytest.raises(InvalidParameter, match="boolean"):
        checks.positive("mass", True, "kg")


@pytest.mark.parametrize("bad", [math.nan, math.inf, 0.0, "x", None])
def test_positive_rejects(bad):
    with pytest.raises(InvalidParameter, match="mass"):
        checks.positive("mass", bad, "kg")


def test_positive_options():
    assert checks.positive("mu", 0.0, allow_zero=True) == 0.0
    assert checks.positive("h", math.inf, allow_inf=True) == math.inf
    assert checks.nonnegative("noise", 0) == 0.0
    with pytest.raises(InvalidParameter):
        checks.nonnegative("noise", -1e-9)


def test_in_range_ends():
    assert checks.in_range("a", 1.0, 0.0, 1.0) == 1.0
    with pytest.raises(InvalidParameter, match=r"a number in \(0, 1\)"):
        checks.in_range("a", 1.0, 0.0, 1.0, closed=(False, False))
    with pytest.raises(InvalidParameter):
        checks.in_range("a", math.nan, 0.0, 1.0)


def test_integer_and_choice():
    assert checks.integer("n", 3.0, minimum=2) == 3
    for bad in (2.5, 1, False, "three"):
        with pytest.raises(InvalidParameter, match="n: expected an integer >= 2"):
            checks.integer("n", bad, minimum=2)
    assert checks.choice("solver", "daqp", ("osqp", "daqp")) == "daqp"
    with pytest.raises(InvalidParameter, match=r"\['osqp', 'daqp'\]"):
        checks.choice("solver", "cvx", ("osqp", "daqp"))


def test_arrays():
    v = checks.vector("q", [1, 2, 3], 3, "rad")
    assert v.dtype == float and v.shape == (3,)
    with pytest.raises(InvalidParameter, match=r"q: expected shape \(3,\) \[rad\]"):
        checks.vector("q", [1, 2], 3, "rad")
    arr, single = checks.batch("q", [1.0, 2.0], 2)
    assert single and arr.shape == (1, 2)
    p = checks.points("centers", np.zeros((5, 2)), min_count=4)
    assert p.shape == (5, 2)
    bad = np.zeros((5, 2))
    bad[3, 1] = np.nan
    with pytest.raises(InvalidParameter, match="centers: row 3 is not finite"):
        checks.points("centers", bad)
    with pytest.raises(InvalidParameter, match="at least 10 rows"):
        checks.points("centers", np.zeros((5, 2)), min_count=10)
    s = checks.series("t", [0.0, 1.0, 2.0], n=3)
    assert s.shape == (3,)
    with pytest.raises(InvalidParameter, match="t: sample 1 is not finite"):
        checks.series("t", [0.0, np.inf])


def test_shown_values_stay_on_one_short_line():
    """Messages quote short values as their repr, long ones by type and size."""
    assert checks.shown(-0.008) == "-0.008"
    assert checks.shown("abc") == "'abc'"
    assert checks.shown(np.zeros((200, 2))) == "an array of shape (200, 2)"
    assert checks.shown(list(range(40))) == "a list of 40 items"
    long_text = checks.shown("x" * 500)
    assert len(long_text) == checks.SHOWN_LENGTH and long_text.endswith("...")
    with pytest.raises(InvalidParameter) as err:
        checks.positive("mu", np.ones(50))
    assert str(err.value) == "mu: expected a finite number > 0, got an array of shape (50,)"
