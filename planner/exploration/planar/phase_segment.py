"""The references of one phase: the :class:`Segment` the phase planners build
(:mod:`.segments`, :mod:`.outline_segments`, :mod:`.corner_probe`) and the controller
follows (:mod:`.controller`, its compiled loop :mod:`.gait_loop`), and their values at one
instant as the controller kernel reads them (:func:`references`)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass


@dataclass
class Segment:
    """The references of one phase (all callables of the time since the phase start [s]).

    Attributes:
        kind: 1, 2 or 3 (Fig. 2.3).
        duration: planned duration [s] ("path finished" after it).
        pose: ``t -> (x, y, theta), (vx, vy, omega)`` object references (phase 1).
        rolling: ``t -> (u_des, s_right_des, phi_des (2,), phid_des (2,))``: fingertip
            contact locations [m] and orientations [rad, rad/s] (phase 1 and the holding
            finger).
        explore: ``t -> (p_des (2,), v_des (2,), phi_des)`` of the exploring finger.
        hold_force: ``t -> internal / holding force [N]``.
        explore_force: ``t -> exploring normal force [N]``.
        theta0: object rotation estimate at the phase start [rad].
        contact_target: where on the exploring pad its contact is held [m] (tactile
            centroid ``u``; a PI on the pad's orientation, ``controller_kernel``'s contact
            servo), or None: the pad's orientation follows ``explore`` alone.
        target: world polar angle [rad] about the estimated centre where the explorer's
            contact ends (phases 2/3: the regrasp; :mod:`.prior_track` compares it with the
            prior's handoff), or None (phase 1).
    """

    kind: int
    duration: float
    pose: Callable | None = None
    rolling: Callable | None = None
    explore: Callable | None = None
    hold_force: Callable | None = None
    explore_force: Callable | None = None
    theta0: float = 0.0
    contact_target: float | None = None
    target: float | None = None


_NO_POSE = (0.0,) * 7
_NO_ROLL = (0.0,) * 7
_NO_EXPLORE = (0.0,) * 6
_NO_FORCE = (0.0, 0.0)


def references(seg: Segment, tl: float) -> tuple:
    """The segment's references at phase time ``tl`` [s] as the floats of ``sv`` (layout
    ``V_HAS_POSE`` .. ``V_FNT`` of :mod:`.controller_kernel`)."""
    if seg.pose is None:
        pose = _NO_POSE
    else:
        (x, y, a), (vx, vy, w) = seg.pose(tl)
        pose = (1.0, x, y, a, vx, vy, w)
    if seg.rolling is None:
        roll = _NO_ROLL
    else:
        u_des, s_des, (p0, p1), (w0, w1) = seg.rolling(tl)
        roll = (1.0, u_des, s_des, p0, p1, w0, w1)
    if seg.explore is None:
        explore = _NO_EXPLORE
    else:
        (px, py), (vx, vy), phi = seg.explore(tl)
        explore = (1.0, px, py, vx, vy, phi)
    force = _NO_FORCE if seg.explore_force is None else (1.0, seg.explore_force(tl))
    return (*pose, *roll, *explore, *force)


__all__ = ["Segment", "references"]
