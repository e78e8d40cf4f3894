"""Scoring detected curvature features against ground truth (issue #6 §4)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter


@dataclass(frozen=True)
class Score:
    """Detection quality of one run.

    Attributes:
        tp, fp, fn: true positives, false positives, false negatives.
        precision: tp / (tp + fp) (1 when nothing was detected and nothing was there).
        recall: tp / (tp + fn) (1 when there was nothing to find).
        f1: harmonic mean of precision and recall (0 when both are 0).
        localization: mean distance between matched detected and true features [m]
            (NaN when nothing matched).
        tolerance: largest distance of a match [m].
        matches: ((detected index, truth index, distance [m]), ...), indices into the
            (merged) lists.
    """

    tp: int
    fp: int
    fn: int
    precision: float
    recall: float
    f1: float
    localization: float
    tolerance: float
    matches: tuple[tuple[int, int, float], ...]


def _coords(f, key: str) -> np.ndarray:
    if key == "position":
        return np.atleast_1d(np.asarray(f.position, dtype=float))
    return np.atleast_1d(float(getattr(f, key)))


def merge_truth(truth: Sequence, tolerance: float, key: str = "position") -> list:
    """Same-sign true features closer than ``tolerance`` to the previous one count once
    (a detector matching within ``tolerance`` cannot tell them apart)."""
    out: list = []
    for f in truth:
        if (
            out
            and out[-1].sign == f.sign
            and np.linalg.norm(_coords(out[-1], key) - _coords(f, key)) < tolerance
        ):
            continue
        out.append(f)
    return out


def score_features(
    detected: Sequence,
    truth: Sequence,
    tolerance: float,
    *,
    key: str = "position",
    merge: bool = False,
) -> Score:
    """Match detected features to true ones (same sign, distance <= ``tolerance``,
    one-to-one, closest pairs first) and count.

    Args:
        detected: detected features (``.sign`` and ``.position``, or the attribute ``key``).
        truth: true features, in path order.
        tolerance: largest matching distance [m] (the issue's default is ``tip_radius / 2``).
        key: ``"position"`` (Euclidean distance of the points [m]) or a scalar attribute such
            as ``"peak"`` (distance along the path, or in time for the App. B.2 scheme).
        merge: merge same-sign features closer than ``tolerance`` first, in the truth and
            in the detections alike (:func:`merge_truth`). Off by default: for what a
            fingertip cannot see, score against observable ground truth instead
            (``SyntheticTrace.observable``).

    Returns:
        A :class:`Score`.
    """
    tol = checks.positive("tolerance", tolerance, "m")
    if key not in ("position", "peak", "start", "end"):
        raise InvalidParameter(
            f"key: got {key!r}; expected one of ['position', 'peak', 'start', 'end']"
        )
    det = merge_truth(list(detected), tol, key) if merge else list(detected)
    tru = merge_truth(list(truth), tol, key) if merge else list(truth)
    pairs = []
    for i, d in enumerate(det):
        for j, t in enumerate(tru):
            if d.sign != t.sign:
                continue
            a, b = _coords(d, key), _coords(t, key)
            if a.shape != b.shape:
                raise InvalidParameter(
                    f"detected[{i}] and truth[{j}] have positions of "
                    f"different dimension: {a.shape} vs {b.shape}"
                )
            dist = float(np.linalg.norm(a - b))
            if dist <= tol:
                pairs.append((dist, i, j))
    pairs.sort()
    used_d, used_t, matches = set(), set(), []
    for dist, i, j in pairs:
        if i in used_d or j in used_t:
            continue
        used_d.add(i)
        used_t.add(j)
        matches.append((i, j, dist))
    tp = len(matches)
    fp, fn = len(det) - tp, len(tru) - tp
    precision = tp / (tp + fp) if tp + fp else (1.0 if fn == 0 else 0.0)
    recall = tp / (tp + fn) if tp + fn else 1.0
    f1 = 2 * precision * recall / (precision + recall) if precision + recall else 0.0
    loc = float(np.mean([m[2] for m in matches])) if matches else float("nan")
    return Score(tp, fp, fn, precision, recall, f1, loc, tol, tuple(sorted(matches)))


__all__ = ["Score", "merge_truth", "score_features"]
