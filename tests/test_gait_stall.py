"""The gait's stall verdict (:func:`planner.exploration.planar.machine.stall_verdict`): a
gait whose last cycles gave back what they turned ends, unless the phase 1 just run
carried the object on; it is not deferred twice in a row."""

from __future__ import annotations

import math

from hypothesis import given
from hypothesis import strategies as st

from planner.exploration.planar.machine import (
    RESUME_ROTATION,
    STALL_CYCLES,
    STALL_ROTATION,
    stall_verdict,
)
from planner.exploration.planar.result import PhaseRecord


def _records(turns_deg):
    """Phase records of ``turns_deg``: one list of per-phase rotations [deg] per cycle,
    its first entry the phase 1 (clockwise: negative)."""
    out, t = [], 0.0
    for cycle in turns_deg:
        for k, turn in enumerate(cycle):
            out.append(PhaseRecord(k + 1, False, t, t + 1.0, math.radians(turn), 0.0, "x"))
            t += 1.0
    return out


def test_too_few_cycles_are_no_stall():
    assert STALL_CYCLES == 3
    still = [-1.0, 0.5, 0.5]  # a cycle that turns nothing
    assert stall_verdict(_records([still] * 2 + [[-1.0]])) == (False, None)
    recs = _records([still] * 3 + [[-1.0]])
    assert stall_verdict(recs) == (True, None)
    assert stall_verdict(recs[:-1]) == (False, None)  # judged after a phase 1 only


def test_cycles_that_give_back_what_they_turn_stall():
    recs = _records([[-8.7, 0.9, 6.6], [-8.0, 0.9, 5.8], [-11.4, 1.0, 8.0], [-9.0]])
    assert stall_verdict(recs) == (True, None)


def test_a_phase_1_that_carries_the_object_on_defers_the_verdict_once():
    # ball_with_ridge, ridge at 315 deg, seed 2: three cycles of -4.9 deg together, then a
    # phase 1 of -25.2 deg
    head = [[-8.7, 0.9, 6.6], [-8.0, 0.9, 5.8], [-11.4, 1.0, 8.0]]
    recs = _records([*head, [-25.2]])
    stalled, deferred = stall_verdict(recs)
    assert not stalled and deferred == len(recs) - 1
    # phases 2/3 then give the 25 deg back, and the next phase 1 turns 20 deg: the
    # verdict is not deferred again
    recs2 = _records([*head, [-25.2, 1.0, 24.0], [-20.0]])
    assert stall_verdict(recs2, deferred) == (True, deferred)
    # ... but had the cycle kept some of it, the gait goes on
    recs3 = _records([*head, [-25.2, 1.0, 12.0], [-20.0]])
    assert stall_verdict(recs3, deferred) == (False, deferred)


@given(
    st.lists(
        st.tuples(
            st.floats(-30.0, 0.0),
            st.floats(-5.0, 25.0),
            st.floats(-5.0, 25.0),
        ),
        min_size=STALL_CYCLES,
        max_size=8,
    ),
    st.floats(-30.0, 0.0),
    st.booleans(),
)
def test_the_verdict_follows_its_definition(cycles, last, deferred_before):
    recs = _records([*map(list, cycles), [last]])
    starts = [i for i, p in enumerate(recs) if p.phase == 1]
    deferred = starts[-2] if deferred_before else None
    stalled, after = stall_verdict(recs, deferred)
    window = sum(math.radians(sum(c)) for c in cycles[-STALL_CYCLES:])
    resumed = math.radians(abs(last)) >= RESUME_ROTATION
    if abs(window) >= STALL_ROTATION:
        assert not stalled and after == deferred
    elif resumed and not deferred_before:
        assert not stalled and after == starts[-1]
    else:
        assert stalled and after == deferred
