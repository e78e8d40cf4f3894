"""Feature type identification by crossing motions (thesis §4.4.1, Fig. 4.7 extended).

Fig. 4.7 tells a cusp, a step and a ridge apart by the curvature features met on one crossing
(one convex feature: cusp; a concave then a convex one: step; concave-convex-concave: ridge).
One crossing cannot tell the six macro types of Table 3.1 apart: a ridge and a bump both read
``-+-`` across, a ravine and a pit ``+-+``. The extension adds the motions that disambiguate:

1. **across**: after the search has met a feature, cross it again at right angles to its axis
   (estimated from the contact normals of the search crossing: on a ridge's flanks the
   normal's horizontal tilt points across it whatever the crossing direction; on a bump it is
   radial and averages to the chord direction, so the perpendicular through the chord's
   middle runs through the top), centred on the feature;
2. **along**: cross it along its axis through its middle.

Cues read from each crossing (fingertip centres in the plate frame):

* ``relief``: rise of the centre above the line joining the crossing's end levels minus its
  dip below it - raised (ridge, bump, cusp), sunken (ravine, pit) or flat;
* ``level_change``: end level minus start level - only a step changes level (and more than
  it rises or dips in between: the tails of a wide pit cut short change level too);
* ``feet``: the curvature pattern has concave features on both sides of a convex one
  (``-+-``, Fig. 4.7's ridge) - a cusp has none (it is a crease between two planes);
* ``crease``: the plate falls away on both sides at the ends of the crossing (a cusp's flanks
  are planes tilted by its half-angle; the plate around a ridge is level);
* ``width`` (along): a raised or sunken part much longer along than across is elongated, flat
  along like a ridge (a finite ridge drops at its end caps when the along crossing is longer
  than the ridge; a bump is as wide along as across).

Across the kinds predict (relief, step, feet, crease) and along the relief:

======  ======  =====  ====  ======  =====
kind    relief  step   feet  crease  along
======  ======  =====  ====  ======  =====
bump    up      no     any   no      up
pit     down    no     any   no      down
ridge   up      no     yes   no      flat
ravine  down    no     any   no      flat
step    flat    yes    any   no      flat
cusp    up      no     no    yes     flat
======  ======  =====  ====  ======  =====

Confidence: every cue agrees with a kind's prediction with probability :data:`P_CUE` (the
feet cue, which noise and shallow feet make less reliable, :data:`P_FEET`); with a uniform
prior the posterior over the six kinds is the confidence reported per kind.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = [
    "KINDS",
    "PREDICTIONS",
    "END_FRACTION",
    "Crossing",
    "TypeDecision",
    "crossing_axis",
    "evidence",
    "feature_width",
    "flow_chart_next",
    "identify",
    "level_change",
    "outline_elongation",
    "outline_thinness",
    "refine_with_outline",
    "relief",
]

KINDS = ("bump", "pit", "ridge", "ravine", "step", "cusp")
#: kind -> (relief across, step, feet, crease, relief along); None = either
PREDICTIONS = {
    "bump": ("up", False, None, False, "up"),
    "pit": ("down", False, None, False, "down"),
    "ridge": ("up", False, True, False, "flat"),
    "ravine": ("down", False, None, False, "flat"),
    "step": ("flat", True, None, False, "flat"),
    "cusp": ("up", False, False, True, "flat"),
}
P_CUE, P_FEET = 0.9, 0.75
#: share of a crossing's samples at each end whose heights are its end levels (the plate on
#: either side: :func:`level_change`, :func:`relief`, :func:`feature_width`) [-]
END_FRACTION = 0.15


@dataclass(frozen=True)
class Crossing:
    """Evidence from one crossing of a feature.

    Attributes:
        pattern: collapsed sign pattern of its curvature features (``"-+-"`` ...).
        role: ``"search"`` (the crossing that met the feature), ``"across"`` or ``"along"``.
        level_change: end level minus start level of the fingertip centre [m].
        relief: rise above minus dip below the line through the end levels [m].
        end_slopes: (2,) slope of the centre path at the start (going backwards) and at the
            end (going forwards): both negative when the plate falls away on both sides.
        width: horizontal length over which the centre departs from the line through the end
            levels by more than half the relief (the feature's width on this crossing) [m].
    """

    pattern: str
    role: str = "across"
    level_change: float = 0.0
    relief: float = 0.0
    end_slopes: tuple[float, float] = (0.0, 0.0)
    width: float = 0.0


@dataclass(frozen=True)
class TypeDecision:
    """Result of type identification.

    Attributes:
        kind: the most probable of :data:`KINDS`, or ``"unknown"`` (nothing was seen).
        confidence: its posterior probability in [0, 1].
        scores: posterior probability of every kind.
        path: the cues read, in order (the branches of the flow chart).
    """

    kind: str
    confidence: float
    scores: dict[str, float] = field(default_factory=dict)
    path: tuple[str, ...] = ()


def flow_chart_next(crossings: list[Crossing]) -> str | None:
    """The motion the extended flow chart asks for next: ``"across"``, ``"along"`` or None.

    One centred crossing decides Fig. 4.7's cusp, step and ridge; the along crossing is what
    tells a bump from a ridge and a pit from a ravine, so it is always asked for.
    """
    roles = {c.role for c in crossings}
    if "across" not in roles:
        return "across"
    if "along" not in roles:
        return "along"
    return None


def _rel(value: float, thr: float) -> str:
    return "up" if value > thr else ("down" if value < -thr else "flat")


def _lik(observed, predicted, p: float) -> float:
    if predicted is None:
        return 0.5
    return p if observed == predicted else 1.0 - p


def identify(
    crossings: list[Crossing],
    level_threshold: float = 5e-4,
    relief_threshold: float = 3e-4,
    crease_slope: float = 0.12,
    elongation: float = 1.8,
) -> TypeDecision:
    """Posterior over the six kinds from the crossings (the extended Fig. 4.7).

    Args:
        crossings: the evidence; ``"across"`` crossings (or the ``"search"`` one when there is
            no across crossing) give the across cues, ``"along"`` crossings the along cue.
        level_threshold: a level change beyond this is a step [m].
        relief_threshold: a relief beyond this is raised/sunken [m].
        crease_slope: both end slopes below minus this make a crease [-].
        elongation: an along crossing whose raised (sunken) part is longer than this times the
            across crossing's is elongated - flat along, as on a ridge (finite ridges drop at
            their end caps when the along crossing is longer than they are).

    Returns:
        :class:`TypeDecision`; ``"unknown"`` with confidence 0 when no crossing saw anything.
    """
    across = [c for c in crossings if c.role == "across"] or [
        c for c in crossings if c.role == "search"
    ]
    along = [c for c in crossings if c.role == "along"]
    seen = [c for c in across if c.pattern or abs(c.relief) > relief_threshold]
    if not seen:
        return TypeDecision("unknown", 0.0, dict.fromkeys(KINDS, 0.0), ("nothing seen",))
    logp = dict.fromkeys(KINDS, 0.0)
    path = []
    for c in across:
        rel = _rel(c.relief, relief_threshold)
        crease = max(c.end_slopes) < -crease_slope
        # a level change is a step's only between level ends: where the plate falls away on
        # both sides (a crease) the end levels are wherever the crossing stopped on the flanks
        step = not crease and abs(c.level_change) > max(level_threshold, abs(c.relief))
        feet = "-+-" in c.pattern
        path.append(
            f"{c.role}: pattern {c.pattern or '(none)'}, relief {rel}, "
            f"{'level change' if step else 'level'}, {'feet' if feet else 'no feet'}, "
            f"{'crease' if crease else 'no crease'}"
        )
        for k in KINDS:
            pr, ps, pf, pc, _ = PREDICTIONS[k]
            rel_k = rel if not step else "flat"  # a step's relief is not informative
            logp[k] += np.log(_lik(rel_k if k == "step" else rel, pr, P_CUE))
            logp[k] += np.log(_lik(step, ps, P_CUE))
            logp[k] += np.log(_lik(feet, pf, P_FEET))
            logp[k] += np.log(_lik(crease, pc, P_CUE))
    w_across = max([c.width for c in across] + [1e-9])
    for c in along:
        rel = _rel(c.relief, relief_threshold)
        if rel != "flat" and c.width > elongation * w_across:
            rel = "flat"  # a finite ridge or ravine: long along, its ends drop within the crossing
        path.append(
            f"along: pattern {c.pattern or '(none)'}, relief {rel}, width "
            f"{c.width * 1e3:.1f} mm vs {w_across * 1e3:.1f} mm across"
        )
        for k in KINDS:
            logp[k] += np.log(_lik(rel, PREDICTIONS[k][4], P_CUE))
    vals = np.array([logp[k] for k in KINDS])
    post = np.exp(vals - vals.max())
    post /= post.sum()
    scores = {k: float(p) for k, p in zip(KINDS, post, strict=True)}
    best = KINDS[int(np.argmax(post))]
    return TypeDecision(best, scores[best], scores, tuple(path))


def crossing_axis(normals_uvw: np.ndarray, direction, min_tilt: float = 0.05) -> np.ndarray:
    """Estimated across-direction (2,) of a feature from a crossing's contact normals.

    Args:
        normals_uvw: (N, 3) outward surface normals along the crossing, plate frame [-].
        direction: (2,) direction of travel of the crossing.
        min_tilt: samples with a smaller horizontal tilt (sine) are ignored.

    Returns:
        (2,) unit vector across the feature (the crossing direction when nothing is tilted).
    """
    d = np.asarray(direction, float)
    d = d / np.linalg.norm(d)
    g = np.asarray(normals_uvw, float)[:, :2]
    t = np.linalg.norm(g, axis=1)
    g = g[t > min_tilt]
    if len(g) == 0:
        return d
    g = g * np.where(g @ d >= 0, 1.0, -1.0)[:, None]
    m = g.sum(axis=0)
    n = np.linalg.norm(m)
    return d if n < 1e-12 else m / n


def _ends(s: np.ndarray, w: np.ndarray, fraction: float):
    k = max(2, int(len(w) * fraction))
    return k, (np.mean(s[:k]), np.mean(w[:k])), (np.mean(s[-k:]), np.mean(w[-k:]))


def level_change(w: np.ndarray, fraction: float = END_FRACTION) -> float:
    """Mean height of the last ``fraction`` of a crossing minus that of the first [m]."""
    w = np.asarray(w, float)
    k = max(1, int(len(w) * fraction))
    return float(np.mean(w[-k:]) - np.mean(w[:k]))


def relief(s: np.ndarray, w: np.ndarray, fraction: float = END_FRACTION) -> float:
    """Rise above minus dip below the line through the crossing's end levels [m].

    Args:
        s: (N,) horizontal arclength [m]; w: (N,) fingertip-centre heights [m].
        fraction: share of samples at each end that fixes the end levels.
    """
    s, w = np.asarray(s, float), np.asarray(w, float)
    _, (s0, w0), (s1, w1) = _ends(s, w, fraction)
    base = w0 + (w1 - w0) * (s - s0) / max(s1 - s0, 1e-12)
    d = w - base
    return float(d.max() + d.min())


def feature_width(s: np.ndarray, w: np.ndarray, fraction: float = END_FRACTION) -> float:
    """Length [m] of the part of a crossing departing from the end-level line by more than
    half of its largest departure (the full width at half maximum of the relief)."""
    s, w = np.asarray(s, float), np.asarray(w, float)
    _, (s0, w0), (s1, w1) = _ends(s, w, fraction)
    d = np.abs(w - (w0 + (w1 - w0) * (s - s0) / max(s1 - s0, 1e-12)))
    if d.max() <= 0:
        return 0.0
    on = np.flatnonzero(d > 0.5 * d.max())
    return float(s[on[-1]] - s[on[0]])


def end_slopes(s: np.ndarray, w: np.ndarray, fraction: float = END_FRACTION) -> tuple[float, float]:
    """Slopes of the centre path over the first and last ``fraction`` of the crossing, each
    taken going away from the middle (negative: the plate falls away) [-]."""
    s, w = np.asarray(s, float), np.asarray(w, float)
    k = max(3, int(len(w) * fraction))
    if len(w) < 2 * k:
        return (0.0, 0.0)
    a = np.polyfit(s[:k], w[:k], 1)[0]
    b = np.polyfit(s[-k:], w[-k:], 1)[0]
    return (float(-a), float(b))


def evidence(centers_uvw, normals_uvw, tip_radius: float, role: str = "across"):
    """Evidence of one crossing from its fingertip centres and contact normals (plate frame).

    Args:
        centers_uvw: (N, 3) fingertip centres [m].
        normals_uvw: (N, 3) outward surface normals at the contacts [-] (for the axis).
        tip_radius: r_f [m].
        role: ``"search"``, ``"across"`` or ``"along"``.

    Returns:
        ``(crossing, analysis, across_direction)``: the :class:`Crossing`, the
        :class:`~planner.exploration.surface.detection_adapter.PathAnalysis` and the (2,)
        estimated direction across the feature.
    """
    from planner.exploration.surface.detection_adapter import analyse_path

    P = np.asarray(centers_uvw, float)
    a = analyse_path(P, tip_radius)
    if len(a.s) >= 6:
        c = Crossing(
            a.pattern,
            role,
            level_change(a.w),
            relief(a.s, a.w),
            end_slopes(a.s, a.w),
            feature_width(a.s, a.w),
        )
    else:
        c = Crossing(a.pattern, role)
    d = P[-1, :2] - P[0, :2]
    return c, a, crossing_axis(normals_uvw, d if np.linalg.norm(d) > 0 else (1.0, 0.0))


def _enclosed(boundary: np.ndarray, hull: bool):
    """The area a traced closed outline ((N, 2) samples in trace order [m]) encloses, a
    shapely geometry (empty for fewer than 4 samples). Samples stitched from several passes
    make the ring cross itself; its valid parts are united, and with ``hull`` replaced by
    their convex hull (a bow-tie's parts can miss the interior between them)."""
    import shapely

    P = np.asarray(boundary, float)
    if len(P) < 4:
        return shapely.Polygon()
    poly = shapely.Polygon(P)
    if not poly.is_valid:
        poly = shapely.make_valid(poly)
        parts = [g for g in shapely.get_parts(poly) if g.geom_type.endswith("Polygon")]
        poly = shapely.union_all(parts) if parts else shapely.Polygon()
        poly = poly.convex_hull if hull and not poly.is_empty else poly
    return poly


def outline_thinness(boundary: np.ndarray, inscribed_radius: float) -> float:
    """Area over that of the largest inscribed disc [-] of a traced closed outline ((N, 2)
    samples in trace order [m]; ``inscribed_radius`` [m], the largest medial radius): 1 for
    a disc, ``1 + 2 L / (pi w)`` for a stadium of half-width ``w`` and straight length
    ``L``, whether straight or bent (a V-shaped ridge's area moments are nearly round); nan
    when the samples enclose no area or the radius is not positive."""
    poly = _enclosed(boundary, hull=False)
    if poly.is_empty or poly.area <= 0 or not inscribed_radius > 0:
        return float("nan")
    return float(poly.area / (math.pi * inscribed_radius**2))


def outline_elongation(boundary: np.ndarray) -> float:
    """Length over width [-] of a traced closed outline ((N, 2) samples in trace order [m]):
    the square root of the ratio of the principal second moments of the *area* it encloses.
    Area moments do not depend on how densely each part was sampled (the tracer keeps only
    settled samples, so a circle traced with gaps has lopsided sample moments but round area
    moments); nan when the samples enclose no area."""
    import shapely

    poly = _enclosed(boundary, hull=True)
    if poly.is_empty or poly.area <= 0:
        return float("nan")
    tri = shapely.get_parts(shapely.delaunay_triangles(poly))
    tri = [t for t in tri if poly.contains(t.representative_point())]
    A = np.array([t.area for t in tri])
    V = np.array([np.asarray(t.exterior.coords)[:3] for t in tri])  # (T, 3, 2)
    c = (A[:, None] * V.mean(axis=1)).sum(axis=0) / A.sum()
    V = V - c
    # second moments of each triangle: A/12 (sum v v^T + (sum v)(sum v)^T)
    S = V.sum(axis=1)
    M = (A[:, None, None] / 12.0) * (
        np.einsum("tki,tkj->tij", V, V) + np.einsum("ti,tj->tij", S, S)
    )
    ev = np.linalg.eigvalsh(M.sum(axis=0))
    return float(np.sqrt(ev[-1] / max(ev[0], 1e-30)))


#: kinds whose outline cannot close inside the explored region: a step's edge divides two
#: plate levels and runs out of the region (its traced outline reaches both ends)
OPEN_KINDS = ("step",)


def _closed_kind(decision: TypeDecision) -> TypeDecision:
    """The decision given that its traced outline closed: the posterior conditioned on a
    closed outline (the :data:`OPEN_KINDS` dropped, the other kinds' scores renormalised),
    its most probable kind and confidence. A crossing that ends on a feature's flank reads a
    level change ("step") while the outline closes around the feature: the across crossing
    of ``scenarios/curved_ridge.yaml`` did, over both arms of the bend, until crossings ran
    out onto a plane (``program._run_out``)."""
    from dataclasses import replace

    rest = {k: v for k, v in decision.scores.items() if k not in OPEN_KINDS}
    total = sum(rest.values())
    if not rest or total <= 0.0:
        return decision
    scores = {k: (v / total if k in rest else 0.0) for k, v in decision.scores.items()}
    kind = max(rest, key=rest.get)
    note = f"traced outline closed: not a {decision.kind} -> {kind}"
    return replace(decision, kind=kind, confidence=scores[kind], scores=scores,
                   path=(*decision.path, note))  # fmt: skip


def refine_with_outline(
    decision: TypeDecision,
    boundary: np.ndarray,
    closed: bool,
    elongation: float = 1.0,
    min_area_elongation: float = 1.4,
    min_thinness: float = 2.0,
) -> TypeDecision:
    """After tracing, compare the outline's shape with the kind (§4.4.1: the pattern of the
    traced curvature region). A closed outline rules out the open kinds (a step:
    :func:`_closed_kind`, the posterior without them). A bump's or a pit's medial axis is a
    point (rotational symmetry); a ridge's or a ravine's is its crest line. A closed outline
    whose pruned skeleton (:func:`~planner.exploration.surface.modelling.feature_model`) is
    longer than ``elongation`` times its largest inscribed radius is a ridge or a ravine (the along
    crossing can run past a short ridge's end caps, and an 8 mm ball makes a 12 mm ridge's
    outline only twice as long as wide) *and* the area it encloses is elongated
    (:func:`outline_elongation` above ``min_area_elongation``, or, for a bent one whose area
    moments are nearly round, :func:`outline_thinness` above ``min_thinness``): the medial
    axis of a small round outline grows with the boundary's noise (a 1 mm pit's outline of
    radius 2 mm, traced with 0.15 mm lateral scatter, gave a 6 mm skeleton), its area
    moments do not (1.02). A bump's or pit's outline reads 1.0-1.1, a 12 mm ridge's 1.9 (5
    mm high, its outline 12 mm wide) to 2.7 (1 mm high); the threshold lies in between. The
    V-shaped ridge of ``scenarios/curved_ridge.yaml`` reads 1.07, its thinness 6; a round
    outline's thinness is 1 plus what the boundary's scatter takes off the inscribed radius
    (0.15 mm on 2 mm: 1.17).

    Args:
        decision: the flow chart's (or the raster match's) decision.
        boundary: (N, 2) traced boundary samples [m]; closed: whether the loop closed.
        elongation: skeleton length over largest medial radius beyond which the feature is
            elongated [-].
        min_area_elongation: least length over width of the enclosed area for elongated [-].
        min_thinness: least area over that of the largest inscribed disc for elongated [-].
    """
    from dataclasses import replace

    from planner.exploration.surface.modelling import feature_model

    if closed and len(boundary) >= 10 and decision.kind in OPEN_KINDS:
        decision = _closed_kind(decision)
    if not closed or len(boundary) < 10 or decision.kind not in ("bump", "pit"):
        return decision
    sk = feature_model(decision.kind, [np.asarray(boundary, float)], True)
    if sk is None or len(sk.radii) == 0 or not sk.length > elongation * float(sk.radii.max()):
        return decision
    area = outline_elongation(boundary)
    thin = outline_thinness(boundary, float(sk.radii.max()))
    if not (area > min_area_elongation or thin > min_thinness):
        return decision
    kind = "ridge" if decision.kind == "bump" else "ravine"
    scores = dict(decision.scores)
    scores[kind], scores[decision.kind] = scores[decision.kind], scores[kind]
    note = (
        f"traced outline's skeleton {sk.length * 1e3:.1f} mm long, inscribed radius "
        f"{sk.radii.max() * 1e3:.1f} mm, area elongation {area:.2f}, thinness {thin:.2f}: "
        f"{decision.kind} -> {kind}"
    )
    return replace(decision, kind=kind, scores=scores, path=(*decision.path, note))
