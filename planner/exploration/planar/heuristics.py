"""Planning heuristics of the gait: the start grasp and the fingertip orientation (§2.2.3).

* :func:`four_region_orientations`: "The Cartesian workspace of each finger is divided into
  four regions, each of which has a preferred fingertip orientation - one that maximizes the
  local configuration space." The regions are the quadrants about the centroid of the
  finger's reachable fingertip points (sampled over its joint ranges); the preferred
  orientation of a region is the one whose inverse kinematics at the region's mean point
  stays farthest from every joint limit.
* :func:`preferred_orientation`: maps a (final) fingertip position to its region.
* :func:`start_grasp_candidates`: phase-1 grasps of the nominal object resting on the palm,
  best first (largest joint-limit margin among Yoshikawa-Nagai-stable ones).
"""

from __future__ import annotations

import math

import numpy as np

from planner.errors import HapexError, InvalidParameter

_CACHE: dict = {}
#: the §2.2.3 orientation of a round tip is searched within this angle of its apex [rad]
#: (:func:`tip_orientation`) ...
TIP_SPREAD = 0.5
#: ... on this many orientations (1 deg apart) [-]
TIP_ORIENTATIONS = 61


def _margin(hand, finger: str, q: np.ndarray) -> np.ndarray:
    lim = hand.finger_limits(finger)
    return np.minimum(q - lim[:, 0], lim[:, 1] - q).min(axis=-1)


def four_region_orientations(hand, finger: str, samples: int = 4000, seed: int = 0):
    """Centroid (2,) of the finger's workspace and the preferred orientation [rad] of each
    quadrant about it (``(4,)``, quadrants counter-clockwise from +x, +y)."""
    key = (hand.params, finger)
    if key in _CACHE:
        return _CACHE[key]
    from robots.planar_hand import kinematics as kin

    lim = hand.finger_limits(finger)
    rng = np.random.default_rng(seed)
    q = rng.uniform(lim[:, 0], lim[:, 1], size=(samples, 3))
    f = hand.params.finger(finger)
    tips, _ = kin.fingertip(np.array(f.base), np.array(f.lengths), q)
    centre = tips.mean(axis=0)
    quad = _quadrant(tips - centre)
    phis = np.linspace(lim[:, 0].sum(), lim[:, 1].sum(), 181)
    best = np.zeros(4)
    for k in range(4):
        pts = tips[quad == k]
        point = pts.mean(axis=0) if len(pts) else centre
        sols, ok = hand.ik_candidates(finger, np.broadcast_to(point, (phis.size, 2)), phis)
        m = np.where(ok, _margin(hand, finger, sols), -np.inf).max(axis=1)
        best[k] = phis[int(np.argmax(m))]
    _CACHE[key] = (centre, best)
    return centre, best


def _quadrant(v: np.ndarray) -> np.ndarray:
    return np.where(v[..., 0] >= 0, np.where(v[..., 1] >= 0, 0, 3), np.where(v[..., 1] >= 0, 1, 2))


def preferred_orientation(hand, finger: str, position) -> float:
    """The preferred fingertip orientation [rad] of the region holding ``position`` (2,)."""
    centre, best = four_region_orientations(hand, finger)
    return float(best[int(_quadrant(np.asarray(position, float) - centre))])


def best_margin_ik(hand, finger: str, position, n: int = 241, around=None, spread=1.0):
    """The IK solution of ``finger`` reaching ``position`` (2,) [m] whose smallest distance
    to a joint limit is largest, over orientations within ``spread`` [rad] of ``around``
    (default: all); None if unreachable."""
    lim = hand.finger_limits(finger)
    if around is None:
        phis = np.linspace(lim[:, 0].sum(), lim[:, 1].sum(), n)
    else:
        phis = np.linspace(around - spread, around + spread, n)
    target = np.broadcast_to(np.asarray(position, float), (n, 2))
    sols, ok = hand.ik_candidates(finger, target, phis)
    if not ok.any():
        return None
    m = np.where(ok, _margin(hand, finger, sols), -np.inf)
    i, j = np.unravel_index(int(np.argmax(m)), m.shape)
    return sols[i, j].copy()


def pad_angle(beta: float, reference: float) -> float:
    """Orientation of the flat left pad lying on a contact of outward normal angle ``beta``
    (``phi = beta + pi/2``), unwrapped to the turn closest to ``reference`` [rad]."""
    phi = beta + 0.5 * math.pi
    return phi + 2 * math.pi * round((reference - phi) / (2 * math.pi))


