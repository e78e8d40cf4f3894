"""The contact search of a set of bodies, called from Python (compiled kernel + fallback).

:class:`ContactSearch` holds a :class:`~planner.sim.planar.packed_outlines.PackedOutlines` and
the kernel's scratch buffers; calling it returns the rows
``(i, j, gap, pax, pay, pbx, pby, nx, ny, curvature)`` of
:func:`planner.sim.planar.stepper.find_contacts` from
:func:`planner.sim.planar.geometry_kernel.contacts_into`. A pair with a body holding a
parametric piece the kernel does not know (a Gaussian bump, a spline;
``PackedOutlines.I[b, 8] == 0``) is computed by the Python
:func:`~planner.sim.planar.contacts.candidates` instead, in place (same results, slower).
"""

from __future__ import annotations

import numpy as np

from planner.errors import InvalidParameter
from planner.sim.planar.contacts import Pose, candidates
from planner.sim.planar.geometry_kernel import contacts_into
from planner.sim.planar.packed_outlines import PackedOutlines

__all__ = ["ContactSearch", "find_contacts_packed"]


def _array(x) -> np.ndarray:
    """``x`` as a writable C-contiguous float64 array (one compiled signature)."""
    if (
        type(x) is np.ndarray
        and x.dtype == np.float64
        and x.flags.c_contiguous
        and x.flags.writeable
    ):
        return x
    return np.array(x, dtype=np.float64, order="C")


class ContactSearch:
    """The compiled contact search over one :class:`PackedOutlines`, with its scratch buffers
    (the mutable half of a model/data split: one per world, reused every step).

    Calling it gives :func:`find_contacts_packed`'s rows (a new array each call).
    """

    def __init__(self, packed: PackedOutlines, capacity: int = 32) -> None:
        self.packed = packed
        self._nb = len(packed.outlines)
        self._np = len(packed.pairs)
        self._out = np.empty((max(int(capacity), 1), 10))
        self._counts = np.empty(self._np, np.int64)

    def __call__(self, poses, margins) -> np.ndarray:
        """Rows ``(i, j, gap, pax, pay, pbx, pby, nx, ny, curvature)`` (n, 10); see
        :func:`find_contacts_packed` for the arguments."""
        pk = self.packed
        poses = _array(poses)
        if poses.shape != (self._nb, 3):
            raise InvalidParameter(
                f"poses: expected shape ({self._nb}, 3) [m, m, rad], got {poses.shape}"
            )
        margins = self._margins(margins)
        n = contacts_into(pk.F, pk.I, poses, pk.pairs, margins, self._out, self._counts)
        if n > len(self._out):
            self._out = np.empty((2 * n, 10))
            n = contacts_into(pk.F, pk.I, poses, pk.pairs, margins, self._out, self._counts)
        rows = self._out[:n].copy()
        return rows if pk.all_known else self._fallback(rows, poses, margins)

    def _margins(self, margins) -> np.ndarray:
        if isinstance(margins, float | int):
            return np.full(self._np, float(margins))
        margins = _array(margins)
        if margins.shape == (self._np,):
            return margins
        if margins.size != 1:
            raise InvalidParameter(
                f"margins: expected one float or shape ({self._np},) [m], got {margins.shape}"
            )
        return np.full(self._np, float(margins.ravel()[0]))

    def _fallback(self, rows, poses, margins) -> np.ndarray:
        """Insert the Python candidates of the pairs the kernel skipped, in pair order."""
        pk = self.packed
        parts, at = [], 0
        for k, (i, j) in enumerate(pk.pairs):
            c = int(self._counts[k])
            if c >= 0:
                parts.append(rows[at : at + c])
                at += c
                continue
            oa, ob = pk.outlines[i], pk.outlines[j]
            got = candidates(oa, Pose(*poses[i]), ob, Pose(*poses[j]), float(margins[k]))
            parts.append(np.array([(i, j, *g) for g in got], float).reshape(-1, 10))
        return np.concatenate(parts) if parts else rows


def find_contacts_packed(packed: PackedOutlines, poses, margins) -> np.ndarray:
    """Contact candidates of the packed bodies at ``poses``.

    Args:
        packed: the bodies' outlines and the pairs to test.
        poses: (nb, 3) ``[x, y, angle]`` of each body's outline frame [m, rad].
        margins: (np,) per pair of ``packed.pairs`` (or one float): candidates with a gap
            below it are returned [m].

    Returns:
        (n, 10) rows ``(i, j, gap, pax, pay, pbx, pby, nx, ny, curvature)``: body indices (as
        floats), gap [m], touching points on i and on j [m], unit normal from j toward i,
        curvature of the touching feature [1/m] (inf at corners) - the tuples of
        :func:`planner.sim.planar.stepper.find_contacts`, in its order. A stepping loop keeps
        one :class:`ContactSearch` instead (same rows, no buffer allocation per call).
    """
    return ContactSearch(packed)(poses, margins)
