"""Boundary tracing (thesis §4.4.2, Fig. 4.8) and the continue-or-move-on parameter (§4.5.2).

The direction of travel is the intersection of the plane parallel to the nominal surface (the
plate) and the plane orthogonal to the contact normal: ``t = z_plate × n`` projected, i.e.
along the level line of the flank under the contact. A lateral correction keeps the contact
on the outline, the contour where the normal is tilted by ``boundary_tilt`` from the plate
normal (uphill when the tilt is too small, downhill when too large). When the tilt vanishes
the finger has lost the feature: it **re-approaches** it along the last uphill direction and
the re-approach samples are dropped from the boundary. Tracing ends when the loop closes, when
both ends of an open feature are reached (the contact leaves the region: the finger returns
to the start and traces the other way), or when the decision parameter of §4.5.2 turns
negative: ``D = w_info g - w_cost t/T`` with ``g`` the share of recent boundary samples that
are new (farther than 1 mm from the older ones) and ``t/T`` the share of the tracing budget
spent. Returning onto already traced boundary makes ``g`` drop to zero: that is how a closed
loop is recognised.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.exploration.surface.motions import move_to
from planner.exploration.surface.runtime import PHASE

__all__ = ["TraceResult", "trace_boundary"]


@dataclass(frozen=True)
class TraceResult:
    """Outcome of tracing one side of a feature.

    Attributes:
        samples: recorder indices of the boundary samples (re-approach dropped).
        closed: the loop closed; ends: ends of an open outline reached (0-2).
        reason: why tracing stopped.
    """

    samples: np.ndarray
    closed: bool
    ends: int
    reason: str


def _inside(p: np.ndarray, region: np.ndarray, margin: float) -> bool:
    return bool(
        region[0, 0] + margin <= p[0] <= region[0, 1] - margin
        and region[1, 0] + margin <= p[1] <= region[1, 1] - margin
    )


def find_outline(ex, cfg, start, inward, sigma: float, limit: float):
    """Slide from ``start`` along ``inward`` until the tilt reaches the outline's.

    ``sigma`` is +1 when the tilt grows uphill (raised features, steps from below) and -1 when
    it grows downhill (the rim of a pit or ravine, crossed from outside). Returns whether the
    outline was found within ``limit`` [m].
    """
    yield from move_to(ex, start, cfg.speed)
    ex.phase = PHASE["reapproach"]
    target = np.sin(cfg.boundary_tilt)
    p0 = ex.est.uv.copy()
    inward = np.asarray(inward, float) / np.linalg.norm(inward)
    while ex.est.tilt < target:
        if float(np.hypot(*(ex.est.uv - p0))) > limit:
            return False
        yield cfg.trace_speed * inward
    return True


def trace_boundary(ex, cfg, region: np.ndarray, sigma: float, orient: float = 1.0):
    """Trace the outline from where the finger is (on it); see the module doc.

    Returns:
        :class:`TraceResult`.
    """
    target = np.sin(cfg.boundary_tilt)
    r = cfg.tip_radius
    k_start, t_start = ex.rec.n, ex.est.t
    start_uv = ex.est.contact[:2].copy()
    samples: list[int] = []
    tangent = None
    last_up = None
    lost_since = None
    ends, travelled, farthest = 0, 0.0, 0.0
    prev = ex.est.uv.copy()
    reason = "trace budget spent"
    while ex.est.t - t_start < cfg.trace_time:
        n = ex.est.normal
        g = np.array([n[0], n[1]])
        tilt = float(np.hypot(*g))
        travelled += float(np.hypot(*(ex.est.uv - prev)))
        prev = ex.est.uv.copy()
        if tilt > 0.35 * target:
            up = -g / tilt
            last_up, lost_since = up, None
            ex.phase = PHASE["trace"]
            t = orient * np.array([-up[1], up[0]])
            if tangent is not None and float(t @ tangent) < -0.2:
                t = -t  # keep the sense of travel through saddles of the tilt field
            tangent = t
            if abs(tilt - target) < 0.25 * target:
                samples.append(ex.rec.n - 1)
            lateral = np.clip(0.3 * (target - tilt) / target, -0.3, 0.3)
            v = cfg.trace_speed * (t + lateral * sigma * up)
        else:  # lost the feature: re-approach along the last uphill direction
            lost_since = ex.est.t if lost_since is None else lost_since
            ex.phase = PHASE["reapproach"]
            if last_up is None or ex.est.t - lost_since > 2.0:
                reason = "lost the feature"
                break
            v = 0.5 * cfg.trace_speed * sigma * last_up
        c = ex.est.contact[:2]
        farthest = max(farthest, float(np.hypot(*(c - start_uv))))
        if not _inside(c, region, 0.25 * r):
            ends += 1
            ex.event("end_reached", "the outline leaves the region", point=c.tolist())
            if ends == 2:
                reason = "both ends reached"
                break
            yield from move_to(ex, ex.rec.centre[k_start, :2], cfg.speed)
            orient, tangent = -orient, None
            continue
        if farthest > 0.2 * r and travelled > max(2.5 * farthest, 0.5 * r):
            if float(np.hypot(*(c - start_uv))) < 0.15 * r:
                reason = "loop closed"
                break
            if ex.est.k % 25 == 0 and _decision(ex, cfg, samples, t_start) < 0:
                reason = "decision parameter < 0 (no new boundary)"
                break
        yield v
    closed = reason == "loop closed" or reason.startswith("decision")
    return TraceResult(np.array(samples, int), closed and ends == 0, ends, reason)


def _decision(ex, cfg, samples: list[int], t_start: float) -> float:
    """§4.5.2: ``D = w_info g - w_cost (t - t0)/T`` (recorded in ``ex.rec.decision``)."""
    from scipy.spatial import cKDTree

    rec = ex.rec
    if len(samples) < 80:
        return 1.0
    recent = np.array(samples[-40:])
    old = np.array([k for k in samples if rec.t[k] < rec.t[recent[0]] - 0.5])
    if len(old) < 10:
        return 1.0
    d, _ = cKDTree(rec.contact[old, :2]).query(rec.contact[recent, :2])
    gain = float(np.mean(d > 1e-3))
    D = cfg.info_weight * gain - cfg.cost_weight * (ex.est.t - t_start) / cfg.trace_time
    rec.decision[max(rec.n - 1, 0)] = D
    return D
