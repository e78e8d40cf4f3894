"""Scores of an exploration against the plate's ground truth (issue 12's metrics).

Found features are matched to true ones by the distance from the found centre to the true
skeleton (within ``2.5 r_f``).

**Type accuracy** is the number of true features with a matched detection of the right
type (each counted once) over the number of matched detections: a feature reported twice
(say as a step and as a ridge, or as a step twice) adds a detection, never a second correct
one, so the accuracy stays in [0, 1] and a duplicate lowers it. ``duplicate_detections``
counts the matched detections beyond the first of each true feature.

**Boundary deviation** is the distance of every traced boundary sample (a fingertip centre)
to the true outline (:func:`planner.exploration.surface.plates.truth_features`): the level
line of the *traced* surface - the offset by ``r_f`` of the plate, which is all the centre
of a round fingertip can follow (§3.2.1) - at the feature's outline level above the plate
level next to the feature, its foot (:func:`~planner.exploration.surface.plates.
foot_levels`: the plane of travel before the feature is met, §4.4.2; where the traced
surface's tilt falls to 5 deg going out from the flank). Centre samples are thus compared
with a line the centre can reach, offset already applied on the truth side (comparing them
with the object's own outline would charge every sample with up to ``r_f`` the tracer
cannot remove). The level is the explorer's (its fraction of the feature's relief,
``rise``); where the feature sits and where its foot is are the plate's.

The level used to be taken above the *asymptotic* plate (the plate without the feature), a
line no explorer can find from inside a region: a bump's or pit's tails fall
off as ``1/s^2`` (a 4 mm pit 5 mm wide still lowers the plate by 0.24 mm 20 mm away), so
the level line ``rise`` off that plate lies on tails of slope 0.02-0.1, where every 0.01 mm
of plate level moves it by 0.1-0.5 mm, and the tracer, reading the plate next to the
feature, was charged 1-4 mm for pits (the benchmark's 1.6 mm pit row) while following its
own level line to 0.1-0.2 mm. The ``own level`` diagnostic scores the samples against the
level line they actually followed (the tracing error alone).

**Skeleton error** is the Hausdorff distance between the found skeleton and the true one
(the true one clipped to the traced extent for open features, which are traced only inside
the region). The skeleton of a step or a cusp is the pseudo-skeleton of §4.4.3 - "for a
cusp or step feature, the finger cannot trace around the feature, it can only trace along
it. The path obtained by tracing along such a feature can be used as a pseudo-skeleton" -
the traced outline itself, so it is scored against the true outline line it follows, not
the step's edge (a ball of radius ``r_f`` rests on the foot of a step of height ``h`` up to
``sqrt(2 r_f h - h^2)`` from its edge: 3.9 mm for 1 mm, which no tracer could remove).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["exploration_metrics", "match_features", "type_accuracy"]


def _skel_geom(points: np.ndarray):
    import shapely

    P = np.asarray(points, float)
    if len(P) == 1:
        return shapely.Point(P[0])
    return shapely.LineString(P)


def match_features(result, truth, tip_radius: float) -> list[int | None]:
    """Index of the true feature each found feature belongs to (None: a false detection)."""
    import shapely

    out = []
    geoms = [_skel_geom(t.skeleton) for t in truth]
    for f in result.features:
        p = shapely.Point(*f.centre)
        d = [g.distance(p) for g in geoms]
        j = int(np.argmin(d)) if d else -1
        out.append(j if d and d[j] < 2.5 * tip_radius else None)
    return out


def _found_skeleton(f):
    sk = f.skeleton
    if sk is None or len(sk.points) == 0:
        return None
    return np.asarray(sk.points, float)


def _hausdorff(found: np.ndarray, true_skel: np.ndarray, closed: bool) -> float:
    import shapely

    t = np.asarray(true_skel, float)
    if len(t) >= 2 and not closed:  # clip the infinite axis to the traced extent
        d = t[1] - t[0]
        d = d / np.linalg.norm(d)
        s = (found - t[0]) @ d
        t = np.array([t[0] + s.min() * d, t[0] + s.max() * d])
    return float(shapely.hausdorff_distance(shapely.MultiPoint(found), _skel_geom(t)))


def _pseudo_hausdorff(found: np.ndarray, truth) -> float:
    """Hausdorff distance [m] of a pseudo-skeleton (a step or cusp traced along, §4.4.3) to
    the true outline line it follows (the nearest one), clipped to the traced extent along
    the feature's axis: the pseudo-skeleton *is* the traced outline, so its truth is the
    true outline, not the step's axis (a ball of radius r_f rests on the foot of a step of
    height h up to sqrt(2 r_f h - h^2) from its edge)."""
    import shapely

    lines = [shapely.LineString(ln) for ln in truth.outline if len(ln) >= 2]
    if not lines:
        return float("nan")
    pts = shapely.points(found)
    line = min(lines, key=lambda g: float(np.mean(shapely.distance(pts, g))))
    t = np.asarray(truth.skeleton, float)
    d = (t[-1] - t[0]) / max(float(np.linalg.norm(t[-1] - t[0])), 1e-12)
    s = (found - t[0]) @ d
    n = np.array([-d[1], d[0]])
    far = 1.0  # [m] the band across the axis, longer than any plate
    band = shapely.Polygon(
        [
            t[0] + a * d + b * far * n
            for a, b in ((s.min(), -1), (s.max(), -1), (s.max(), 1), (s.min(), 1))
        ]
    )
    clipped = line.intersection(band)
    if clipped.is_empty:
        return float("nan")
    return float(shapely.hausdorff_distance(shapely.MultiPoint(found), clipped))


def type_accuracy(kinds, match, truth) -> tuple[float, int]:
    """``(accuracy, duplicates)`` of the found features' ``kinds`` matched (``match``: the
    index into ``truth`` of each, None when unmatched) to the true features ``truth`` (each
    with a ``.kind``), as defined in the module doc: the true features with a matched
    detection of their type over the matched detections (nan without any), and the matched
    detections beyond the first of each true feature."""
    pairs = [(k, j) for k, j in zip(kinds, match, strict=True) if j is not None]
    right = {j for k, j in pairs if k == truth[j].kind}
    duplicates = len(pairs) - len({j for _, j in pairs})
    return (len(right) / len(pairs) if pairs else float("nan")), duplicates


def exploration_metrics(result, plate, region, tip_radius: float, normal_force: float) -> dict:
    """All scalar metrics of one exploration (JSON-serialisable dict)."""
    import shapely

    from planner.exploration.surface.plates import truth_features

    truth = truth_features(plate, region, tip_radius, result.settings.boundary_rise)
    match = match_features(result, truth, tip_radius)
    found_true = {j for j in match if j is not None}
    accuracy, duplicates = type_accuracy([f.kind for f in result.features], match, truth)
    devs, dmax, closures, haus = [], 0.0, [], []
    for f, j in zip(result.features, match, strict=True):
        if j is None:
            continue
        t = truth_features(plate, region, tip_radius, _rises(plate, j, f.rise))[j]
        if len(f.boundary) and t.outline:
            outline = shapely.MultiLineString([ln for ln in t.outline if len(ln) >= 2])
            d = shapely.distance(shapely.points(f.boundary), outline)
            devs.append(d)
            dmax = max(dmax, float(d.max()))
        if t.closed:
            closures.append(bool(f.closed))
        sk = _found_skeleton(f)
        if sk is not None and t.kind in ("step", "cusp") and f.kind == t.kind:
            haus.append(_pseudo_hausdorff(sk, t))
        elif sk is not None:
            haus.append(_hausdorff(sk, t.skeleton, t.closed))
    own = _own_level_deviation(result, plate, region, tip_radius, match)
    dev = np.concatenate(devs) if devs else np.zeros(0)
    log = result.log
    fn = _normal_force_error(result, log, normal_force)
    path = result.path
    length = float(np.sum(np.hypot(*np.diff(path[:, :2], axis=0).T))) if len(path) > 1 else 0.0
    lat = [f.latency for f in result.features if math.isfinite(f.latency)]
    return {
        "features_present": len(truth),
        "features_found": len(found_true),
        "false_detections": sum(j is None for j in match),
        "duplicate_detections": duplicates,
        "type_accuracy": accuracy,
        "boundary_deviation_mean_mm": float(dev.mean() * 1e3) if dev.size else float("nan"),
        "boundary_deviation_max_mm": dmax * 1e3 if dev.size else float("nan"),
        "boundary_deviation_own_level_mm": own,
        "closure": float(np.mean(closures)) if closures else float("nan"),
        "skeleton_hausdorff_mm": float(np.max(haus) * 1e3) if haus else float("nan"),
        "exploration_time_s": result.sim_time,
        "path_length_m": length,
        "normal_force_rms_error_N": fn,
        "real_time_factor": result.real_time_factor,
        "detection_latency_mean_s": float(np.mean(lat)) if lat else float("nan"),
        "saturation_events": sum(e.kind == "torque_saturated" for e in result.events),
    }


def _own_level_deviation(result, plate, region, tip_radius: float, match) -> float:
    """Mean distance [mm] of the boundary samples of bumps, pits, ridges and ravines to the
    true outline *at the level the tracer followed* (the median centre height of its
    samples), not ``rise`` off the feature's foot: a diagnostic that separates the tracing
    error from the choice of the level (the foot read by the tracer); nan without such
    features."""
    import shapely

    from planner.exploration.surface.plates import truth_features

    rows = {tuple(p[:2]): p[2] for p in np.asarray(result.path)}
    devs = []
    for f, j in zip(result.features, match, strict=True):
        kind = plate.features[j].kind if j is not None else ""
        if kind not in ("bump", "pit", "ridge", "ravine") or len(f.boundary) < 4:
            continue
        z = np.array([rows.get(tuple(q), np.nan) for q in f.boundary])
        sign = -1.0 if kind in ("pit", "ravine") else 1.0
        rise = sign * (float(np.nanmedian(z)) - tip_radius - float(plate.base))
        if not rise > 0:
            continue
        t = truth_features(plate, region, tip_radius, _rises(plate, j, rise), foot_tilt=None)[j]
        lines = [ln for ln in t.outline if len(ln) >= 2]
        if lines:
            d = shapely.distance(shapely.points(f.boundary), shapely.MultiLineString(lines))
            devs.append(d)
    return float(np.concatenate(devs).mean() * 1e3) if devs else float("nan")


def _rises(plate, j: int, rise: float) -> np.ndarray:
    out = np.full(len(plate.features), 2.5e-4)
    out[j] = rise
    return out


def _normal_force_error(result, log, normal_force: float) -> float:
    """RMS of (true contact force - f_des) over the steps in contact after the approach [N]."""
    if log is None or log.normal_force.size == 0:
        return float("nan")
    fn = log.normal_force.sum(axis=1)
    on = fn > 0
    if len(result.phase):
        settled = np.zeros(len(fn), bool)
        k = min(len(fn) - 1, len(result.phase))
        settled[1 : k + 1] = result.phase[:k] != 0  # not during the approach
        on &= settled
    if not on.any():
        return float("nan")
    return float(np.sqrt(np.mean((fn[on] - normal_force) ** 2)))
