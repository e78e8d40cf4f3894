"""Boundary validators shared by the skeleton modules (raise :class:`InvalidParameter`)."""

from __future__ import annotations

import math

import numpy as np

from planner.errors import InvalidParameter


def check_points(points: object, name: str = "boundary", min_count: int = 1) -> np.ndarray:
    """Return ``points`` as a finite float (M, 2) array or raise :class:`InvalidParameter`.

    Args:
        points: array-like of 2-D points [m].
        name: argument name used in error messages.
        min_count: the least number of points accepted.

    Returns:
        (M, 2) float64 array (a copy).
    """
    try:
        arr = np.array(points, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InvalidParameter(
            f"{name}: expected an (M, 2) array of points [m], got an object numpy cannot "
            f"convert to floats ({exc})"
        ) from None
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise InvalidParameter(
            f"{name}: expected shape (M, 2) (one row per point, columns x, y [m]), "
            f"got shape {arr.shape}"
        )
    if arr.shape[0] < min_count:
        raise InvalidParameter(f"{name}: expected at least {min_count} points, got {arr.shape[0]}")
    bad = ~np.isfinite(arr).all(axis=1)
    if bad.any():
        raise InvalidParameter(
            f"{name}: expected finite coordinates, got NaN/inf in row(s) "
            f"{np.flatnonzero(bad)[:5].tolist()}"
        )
    return arr


def check_positive(
    value: object, name: str, allow_none: bool = True, allow_zero: bool = False
) -> float | None:
    """Return ``value`` as a float > 0 (or >= 0, or ``None``) or raise InvalidParameter."""
    if value is None:
        if allow_none:
            return None
        raise InvalidParameter(f"{name}: expected a positive number, got None")
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InvalidParameter(f"{name}: expected a number, got {value!r}") from None
    ok = math.isfinite(v) and (v >= 0 if allow_zero else v > 0)
    if not ok:
        expected = ">= 0" if allow_zero else "> 0"
        raise InvalidParameter(f"{name}: expected a finite number {expected}, got {value!r}")
    return v


def dedupe(points: np.ndarray) -> np.ndarray:
    """Drop exactly repeated rows of ``points`` (M, 2), keeping the first occurrence in order."""
    _, first = np.unique(points, axis=0, return_index=True)
    if first.size == points.shape[0]:
        return points
    return points[np.sort(first)]
