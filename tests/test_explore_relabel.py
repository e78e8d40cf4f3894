"""A kind changed by the traced outline (refine_with_outline) is an event, so the events
and the result agree (audit finding 9: ridge_plate's events said bump, its result ridge)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from planner.exploration.surface.identify import TypeDecision
from planner.exploration.surface.program import FeatureRecord, relabel


class _Ex:
    """The explorer's recorder rows and event list, as relabel reads and writes them."""

    def __init__(self, outline: np.ndarray) -> None:
        centre = np.column_stack([outline, np.zeros(len(outline))])
        self.rec = SimpleNamespace(centre=centre)
        self.events: list[tuple[str, str, dict]] = []

    def event(self, etype: str, message: str, **data) -> None:
        self.events.append((etype, message, data))


def _stadium(half: float, radius: float, n: int = 400) -> np.ndarray:
    """(n, 2) a closed stadium outline: axis 2 ``half`` long, ``radius`` wide [m]."""
    t = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    x = np.clip(np.cos(t) * (half + radius), -half, half)
    # the caps: a circle of ``radius`` about each end of the axis
    cap = np.abs(np.cos(t) * (half + radius)) > half
    x = np.where(cap, np.sign(np.cos(t)) * half + radius * np.cos(t), x)
    return np.column_stack([x, radius * np.sin(t)])


def _record(outline: np.ndarray, kind: str) -> FeatureRecord:
    scores = {k: (0.9 if k == kind else 0.02) for k in ("bump", "pit", "ridge", "ravine")}
    dec = TypeDecision(kind, 0.9, scores, ("crossings",))
    rec_f = FeatureRecord(dec, np.zeros(2), np.array([1.0, 0.0]), closed=True)
    rec_f.sides.append(np.arange(len(outline)))
    return rec_f


def test_a_thin_closed_outline_relabels_a_bump_a_ridge_with_an_event():
    """ridge_plate's case: the crossings said bump; the outline, 24 mm by 6 mm, is a
    ridge's. The event carries both kinds, the record the new one."""
    outline = _stadium(0.009, 0.003)
    ex, rec_f = _Ex(outline), _record(outline, "bump")
    relabel(ex, rec_f)
    assert rec_f.decision.kind == "ridge"
    ((kind, message, data),) = ex.events
    assert kind == "feature_relabelled"
    assert data == {"kind": "ridge", "was": "bump"}
    assert message.startswith("bump (0.90) -> ridge (")


def test_a_round_closed_outline_keeps_the_bump_without_an_event():
    t = np.linspace(0.0, 2 * np.pi, 400, endpoint=False)
    outline = 0.004 * np.column_stack([np.cos(t), np.sin(t)])
    ex, rec_f = _Ex(outline), _record(outline, "bump")
    relabel(ex, rec_f)
    assert rec_f.decision.kind == "bump"
    assert ex.events == []
