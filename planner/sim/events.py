"""Events of a simulation run: contacts made/lost, faults, and the end of a run.

Faults never escape :func:`planner.sim.loop.run` as exceptions: they become
:class:`SimEvent` records in ``SimLog.events``; when the run cannot go on, the last event is
``"stopped"`` (or ``"blow_up"``) and the log's ``status``/``reason`` say why.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

__all__ = ["EVENT_KINDS", "SimEvent"]

EVENT_KINDS = (
    "contact_made",
    "contact_lost",
    "object_dropped",
    "joint_limit",
    "jammed",
    "torque_saturated",
    "blow_up",
    "singular",
    "controller_error",
    "stopped",
)
"""The kinds of events worlds and the run loop emit."""


@dataclass(frozen=True)
class SimEvent:
    """One event of a run.

    Attributes:
        t: simulated time of the event [s].
        kind: one of :data:`EVENT_KINDS`.
        message: one human-readable line.
        data: plain values (str, float, int, lists) describing the event.
    """

    t: float
    kind: str
    message: str = ""
    data: dict[str, Any] = field(default_factory=dict)

    def as_dict(self) -> dict[str, Any]:
        """A JSON-ready dict (for ``result.json`` events)."""
        return {"t": float(self.t), "kind": self.kind, "message": self.message, **self.data}
