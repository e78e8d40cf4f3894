"""Feature and global skeletons of the traced features (thesis §4.4.3, §4.5.3).

* Closed outlines (bumps, pits, closed ridges): the pruned DVMA of the boundary samples
  (thinned to the tracer's lateral accuracy, :func:`thin_samples`)
  (:func:`planner.skeleton.feature_skeleton`), with the significance pruning at the
  tracer's lateral accuracy (:data:`SIGNIFICANCE`): the traced outline is a smooth level
  line whose samples are kept within ``ACCEPT_LATERAL`` of it, and the medial axis of a
  near-circle known that well wanders by several times as much (a bump's skeleton is a
  point).
* Open features traced on both sides (ridges, ravines reaching the region's edges): the
  medial axis between the two sides - the DVMA of both sides' samples, pruned to its
  largest connected part (Fig. 4.13); if the skeleton library cannot build it (the samples
  enclose no area), the midpoints between each sample and the nearest one of the other side.
* Features traced *along* (steps, cusps): the pseudo-skeleton, the traced path itself.
* The global skeleton of all features (Fig. 4.15) and the §4.5.3 region report
  (:func:`planner.skeleton.global_skeleton`, :func:`planner.skeleton.region_report`).
"""

from __future__ import annotations

import numpy as np

from planner.errors import HapexError
from planner.exploration.surface.tracing import ACCEPT_LATERAL

__all__ = ["SIGNIFICANCE", "THIN", "feature_model", "global_model", "thin_samples"]

#: what the medial disks may move when pruning [m]: samples on opposite sides of the outline
#: are each within ``ACCEPT_LATERAL`` of it
SIGNIFICANCE = 2.0 * ACCEPT_LATERAL
#: closest two boundary samples kept for the DVMA [m]: half the tracer's lateral band
#: (kept samples lie within ``ACCEPT_LATERAL`` of the level line, so two laps interleave
#: within it); thinning to the whole band (0.15 mm) left the boundary too sparse where the
#: finger went round once and broke a 3 mm ridge's axis at one end, while 0.05-0.1 mm
#: gave the same skeletons (checked on four outlines of both plate sets)
THIN = 0.5 * ACCEPT_LATERAL


def thin_samples(points: np.ndarray, spacing: float = THIN) -> np.ndarray:
    """The samples (N, 2) [m], in their order, without those closer than ``spacing`` [m] to
    an earlier kept one.

    The DVMA's pruning (§4.4.3) relies on "a minimum distance between samples at the
    boundary" set by the finger's speed and the sampling rate; a traced outline breaks
    that assumption where the finger went round twice (closing the loop, filling a hole)
    and the two laps, a fraction of ``ACCEPT_LATERAL`` apart, interleave: the Voronoi
    edges between them fall to the edge-length and generator-distance tests and the medial
    axis breaks into pieces (a 16 mm ravine's skeleton reduced to a point, 8 mm from its
    ends). Samples closer than the tracer's lateral accuracy carry no more shape."""
    from scipy.spatial import cKDTree

    P = np.asarray(points, float)
    if len(P) < 3:
        return P
    near = cKDTree(P).query_ball_point(P, spacing)
    keep = np.ones(len(P), bool)
    for i, js in enumerate(near):
        if keep[i]:
            for j in js:
                if j > i:
                    keep[j] = False
    return P[keep]


#: thinning distances tried for a closed outline's DVMA [m] (around :data:`THIN`)
THINNINGS = (2.0 / 3.0 * THIN, THIN, 4.0 / 3.0 * THIN)


def _closed_skeleton(samples: np.ndarray):
    """The pruned DVMA of a closed outline's samples, thinned (:func:`thin_samples`) at each
    of :data:`THINNINGS`; the longest skeleton without a loop is kept (the longest of all
    when each has one).

    The edge-length and generator tests of the DVMA's pruning can drop one medial-axis edge
    where the thinned samples happen to sit unevenly; the axis then falls into pieces and
    only the largest is kept (a 16 mm ravine's skeleton 5 mm long, 7 mm off at one end, at
    one thinning, whole at the neighbouring ones). The outline's medial axis is the same at
    every thinning, so the skeleton that lost least of it is kept; spurs do not make one
    longer (the significance pruning removes them), a loop might, hence loops last."""
    from planner.skeleton import feature_skeleton

    best, key = None, None
    for d in THINNINGS:
        try:
            sk = feature_skeleton(thin_samples(samples, d), min_significance=SIGNIFICANCE)
        except HapexError:
            continue
        k = (not sk.has_loop, float(sk.length))
        if key is None or k > key:
            best, key = sk, k
    if best is None:
        return feature_skeleton(thin_samples(samples), min_significance=SIGNIFICANCE)
    return best


def _midline(a: np.ndarray, b: np.ndarray):
    from scipy.spatial import cKDTree

    from planner.skeleton import pseudo_skeleton

    _, j = cKDTree(b).query(a)
    mid = 0.5 * (a + b[j])
    d = np.diff(a, axis=0)
    main = d.sum(axis=0)
    order = np.argsort(mid @ (main / max(np.linalg.norm(main), 1e-12)))
    return pseudo_skeleton(mid[order])


def feature_model(kind: str, sides: list[np.ndarray], closed: bool):
    """The skeleton of one feature from its traced sides ((N_i, 2) samples [m]); None when
    fewer than 4 samples were traced."""
    from planner.skeleton import pseudo_skeleton

    sides = [np.asarray(s, float) for s in sides if len(s) >= 2]
    if not sides or sum(len(s) for s in sides) < 4:
        return None
    try:
        if closed:
            return _closed_skeleton(np.vstack(sides))
        if kind in ("step", "cusp") or len(sides) == 1:
            return pseudo_skeleton(sides[0])
        if len(sides) >= 2:
            return _midline(sides[0], sides[1])
    except HapexError:
        return pseudo_skeleton(sides[0]) if len(sides[0]) >= 2 else None
    return None


def global_model(boundaries: list[np.ndarray], tip_radius: float):
    """``(global_skeleton, region_report)`` of the features' boundary samples; ``(None, ())``
    with fewer than two traced features."""
    from planner.skeleton import global_skeleton, region_report

    bnd = [np.asarray(b, float) for b in boundaries if len(b) >= 4]
    if len(bnd) < 2:
        return None, ()
    try:
        gs = global_skeleton(bnd)
        return gs, tuple(region_report(gs, tip_radius))
    except HapexError:
        return None, ()
