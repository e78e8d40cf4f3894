"""Argument checks shared by the public functions of the detection package."""

from __future__ import annotations

import numpy as np

from planner.errors import InvalidParameter

MIN_SAMPLES = 8


def as_points(
    name: str,
    value,
    *,
    n: int | None = None,
    dims: tuple[int, ...] = (2, 3),
    min_samples: int = MIN_SAMPLES,
) -> np.ndarray:
    """Return ``value`` as a finite float array of shape (N, D) with D in ``dims``.

    Raises:
        InvalidParameter: wrong shape, too few rows, a row count other than ``n``, or
            non-finite values (the first bad row is named).
    """
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InvalidParameter(
            f"{name}: expected an (N, 2) or (N, 3) array of numbers [m], "
            f"got {type(value).__name__} ({exc})"
        ) from None
    if arr.ndim != 2 or arr.shape[1] not in dims:
        raise InvalidParameter(
            f"{name}: expected shape (N, {' or '.join(map(str, dims))}), got {arr.shape}"
        )
    if n is not None and arr.shape[0] != n:
        raise InvalidParameter(
            f"{name}: expected {n} rows (one per fingertip-centre sample), got {arr.shape[0]}"
        )
    if arr.shape[0] < min_samples:
        raise InvalidParameter(
            f"{name}: expected at least {min_samples} samples, got {arr.shape[0]}"
        )
    bad = ~np.isfinite(arr).all(axis=1)
    if bad.any():
        i = int(np.argmax(bad))
        raise InvalidParameter(
            f"{name}: row {i} is not finite ({arr[i].tolist()}); "
            f"{int(bad.sum())} non-finite rows in all"
        )
    return arr


def as_series(
    name: str, value, *, n: int | None = None, min_samples: int = MIN_SAMPLES
) -> np.ndarray:
    """Return ``value`` as a finite 1-D float array (N,)."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InvalidParameter(
            f"{name}: expected a 1-D array of numbers, got {type(value).__name__} ({exc})"
        ) from None
    if arr.ndim != 1:
        raise InvalidParameter(f"{name}: expected a 1-D array (N,), got shape {arr.shape}")
    if n is not None and arr.shape[0] != n:
        raise InvalidParameter(f"{name}: expected {n} samples, got {arr.shape[0]}")
    if arr.shape[0] < min_samples:
        raise InvalidParameter(
            f"{name}: expected at least {min_samples} samples, got {arr.shape[0]}"
        )
    bad = ~np.isfinite(arr)
    if bad.any():
        i = int(np.argmax(bad))
        raise InvalidParameter(f"{name}: sample {i} is not finite ({arr[i]})")
    return arr


def positive(name: str, value, unit: str = "m") -> float:
    """Return ``value`` as a float > 0 or raise :class:`InvalidParameter`."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InvalidParameter(
            f"{name}: expected a positive number [{unit}], got {value!r}"
        ) from None
    if not np.isfinite(v) or v <= 0:
        raise InvalidParameter(f"{name}: expected a positive number [{unit}], got {v!r}")
    return v


def choice(name: str, value, choices) -> object:
    """Return ``value`` if it is one of ``choices`` or raise :class:`InvalidParameter`."""
    if value not in choices:
        raise InvalidParameter(f"{name}: got {value!r}; expected one of {list(choices)}")
    return value