def left_ik(hand, point, beta: float, mid: float):
    """Left finger joints (3,) touching the contact ``point`` (2,) [m] of outward normal
    angle ``beta`` [rad] on the object: the flat pad lying on it (:func:`pad_angle`,
    unwrapped near ``mid``), or a round tip with the best joint margin whose centre is
    ``r_L`` out along the normal; None when unreachable."""
    rL = hand.params.left.round_radius
    if not rL:
        try:
            return hand.inverse_kinematics("left", point, angle=pad_angle(beta, mid))
        except HapexError:  # unreachable candidates are skipped
            return None
    n = np.array([math.cos(beta), math.sin(beta)])
    return best_margin_ik(hand, "left", np.asarray(point, float) + rL * n,
                          around=beta + 0.5 * math.pi)  # fmt: skip


def start_grasp_candidates(
    hand, centre, radius: float, mu: float, prior=None, stability_margin: float = 0.15
):
    """Phase-1 grasps of the nominal circle (``centre`` (2,), ``radius``) [m], best first:
    by the smaller of the joint-limit margin and the Yoshikawa-Nagai stability margin
    (``atan(mu) - stability_margin`` minus the contact line's angle to the normals) [rad].

    Args:
        prior: optional ``(beta_left, beta_right)`` world contact angles [rad] (the gait
            prior of ``plan_gait``) tried first.

    Returns:
        list of ``(beta_left, beta_right, q (6,), margin [rad])``.
    """
    r = hand.params.right.tip_radius
    c = np.asarray(centre, float)
    out = []
    bl = np.deg2rad(np.arange(110.0, 176.0, 5.0))
    br = np.deg2rad(np.arange(-10.0, 71.0, 5.0))
    pairs = [(a, b) for a in bl for b in br]
    if prior is not None:
        pairs.insert(0, (float(prior[0]), float(prior[1])))
    mid = float(hand.finger_limits("left").sum(axis=0).mean())
    for a, b in pairs:
        half = 0.5 * abs(a - b)
        stab = math.atan(mu) - stability_margin - (0.5 * math.pi - half)
        if stab < 0:  # the contact line leaves the (reduced) cones
            continue
        nL = np.array([math.cos(a), math.sin(a)])
        nR = np.array([math.cos(b), math.sin(b)])
        qL = left_ik(hand, c + radius * nL, a, mid)
        if qL is None:
            continue
        qR = best_margin_ik(hand, "right", c + (radius + r) * nR, around=b + 0.5 * math.pi)
        if qR is None:
            continue
        m = min(_margin(hand, "left", qL), _margin(hand, "right", qR), stab)
        out.append((float(a), float(b), np.r_[qL, qR], float(m)))
    if prior is not None and out and out[0][:2] == (float(prior[0]), float(prior[1])):
        first, rest = out[0], sorted(out[1:], key=lambda g: -g[3])
        return [first, *rest]
    return sorted(out, key=lambda g: -g[3])


def _reach_margin(hand, finger: str, points: np.ndarray, phis: np.ndarray) -> np.ndarray:
    """Joint-limit margin [rad] of reaching each ``points[i]`` (M, 2) with orientation
    ``phis[i]`` (M,), best IK branch; ``-inf`` where unreachable."""
    sols, ok = hand.ik_candidates(finger, points, phis)
    return np.where(ok, _margin(hand, finger, sols), -np.inf).max(axis=1)


def regrasp_orientation(
    hand,
    centre,
    radius: float,
    beta: float,
    travel: float,
    spread: float = TIP_SPREAD,
    n: int = TIP_ORIENTATIONS,
    finger: str = "right",
) -> float:
    """Orientation [rad] of a round tip (the right one, or ``finger`` "left" on a hand with
    a round left tip) for its new grasp at world polar angle ``beta`` [rad] on the
    estimated circle (``centre`` (2,), ``radius`` [m]).

    The §2.2.3 heuristic ("a preferred fingertip orientation - one that maximizes the local
    configuration space") evaluated where the finger will work: the orientation within
    ``spread`` [rad] of the tip's apex that maximizes the smaller joint-limit margin at the
    new grasp and at the end of the next phase 1 (the contact ``travel`` [rad] further,
    clockwise; in rolling on a circle of radius ~2 r the tip keeps its orientation to within
    a few degrees, so the same orientation is checked there). Falls back to the four-region
    preference when no orientation reaches both points.

    Raises:
        InvalidParameter: ``finger`` is not "left" or "right", or that finger has a flat pad.
    """
    if finger not in ("left", "right"):
        raise InvalidParameter(f"finger: must be 'left' or 'right', got {finger!r}")
    r = getattr(hand.params, finger).round_radius
    if r <= 0.0:
        raise InvalidParameter(f"finger: the {finger} finger has a flat pad, not a round tip")
    c = np.asarray(centre, float)
    centres = [c + (radius + r) * np.array([math.cos(b), math.sin(b)])
               for b in (beta, beta - travel)]  # fmt: skip
    return tip_orientation(hand, centres, beta + 0.5 * math.pi, spread, n, finger)


