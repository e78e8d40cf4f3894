"""Boundary tracing (thesis §4.4.2, Fig. 4.8) and the continue-or-move-on parameter (§4.5.2).

The direction of travel is the intersection of the plane parallel to the nominal surface (the
plate) and the plane orthogonal to the contact normal: ``t ∝ z_plate × n``, the level line of
the flank under the contact. What keeps the finger on the outline is a lateral correction. The
contact *tilt* cannot be servoed: in the concave foot of a feature sharper than the fingertip
the ball touches either the plate (tilt 0) or the flank (tilt ~30°) - an interference point,
§3.2.1 - and the tilt jumps. The fingertip centre's height above the plate is continuous (the
traced surface): the finger keeps its centre ``boundary_rise`` above (or below, for a pit or a
ravine) the plate level where it started, so the outline traced is a level line of the traced
surface, and the feature's skeleton (the medial axis is shared by the offset curves) is
unchanged. Samples far from that level (re-approach after losing the feature) are dropped.

Tracing ends when the loop closes, when both ends of an open feature are reached (the contact
leaves the region: the finger returns to the start and traces the other way), or when the
decision parameter of §4.5.2 turns negative: ``D = w_info g - w_cost t/T`` with ``g`` the share
of recent boundary samples that are new (farther than 1 mm from the older ones) and ``t/T``
the share of the tracing budget spent; coming back onto traced boundary makes ``g`` drop to 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.exploration.surface.motions import move_to
from planner.exploration.surface.runtime import PHASE

__all__ = ["Outline", "TraceResult", "find_outline", "trace_boundary"]


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


@dataclass(frozen=True)
class Outline:
    """Where the approach met the feature.

    Attributes:
        level: centre height to keep [m]; sigma: +1 raised from this side, -1 sunken.
        rise: distance of ``level`` from the plate level [m].
        inward: (2,) direction of the approach [-].
    """

    level: float
    sigma: float
    inward: np.ndarray
    rise: float = 2.5e-4


def _inside(p: np.ndarray, region: np.ndarray, margin: float) -> bool:
    return bool(
        region[0, 0] + margin <= p[0] <= region[0, 1] - margin
        and region[1, 0] + margin <= p[1] <= region[1, 1] - margin
    )


def find_outline(ex, cfg, start, inward, limit: float, rise: float | None = None):
    """Slide from ``start`` along ``inward`` until the centre leaves the plate level by
    ``boundary_rise``; returns an :class:`Outline` or None (not met within ``limit`` [m])."""
    yield from move_to(ex, start, cfg.speed)
    ex.phase = PHASE["reapproach"]
    inward = np.asarray(inward, float) / np.linalg.norm(inward)
    ref = []
    for _ in range(30):  # the plate level here
        ref.append(ex.est.centre[2])
        yield np.zeros(2)
    w0 = float(np.mean(ref))
    p0 = ex.est.uv.copy()
    rise = cfg.boundary_rise if rise is None else rise
    while abs(ex.est.centre[2] - w0) < rise:
        if float(np.hypot(*(ex.est.uv - p0))) > limit:
            return None
        yield cfg.trace_speed * inward
    sigma = 1.0 if ex.est.centre[2] > w0 else -1.0
    return Outline(w0 + sigma * rise, sigma, inward, rise)


def trace_boundary(ex, cfg, region: np.ndarray, outline: Outline, orient: float = 1.0):
    """Trace the level line ``outline.level`` of the centre from where the finger is.

    Returns:
        :class:`TraceResult`.
    """
    r, rise = cfg.tip_radius, outline.rise
    k_start, t_start = ex.rec.n, ex.est.t
    start_uv = ex.est.uv.copy()
    samples: list[int] = []
    tangent = None
    into = outline.inward.copy()  # direction towards the feature (2,)
    ends, travelled, farthest = 0, 0.0, 0.0
    prev = ex.est.uv.copy()
    reason = "trace budget spent"
    while ex.est.t - t_start < cfg.trace_time:
        n = ex.est.normal
        g = np.array([n[0], n[1]])
        tilt = float(np.hypot(*g))
        travelled += float(np.hypot(*(ex.est.uv - prev)))
        prev = ex.est.uv.copy()
        if tilt > 0.03:  # the contact is on the feature: the uphill direction is known
            up = -g / tilt
            into = outline.sigma * up
        t = orient * np.array([-into[1], into[0]])
        if tangent is not None and float(t @ tangent) < -0.2:
            t = -t  # keep the sense of travel through saddles of the tilt field
        tangent = t
        err = outline.sigma * (outline.level - ex.est.centre[2]) / rise
        lateral = float(np.clip(0.8 * err, -0.7, 0.7))
        on = abs(err) < 0.5
        ex.phase = PHASE["trace"] if abs(err) < 2.0 else PHASE["reapproach"]
        if on:
            samples.append(ex.rec.n - 1)
        v = cfg.trace_speed * ((t if abs(err) < 2.0 else 0.3 * t) + lateral * into)
        c = ex.est.uv
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
            if float(np.hypot(*(c - start_uv))) < 0.1 * r:
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
    d, _ = cKDTree(rec.centre[old, :2]).query(rec.centre[recent, :2])
    gain = float(np.mean(d > 1e-3))
    D = cfg.info_weight * gain - cfg.cost_weight * (ex.est.t - t_start) / cfg.trace_time
    rec.decision[max(rec.n - 1, 0)] = D
    return D
