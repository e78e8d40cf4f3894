"""Boundary validators shared by the robot models: shapes and finiteness of array arguments."""

from __future__ import annotations

import numpy as np

from planner.errors import InvalidParameter


def as_vector(value, size: int, name: str) -> np.ndarray:
    """Return ``value`` as a finite float array of shape ``(size,)``.

    Raises:
        InvalidParameter: wrong shape or non-finite entries.
    """
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InvalidParameter(
            f"{name} must be a numeric array of shape ({size},), got {value!r}"
        ) from None
    if arr.shape != (size,):
        raise InvalidParameter(f"{name} must have shape ({size},), got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InvalidParameter(f"{name} must be finite, got {arr.tolist()}")
    return arr


def as_batch(value, size: int, name: str) -> tuple[np.ndarray, bool]:
    """Return ``value`` as a finite ``(N, size)`` array and whether the input was a single row.

    Raises:
        InvalidParameter: wrong trailing dimension or non-finite entries.
    """
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InvalidParameter(
            f"{name} must be a numeric array of shape ({size},) or (N, {size}), got {value!r}"
        ) from None
    single = arr.ndim == 1
    if single:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != size:
        raise InvalidParameter(
            f"{name} must have shape ({size},) or (N, {size}), got shape {np.shape(value)}"
        )
    if not np.all(np.isfinite(arr)):
        raise InvalidParameter(f"{name} must be finite")
    return arr, single


def check_positive(value: float, name: str, unit: str) -> float:
    """Return ``float(value)`` if it is finite and > 0, else raise :class:`InvalidParameter`."""
    v = float(value)
    if not np.isfinite(v) or v <= 0.0:
        raise InvalidParameter(f"{name} must be a finite number > 0 [{unit}], got {value!r}")
    return v


def check_choice(value: str, name: str, choices: tuple[str, ...]) -> str:
    """Return ``value`` if it is one of ``choices``, else raise :class:`InvalidParameter`."""
    if value not in choices:
        raise InvalidParameter(f"{name} must be one of {list(choices)}, got {value!r}")
    return value
