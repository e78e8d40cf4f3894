"""A convex QP stated once, validated at construction (the qpsolvers convention).

::

    minimize    1/2 x^T P x + q^T x
    subject to  G x <= h,   A x = b,   lb <= x <= ub

:class:`QPProblem` checks every shape and value when it is built, so a backend never sees
inconsistent data, and it can be written to / read from an ``.npz`` file to replay a failed
solve (see :meth:`planner.errors.InfeasibleProblem.save`).
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

from planner import checks
from planner.errors import InvalidParameter

__all__ = ["QPProblem"]

_KEYS = ("P", "q", "G", "h", "A", "b", "lb", "ub")


def _matrix(name: str, value: object, cols: int, rows: int | None = None) -> np.ndarray:
    """``value`` as a finite float ``(rows, cols)`` array (any row count when ``rows`` is None)."""
    want = f"({'m' if rows is None else rows}, {cols})"
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise InvalidParameter(
            f"{name}: expected a matrix of shape {want}, got {type(value).__name__}"
        ) from None
    if arr.ndim == 1 and rows is None and arr.size == cols:
        arr = arr[None, :]  # one constraint row given as a vector
    if arr.ndim != 2 or arr.shape[1] != cols or (rows is not None and arr.shape[0] != rows):
        raise InvalidParameter(f"{name}: expected shape {want}, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InvalidParameter(f"{name}: expected finite entries, got NaN or inf")
    return arr


def _bound(name: str, value: object, size: int, forbidden: float) -> np.ndarray:
    """A bound vector that may hold infinities of the harmless sign (``-inf`` in ``lb``)."""
    try:
        arr = np.array(value, dtype=float).ravel()
    except (TypeError, ValueError):
        raise InvalidParameter(
            f"{name}: expected an array of shape ({size},), got {type(value).__name__}"
        ) from None
    if arr.shape != (size,):
        raise InvalidParameter(f"{name}: expected shape ({size},), got shape {arr.shape}")
    if np.any(np.isnan(arr)) or np.any(arr == forbidden):
        raise InvalidParameter(
            f"{name}: expected numbers (or {-forbidden:+g} for no bound), got {arr.tolist()}"
        )
    return arr


@dataclass(frozen=True)
class QPProblem:
    """A convex quadratic program, checked at construction.

    Attributes:
        P: (n, n) symmetric positive semi-definite cost matrix (zeros for an LP).
        q: (n,) linear cost.
        G, h: (m, n) and (m,) inequalities ``G x <= h``, or both ``None``.
        A, b: (p, n) and (p,) equalities ``A x = b``, or both ``None``.
        lb, ub: (n,) bounds (``-inf`` / ``+inf`` entries mean no bound), or ``None``.

    Units are those of the caller's rows (forces [N], torques [N m] ...).

    Raises:
        InvalidParameter: a wrong shape, NaN, an unpaired ``G``/``h`` or ``A``/``b``, a
            non-symmetric ``P`` or ``lb > ub``.
    """

    P: np.ndarray
    q: np.ndarray
    G: np.ndarray | None = None
    h: np.ndarray | None = None
    A: np.ndarray | None = None
    b: np.ndarray | None = None
    lb: np.ndarray | None = None
    ub: np.ndarray | None = None

    def __post_init__(self) -> None:
        q = np.atleast_1d(np.asarray(self.q, dtype=float)).ravel()
        q = checks.vector("q", q, q.size)
        n = q.size
        P = _matrix("P", self.P, n, n)
        if not np.allclose(P, P.T, rtol=1e-10, atol=1e-12 * max(1.0, float(np.abs(P).max()))):
            raise InvalidParameter("P: expected a symmetric matrix, got P != P^T")
        out = {"P": P, "q": q}
        for M, v in (("G", "h"), ("A", "b")):
            mat, vec = getattr(self, M), getattr(self, v)
            if (mat is None) != (vec is None):
                raise InvalidParameter(
                    f"{M}, {v}: expected both or neither, got only {M if vec is None else v}"
                )
            if mat is not None:
                out[M] = _matrix(M, mat, n)
                out[v] = checks.vector(v, np.ravel(vec), out[M].shape[0])
        for name, forbidden in (("lb", np.inf), ("ub", -np.inf)):
            if getattr(self, name) is not None:
                out[name] = _bound(name, getattr(self, name), n, forbidden)
        if "lb" in out and "ub" in out and np.any(out["lb"] > out["ub"]):
            i = int(np.argmax(out["lb"] > out["ub"]))
            raise InvalidParameter(
                f"lb, ub: expected lb <= ub, got lb[{i}] = {out['lb'][i]:g} > ub[{i}] = "
                f"{out['ub'][i]:g}"
            )
        for key, value in out.items():
            object.__setattr__(self, key, value)

    @property
    def n(self) -> int:
        """Number of variables."""
        return self.q.size

    @classmethod
    def lp(cls, c, G=None, h=None, A=None, b=None, lb=None, ub=None) -> QPProblem:
        """The LP ``min c^T x`` under the same constraints (``P = 0``)."""
        c = np.atleast_1d(np.asarray(c, dtype=float)).ravel()
        return cls(np.zeros((c.size, c.size)), c, G, h, A, b, lb, ub)

    def unpack(self) -> tuple:
        """``(P, q, G, h, A, b, lb, ub)``, as qpsolvers' ``Problem.unpack``."""
        return tuple(getattr(self, k) for k in _KEYS)

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The arrays that are set, by name (what :meth:`save` writes)."""
        return {
            f.name: getattr(self, f.name) for f in fields(self) if getattr(self, f.name) is not None
        }

    def save(self, path: str | Path) -> Path:
        """Write the problem to ``path`` (``.npz``); :meth:`load` reads it back."""
        path = Path(path)
        np.savez(path, **self.to_arrays())
        return path if path.suffix == ".npz" else path.with_name(path.name + ".npz")

    @classmethod
    def load(cls, path: str | Path) -> QPProblem:
        """Read a problem written by :meth:`save` or :meth:`planner.errors.InfeasibleProblem.save`.

        Raises:
            InvalidParameter: the file holds no ``P`` and ``q`` arrays.
        """
        with np.load(Path(path), allow_pickle=False) as data:
            if "P" not in data or "q" not in data:
                raise InvalidParameter(
                    f"path: expected an .npz file with arrays P and q, got {sorted(data.files)} "
                    f"in {path}"
                )
            return cls(**{k: data[k] for k in _KEYS if k in data})