def tip_orientation(
    hand,
    tip_centres,
    apex: float,
    spread: float = TIP_SPREAD,
    n: int = TIP_ORIENTATIONS,
    finger: str = "right",
) -> float:
    """Orientation [rad] of a round tip (``finger``), within ``spread`` [rad] of ``apex`` [rad]
    (the orientation that touches the surface at the tip's axis: the surface's outward
    normal angle + pi/2), that maximizes the smallest joint-limit margin over the tip
    centres ``tip_centres`` (each (2,) [m]; the same orientation at each); the four-region
    preference at the first centre (clipped to the spread) when no orientation reaches them
    all (the §2.2.3 heuristic, :func:`regrasp_orientation` on a circle)."""
    phis, m = _tip_margins(hand, finger, tip_centres, apex, spread, n)
    if not np.isfinite(m).any():
        pref = preferred_orientation(hand, finger, tip_centres[0])
        return apex + float(np.clip(math.remainder(pref - apex, 2 * math.pi), -spread, spread))
    return float(phis[int(np.argmax(m))])


def _tip_margins(hand, finger: str, tip_centres, apex: float, spread: float, n: int):
    """``(phis, margins)``: ``n`` orientations [rad] within ``spread`` of ``apex`` and, for
    each, the smallest joint-limit margin [rad] of the round tip of ``finger`` over the tip
    centres ``tip_centres`` (each (2,) [m]) held at that orientation (``-inf``:
    unreachable)."""
    phis = apex + np.linspace(-spread, spread, n)
    pts = [np.broadcast_to(np.asarray(p, float), (n, 2)) for p in tip_centres]
    return phis, np.min([_reach_margin(hand, finger, p, phis) for p in pts], axis=0)


def stable_pair(beta_left: float, beta_right: float, mu: float, margin: float) -> float:
    """Yoshikawa-Nagai stability margin [rad] of a two-finger grasp of a circle at world
    polar angles ``beta_left``, ``beta_right`` [rad]: ``atan(mu) - margin`` minus the angle
    between the contact line and the contact normals (>= 0: stable with the margin)."""
    half = 0.5 * abs(math.atan2(math.sin(beta_left - beta_right), math.cos(beta_left - beta_right)))
    return math.atan(mu) - margin - (0.5 * math.pi - half)


def regrasp_left_angle(
    hand, centre, radius: float, beta_right: float, mu: float, margin: float, travel: float
) -> float | None:
    """World polar angle [rad] of the left tip's new grasp (end of phase 3) for the next
    phase 1, or None when no stable, reachable one exists.

    Candidates from 120 to 180 deg: the pair with the right contact ``beta_right`` must be
    stable (:func:`stable_pair` >= 0) and the pad must reach both the new grasp and the end
    of the next rotation (``travel`` [rad] clockwise). Among those the score is the smaller of
    the two joint-limit margins and the stability margin (the same rule as the start grasp);
    a higher contact also lets the pad carry more of the object's weight by friction.
    """
    c = np.asarray(centre, float)
    rL = hand.params.left.round_radius
    cand = np.deg2rad(np.arange(120.0, 180.5, 2.5))
    best, arg = -np.inf, None
    mid = float(hand.finger_limits("left").sum(axis=0).mean())
    for b in cand:
        stab = stable_pair(b, beta_right, mu, margin)
        if stab < 0:
            continue
        bb = np.array([b, b - travel])
        if not rL:
            pts = c + radius * np.column_stack([np.cos(bb), np.sin(bb)])
            phis = np.array([pad_angle(x, mid) for x in bb])
            reach = float(_reach_margin(hand, "left", pts, phis).min())
        else:  # a round tip: its best orientation near the apex for both points
            centres = c + (radius + rL) * np.column_stack([np.cos(bb), np.sin(bb)])
            _, m = _tip_margins(hand, "left", centres, b + 0.5 * math.pi, TIP_SPREAD,
                                TIP_ORIENTATIONS)  # fmt: skip
            reach = float(m.max())
        score = min(reach, stab)
        if score > best:
            best, arg = score, float(b)
    return arg if best > 0 else None


__all__ = [
    "TIP_ORIENTATIONS",
    "TIP_SPREAD",
    "best_margin_ik",
    "four_region_orientations",
    "left_ik",
    "pad_angle",
    "preferred_orientation",
    "regrasp_left_angle",
    "regrasp_orientation",
    "stable_pair",
    "start_grasp_candidates",
    "tip_orientation",
]
