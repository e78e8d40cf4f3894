"""Measures of an exploration: outline coverage and the exploring pad's features."""

from __future__ import annotations

import math

import numpy as np

from planner.exploration.planar.result import DetectedFeature

#: radius of the virtual fingertip the pad's trace is offset by for the detection [m]
VIRTUAL_RADIUS = 0.003


def coverage_of(log, body: str, profile, cells: int = 360) -> float:
    """Fraction of the outline's polar-angle cells touched by a fingertip (true contacts)."""
    hit = np.zeros(cells, dtype=bool)
    pose = log.poses[body]
    for j, pair in enumerate(log.pairs):
        a, b = pair.split("|")
        if body not in (a, b) or not any(x.endswith((".left", ".right")) for x in (a, b)):
            continue
        rows, slots = np.nonzero((log.contact_pair == j) & (log.normal_force > 0))
        if rows.size == 0:
            continue
        P = log.contact_point[rows, slots]
        x, y, ang = pose[rows, 0], pose[rows, 1], pose[rows, 2]
        dx, dy = P[:, 0] - x, P[:, 1] - y
        c, s = np.cos(ang), np.sin(ang)
        ox, oy = c * dx + s * dy, -s * dx + c * dy
        k = (np.floor(np.mod(np.arctan2(oy, ox), 2 * np.pi) / (2 * np.pi) * cells)).astype(int)
        hit[np.clip(k, 0, cells - 1)] = True
    return float(hit.mean())


def _detect(points: np.ndarray, normals: np.ndarray) -> list[tuple[np.ndarray, int]]:
    """THE adapter to ``planner.detection`` (its types are being unified elsewhere).

    Args:
        points: (N, 2) sensed contact points of the pad in the object frame [m].
        normals: (N, 2) outward object normals there.

    Returns:
        ``[(position (2,), sign), ...]`` of the curvature features found.
    """
    from planner.detection import detect_features

    centres = points + VIRTUAL_RADIUS * normals
    feats = detect_features(centres, VIRTUAL_RADIUS, algorithm=1, normals=normals,
                            contacts=points)  # fmt: skip
    return [(np.asarray(f.position, float), int(f.sign)) for f in feats]


def detect_pad_features(trace: dict, profile, rest, radius: float) -> list[DetectedFeature]:
    """Features in the left pad's sensed trace while it explores (phase 3).

    Points are mapped to the object frame with the *estimated* pose (centre and rotation
    from the sensors), detected per contiguous phase-3 run, reported as polar angles on the
    object and matched to the nearest true curvature feature of ``profile``.
    """
    if len(trace.get("t", ())) == 0:
        return []
    kind, touch = trace["kind"], trace["pad_touch"] > 0
    sel = (kind == 3) & touch
    truth = [math.atan2(f.position[1], f.position[0])
             for f in profile.curvature_features(VIRTUAL_RADIUS)]  # fmt: skip
    out = []
    idx = np.flatnonzero(sel)
    if idx.size == 0:
        return []
    runs = np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1)
    for run in runs:
        if run.size < 20:
            continue
        th = trace["theta"][run]
        c, s = np.cos(-th), np.sin(-th)
        px, py = trace["pLx"][run] - trace["cx"][run], trace["pLy"][run] - trace["cy"][run]
        nx, ny = trace["nLx"][run], trace["nLy"][run]
        P = np.column_stack([c * px - s * py, s * px + c * py])
        N = np.column_stack([c * nx - s * ny, s * nx + c * ny])
        keep = np.concatenate([[True], np.any(np.abs(np.diff(P, axis=0)) > 1e-6, axis=1)])
        P, N = P[keep], N[keep]
        if len(P) < 10:
            continue
        try:
            found = _detect(P, N)
        except Exception:  # noqa: BLE001 - a trace the detector cannot use adds nothing
            continue
        for pos, sign in found:
            a = math.atan2(pos[1], pos[0])
            if truth:
                err = [math.atan2(math.sin(a - b), math.cos(a - b)) for b in truth]
                j = int(np.argmin(np.abs(err)))
                out.append(
                    DetectedFeature(a, "convex" if sign > 0 else "concave", truth[j], err[j])
                )
            else:
                out.append(DetectedFeature(a, "convex" if sign > 0 else "concave"))
    return out


__all__ = ["VIRTUAL_RADIUS", "coverage_of", "detect_pad_features"]
