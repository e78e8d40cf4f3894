"""The phase machine's second phase 2 on a posed outline (machine._Runner._next): a phase 2
planned from a rejected pose fit (the object still moving after phase 1) is planned again
once the outline is posed, once."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from planner.exploration.planar.machine import _Runner


def _runner(fit_now: bool, posed_at_start: bool, again: bool = False, eps: float = 1.0):
    r = _Runner.__new__(_Runner)
    est = SimpleNamespace()
    r.world = SimpleNamespace(time=1.5, observe=lambda: None)
    r.ctrl = SimpleNamespace(sensing=SimpleNamespace(update=lambda obs, source: est))
    r.shape = SimpleNamespace(update=lambda e, theta: fit_now,
                              right_palm_epsilon=lambda e, mu: eps)  # fmt: skip
    r.s = SimpleNamespace(mu=1.0, min_epsilon=0.05)
    r.theta, r.events = 0.0, []
    r._posed, r._again = posed_at_start, again
    return r, est


def test_phase_2_from_a_rejected_fit_runs_again_once():
    r, est = _runner(fit_now=True, posed_at_start=False)
    assert r._next(2, "path finished", est) == (2, False)
    assert r._again and r.events[-1]["kind"] == "replan"
    # the repeated phase 2 (its start fit rejected again) goes on as the cycle says
    r._posed = False
    assert r._next(2, "path finished", est) == (3, False)


@pytest.mark.parametrize(("fit_now", "posed"), [(True, True), (False, False), (False, True)])
def test_no_second_phase_2_otherwise(fit_now, posed):
    """Planned from a used fit, or the outline still not posed: the cycle (phase 3, or
    transition 4 when the right-palm hold is not stable)."""
    r, est = _runner(fit_now=fit_now, posed_at_start=posed)
    assert r._next(2, "path finished", est) == (3, False)
    r, est = _runner(fit_now=fit_now, posed_at_start=posed, eps=0.0)
    assert r._next(2, "path finished", est) == (1, True)
    assert r.events[-1]["kind"] == "transition_4"
