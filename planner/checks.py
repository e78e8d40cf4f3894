"""The one argument-checking module of hapex: validators for public entry points.

Every validator takes the argument's ``name`` first, then its ``value``, and either returns
the value converted (a ``float``, an ``int`` or a float ``numpy`` array) or raises
:class:`planner.errors.InvalidParameter` with one message that names the argument, the value
received, its unit and what was expected::

    tip_radius: expected a finite number > 0 [m], got -0.008

Validate at the boundary (public functions, constructors of settings objects), never inside
hot loops. This module is a leaf: it imports only :mod:`planner.errors` and numpy.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

from planner.errors import InvalidParameter

__all__ = [
    "batch",
    "boolean",
    "choice",
    "in_range",
    "integer",
    "nonnegative",
    "points",
    "positive",
    "series",
    "shown",
    "vector",
]


#: a value whose repr is longer than this [characters] is shown by its type and size
SHOWN_LENGTH = 60


def shown(value: object) -> str:
    """``value`` as it is quoted in a one-line error message: its repr when short, else its
    type and size (``"an array of shape (200, 2)"``, ``"a list of 40 items"``) or the repr
    cut to :data:`SHOWN_LENGTH` characters - never several lines."""
    text = repr(value)
    if len(text) <= SHOWN_LENGTH and "\n" not in text:
        return text
    if isinstance(value, np.ndarray):
        return f"an array of shape {value.shape}"
    if isinstance(value, (list, tuple, dict, set)):
        return f"a {type(value).__name__} of {len(value)} items"
    flat = " ".join(text.split())
    return flat if len(flat) <= SHOWN_LENGTH else flat[: SHOWN_LENGTH - 3] + "..."


def _unit(unit: str) -> str:
    return f" [{unit}]" if unit else ""


def _number(name: str, value: object, expected: str) -> float:
    if isinstance(value, bool):
        raise InvalidParameter(f"{name}: expected {expected}, got the boolean {value!r}")
    try:
        return float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InvalidParameter(f"{name}: expected {expected}, got {shown(value)}") from None


def positive(
    name: str, value: object, unit: str = "", *, allow_zero: bool = False, allow_inf: bool = False
) -> float:
    """Return ``value`` as a float > 0 (>= 0 with ``allow_zero``; ``inf`` with ``allow_inf``).

    Args:
        name: the argument's name, as the caller spells it.
        value: the value received.
        unit: its SI unit (``"m"``, ``"N"``, ``"rad"`` ...), shown in the message.
        allow_zero: accept 0.
        allow_inf: accept ``+inf``.
    """
    bound = ">= 0" if allow_zero else "> 0"
    finite = "" if allow_inf else "finite "
    expected = f"a {finite}number {bound}{_unit(unit)}"
    v = _number(name, value, expected)
    ok = (v >= 0.0 if allow_zero else v > 0.0) and not math.isnan(v)
    if not ok or (math.isinf(v) and not allow_inf):
        raise InvalidParameter(f"{name}: expected {expected}, got {shown(value)}")
    return v


def nonnegative(name: str, value: object, unit: str = "") -> float:
    """Return ``value`` as a finite float >= 0 (see :func:`positive`)."""
    return positive(name, value, unit, allow_zero=True)


def in_range(
    name: str,
    value: object,
    low: float,
    high: float,
    unit: str = "",
    *,
    closed: tuple[bool, bool] = (True, True),
) -> float:
    """Return ``value`` as a float in the interval from ``low`` to ``high``.

    Args:
        closed: whether each end of the interval is included.
    """
    left = "[" if closed[0] else "("
    right = "]" if closed[1] else ")"
    expected = f"a number in {left}{low:g}, {high:g}{right}{_unit(unit)}"
    v = _number(name, value, expected)
    above = v >= low if closed[0] else v > low
    below = v <= high if closed[1] else v < high
    if not (above and below) or math.isnan(v):
        raise InvalidParameter(f"{name}: expected {expected}, got {shown(value)}")
    return v


def integer(name: str, value: object, minimum: int | None = None) -> int:
    """Return ``value`` as an ``int`` (>= ``minimum`` when given); floats like 3.0 pass."""
    expected = "an integer" + (f" >= {minimum}" if minimum is not None else "")
    if isinstance(value, bool):
        raise InvalidParameter(f"{name}: expected {expected}, got the boolean {value!r}")
    try:
        f = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InvalidParameter(f"{name}: expected {expected}, got {shown(value)}") from None
    if not math.isfinite(f) or f != int(f) or (minimum is not None and f < minimum):
        raise InvalidParameter(f"{name}: expected {expected}, got {shown(value)}")
    return int(f)


def boolean(name: str, value: object) -> bool:
    """Return ``value`` if it is a ``bool`` (numpy's too); anything else is refused (a string
    such as "false" would read as True)."""
    if not isinstance(value, bool | np.bool_):
        raise InvalidParameter(f"{name}: expected true or false, got {shown(value)}")
    return bool(value)


def choice(name: str, value: object, choices: Iterable[object]) -> object:
    """Return ``value`` if it is one of ``choices``; the message lists the choices."""
    options = list(choices)
    if value not in options:
        raise InvalidParameter(f"{name}: expected one of {options}, got {shown(value)}")
    return value


def _array(name: str, value: object, shape_text: str, unit: str) -> np.ndarray:
    try:
        return np.array(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InvalidParameter(
            f"{name}: expected an array of shape {shape_text}{_unit(unit)}, "
            f"got {type(value).__name__} ({exc})"
        ) from None


def _first_bad(name: str, arr: np.ndarray, what: str) -> None:
    if arr.ndim == 0 or np.isfinite(arr).all():  # the common case: one pass, no row scan
        return
    bad = ~np.isfinite(arr.reshape(arr.shape[0], -1)).all(axis=1) if arr.ndim else None
    if bad is not None and bad.any():
        i = int(np.argmax(bad))
        raise InvalidParameter(
            f"{name}: {what} {i} is not finite ({np.asarray(arr[i]).tolist()}); "
            f"{int(bad.sum())} non-finite in all"
        )


def vector(name: str, value: object, size: int, unit: str = "") -> np.ndarray:
    """Return ``value`` as a finite float array of shape ``(size,)`` (a copy)."""
    arr = _array(name, value, f"({size},)", unit)
    if arr.shape != (size,):
        raise InvalidParameter(
            f"{name}: expected shape ({size},){_unit(unit)}, got shape {arr.shape}"
        )
    if not np.all(np.isfinite(arr)):
        raise InvalidParameter(f"{name}: expected finite values, got {arr.tolist()}")
    return arr


def batch(name: str, value: object, size: int, unit: str = "") -> tuple[np.ndarray, bool]:
    """Return ``value`` as a finite ``(N, size)`` array and whether it was a single row."""
    arr = _array(name, value, f"({size},) or (N, {size})", unit)
    single = arr.ndim == 1
    if single:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != size:
        raise InvalidParameter(
            f"{name}: expected shape ({size},) or (N, {size}){_unit(unit)}, "
            f"got shape {np.shape(value)}"
        )
    _first_bad(name, arr, "row")
    return arr, single


def points(
    name: str,
    value: object,
    *,
    dims: tuple[int, ...] = (2, 3),
    n: int | None = None,
    min_count: int = 1,
    unit: str = "m",
) -> np.ndarray:
    """Return ``value`` as a finite float ``(N, D)`` array with ``D`` in ``dims`` (a copy).

    Args:
        n: the exact number of rows required, if any.
        min_count: the least number of rows accepted.
    """
    shape_text = f"(N, {' or '.join(map(str, dims))})"
    arr = _array(name, value, shape_text, unit)
    if arr.ndim != 2 or arr.shape[1] not in dims:
        raise InvalidParameter(
            f"{name}: expected shape {shape_text}{_unit(unit)}, got shape {arr.shape}"
        )
    if n is not None and arr.shape[0] != n:
        raise InvalidParameter(f"{name}: expected {n} rows, got {arr.shape[0]}")
    if arr.shape[0] < min_count:
        raise InvalidParameter(f"{name}: expected at least {min_count} rows, got {arr.shape[0]}")
    _first_bad(name, arr, "row")
    return arr


def series(
    name: str, value: object, *, n: int | None = None, min_count: int = 1, unit: str = ""
) -> np.ndarray:
    """Return ``value`` as a finite 1-D float array ``(N,)`` (a copy)."""
    arr = _array(name, value, "(N,)", unit)
    if arr.ndim != 1:
        raise InvalidParameter(f"{name}: expected a 1-D array (N,), got shape {arr.shape}")
    if n is not None and arr.shape[0] != n:
        raise InvalidParameter(f"{name}: expected {n} samples, got {arr.shape[0]}")
    if arr.shape[0] < min_count:
        raise InvalidParameter(f"{name}: expected at least {min_count} samples, got {arr.shape[0]}")
    _first_bad(name, arr, "sample")
    return arr
