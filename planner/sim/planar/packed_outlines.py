"""All bodies' compiled outlines packed into two flat arrays for the compiled contact search.

:class:`PackedOutlines` is built once, when the world's bodies are known
(:meth:`PackedOutlines.from_bodies`), from the :class:`~planner.sim.planar.outline.Outline`
of each body. Its arrays are what :mod:`planner.sim.planar.geometry_kernel` reads:

``F`` (float64, 1-D): the first ``nb`` entries are the bodies' bounding radii [m]; then, per
body, its lines (rows ``ax, ay, bx, by, nx, ny``), arcs (:data:`ARC` entries: ``cx, cy, r,
phi0, sweep, convex`` and the directions of the ends, ``cos phi0, sin phi0, cos phi1, sin
phi1`` with ``phi1 = phi0 + sweep``), corners (``cx, cy``), parametric-piece headers
(:data:`PH` entries: ``kind, u0, u1, direction, periodic, ntab, tab, c0x, c0y, c1x, c1y, c2x,
c2y, nblk, blk, m, s``), seed tables (``ntab`` parameters, then ``ntab`` x, then ``ntab`` y) and
the bounding circles ``cx, cy, r`` of the tables' blocks of :data:`BLOCK` samples (at
``blk``; they let the kernel skip most samples when seeding, with the same result), all in
the body frame.

``I`` (int64, ``(nb, 10)``): per body the offsets into ``F`` and counts ``line0, nlines,
arc0, narcs, corner0, ncorners, param0, nparams, known, ends``; ``known`` is 1 when the
kernel handles every piece of the body; ``ends`` is the offset of an open outline's two end
points and the depth of its body behind its face (``x0, y0, x1, y1, depth``; ``depth`` [m]
may be inf, :attr:`~planner.sim.planar.outline.Outline.depth`), -1 for a closed one.

Parametric pieces are recognised by their values, not by their names: a piece whose
``f, df, ddf`` equal, on the whole 257-sample seed table, to 1e-13 of their largest values

* ``c0 + c1 cos u + c2 sin u`` (:data:`TRIG`: ellipses, also rotated and shifted), or
* ``c0 + c1 u + c2 u^2`` (:data:`QUAD`: parabolic bumps and pits), or
* ``c0 + c1 u + c2 exp(-(u - m)^2 / (2 s^2))`` (:data:`GAUSS`: Gaussian bumps and pits),

is evaluated in closed form by the kernel. Any other parametric piece (splines) marks its
body ``known = 0``; pairs with such a body go through the Python
:func:`~planner.sim.planar.contacts.candidates` (same results, slower).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from planner.sim.planar.outline import Outline, ParamPiece

__all__ = [
    "ARC",
    "BLOCK",
    "GAUSS",
    "PH",
    "QUAD",
    "TRIG",
    "PackedOutlines",
    "body_pairs",
    "param_model",
]

TRIG, QUAD, GAUSS = 1, 2, 3
PH = 17  # entries of a parametric-piece header in F
BLOCK = 16  # seed-table samples per bounding circle
ARC = 10  # entries of an arc row in F
FIT_TOL = 1e-13  # recognition tolerance, relative to the piece's size


@dataclass(frozen=True)
class PackedOutlines:
    """The outlines of ``nb`` bodies in the kernel's flat layout (see the module docstring).

    Attributes:
        F: (nf,) float64 geometry [m, rad].
        I: (nb, 10) int64 offsets and counts per body.
        pairs: (np, 2) int64 body pairs ``i < j`` tested by default (from
            :meth:`from_bodies`: every pair except fixed-fixed), in the order of
            :func:`planner.sim.planar.stepper.find_contacts`.
        outlines: the compiled outlines (for the Python fallback).
        all_known: every body is handled by the kernel (no fallback pair).
    """

    F: np.ndarray
    I: np.ndarray  # noqa: E741 - the layout's name
    pairs: np.ndarray
    outlines: tuple[Outline, ...]
    all_known: bool

    @classmethod
    def from_outlines(cls, outlines, pairs=None) -> PackedOutlines:
        """Pack ``outlines`` (sequence of :class:`Outline`); ``pairs`` (np, 2) default: all."""
        outlines = tuple(outlines)
        for k, ol in enumerate(outlines):
            if not isinstance(ol, Outline):
                raise InvalidParameter(
                    f"outlines[{k}]: expected an Outline, got {checks.shown(ol)}"
                )
        nb = len(outlines)
        if pairs is None:
            pairs = [(i, j) for i in range(nb) for j in range(i + 1, nb)]
        P = np.array(pairs, dtype=np.int64).reshape(-1, 2)
        if len(P) and (P.min() < 0 or P.max() >= nb or np.any(P[:, 0] == P[:, 1])):
            raise InvalidParameter(f"pairs: expected distinct body indices in [0, {nb}), got {P}")
        F, I = _pack(outlines)
        return cls(F, I, P, outlines, bool(np.all(I[:, 8] == 1)))

    @classmethod
    def from_bodies(cls, bodies) -> PackedOutlines:
        """Pack the world's ``bodies`` (each with ``.outline`` and ``.kind``); pairs of two
        fixed bodies are left out, as in :func:`planner.sim.planar.stepper.find_contacts`."""
        from planner.sim.planar.bodies import FIXED

        kinds = [b.kind for b in bodies]
        return cls.from_outlines([b.outline for b in bodies], body_pairs(kinds, FIXED))


def body_pairs(kinds, fixed) -> list[tuple[int, int]]:
    """Pairs ``(i, j)``, ``i < j``, of bodies not both of kind ``fixed``, in loop order."""
    n = len(kinds)
    return [
        (i, j)
        for i in range(n)
        for j in range(i + 1, n)
        if not (kinds[i] == fixed and kinds[j] == fixed)
    ]


def _pack(outlines) -> tuple[np.ndarray, np.ndarray]:
    nb = len(outlines)
    chunks: list[np.ndarray] = [np.array([ol.bound for ol in outlines], float)]
    size = nb
    I = np.zeros((nb, 10), np.int64)  # noqa: E741

    def put(a) -> int:
        nonlocal size
        a = np.asarray(a, float).ravel()
        start = size
        chunks.append(a)
        size += len(a)
        return start

    for b, ol in enumerate(outlines):
        I[b, 0], I[b, 1] = put(ol.lines), len(ol.lines)
        I[b, 2], I[b, 3] = put([_arc_row(row) for row in ol.arc_list]), len(ol.arcs)
        I[b, 4], I[b, 5] = put(ol.corners), len(ol.corners)
        models = [param_model(pp) for pp in ol.params]
        known = all(m is not None for m in models)
        heads = np.zeros((len(ol.params), PH))
        for k, (pp, m) in enumerate(zip(ol.params, models, strict=True)):
            kind, c = m if m is not None else (0, np.zeros(8))
            tab = put(np.concatenate([pp.u, pp.pts[:, 0], pp.pts[:, 1]]))
            blocks = _block_circles(pp.pts)
            heads[k, :7] = (kind, pp.u[0], pp.u[-1], pp.direction, pp.periodic, len(pp.u), tab)
            heads[k, 7:13] = c[:6]
            heads[k, 13:15] = (len(blocks), put(blocks))
            heads[k, 15:17] = c[6:]
        I[b, 6], I[b, 7] = put(heads), len(ol.params)
        I[b, 8] = int(known)
        I[b, 9] = put([*np.ravel(ol.ends), ol.depth]) if ol.ends else -1
    return np.concatenate(chunks), I


def _block_circles(pts: np.ndarray) -> np.ndarray:
    """(nblk, 3) circles ``cx, cy, r`` [m] holding each run of :data:`BLOCK` table points
    (radius widened by 1e-9 relative + 1e-15 m: a lower bound survives round-off)."""
    out = []
    for k0 in range(0, len(pts), BLOCK):
        blk = pts[k0 : k0 + BLOCK]
        c = blk.mean(axis=0)
        r = float(np.max(np.hypot(blk[:, 0] - c[0], blk[:, 1] - c[1])))
        out.append((c[0], c[1], r * (1 + 1e-9) + 1e-15))
    return np.array(out, float).reshape(-1, 3)


def _arc_row(row) -> list[float]:
    """An arc's row: its 6 entries and the cos/sin of its end angles (math.cos/sin: the
    values the Python path computes at every query)."""
    phi0, phi1 = row[3], row[3] + row[4]
    return [*row, math.cos(phi0), math.sin(phi0), math.cos(phi1), math.sin(phi1)]


def param_model(pp: ParamPiece):
    """``(kind, (c0x, c0y, c1x, c1y, c2x, c2y, m, s))`` when the piece is one of the closed
    forms of the module docstring (each of c, c', c'' equal on its seed table to 1e-13 of its
    largest value), else None."""
    piece, u = pp.piece, pp.u
    exact = piece.f(u), piece.df(u), piece.ddf(u)
    for kind, fit in ((TRIG, _fit_trig), (QUAD, _fit_quad), (GAUSS, _fit_gauss)):
        try:  # a piece may refuse parameters off its range: then it is not this form
            with np.errstate(all="ignore"):
                c = fit(piece, u)
                model = model_eval(kind, c, u) if c is not None else None
        except (ArithmeticError, ValueError):
            continue
        if model is None:
            continue
        if all(
            np.abs(m - e).max() <= FIT_TOL * max(float(np.abs(e).max()), 1e-300)
            for m, e in zip(model, exact, strict=True)
        ):
            return kind, c
    return None


def _fit_trig(piece, u: np.ndarray) -> np.ndarray:
    g = piece.f(np.array([0.0, np.pi, 0.5 * np.pi, -0.5 * np.pi]))
    c = (0.5 * (g[0] + g[1]), 0.5 * (g[0] - g[1]), 0.5 * (g[2] - g[3]))
    return np.concatenate([*c, (0.0, 0.0)])


def _fit_quad(piece, u: np.ndarray) -> np.ndarray:
    uu = u[:1]
    c2 = 0.5 * piece.ddf(uu)[0]
    c1 = piece.df(uu)[0] - 2.0 * c2 * u[0]
    c0 = piece.f(uu)[0] - c1 * u[0] - c2 * u[0] * u[0]
    return np.concatenate([c0, c1, c2, (0.0, 0.0)])


def _fit_gauss(piece, u: np.ndarray):
    """``c0 + c1 u + c2 exp(-(u - m)^2 / (2 s^2))``: m +- s are the two zeros of c''(u)
    (refined by bisection), then c'' (m) = -c2 / s^2, c'(m) = c1, c(m) = c0 + c1 m + c2."""
    d2 = piece.ddf(u)
    k = int(np.argmax(np.hypot(d2[:, 0], d2[:, 1])))
    e = d2[k] / np.hypot(*d2[k])
    side = np.sign(d2 @ e)
    flips = np.flatnonzero(side[:-1] * side[1:] < 0)
    if len(flips) != 2:
        return None

    def ddf_e(x: float) -> float:
        return float(piece.ddf(np.array([x]))[0] @ e)

    zeros = []
    for i in flips:
        lo, hi = float(u[i]), float(u[i + 1])
        flo = ddf_e(lo)
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if mid in (lo, hi):
                break
            if (ddf_e(mid) < 0) == (flo < 0):
                lo, flo = mid, ddf_e(mid)
            else:
                hi = mid
        zeros.append(0.5 * (lo + hi))
    m, s = 0.5 * (zeros[0] + zeros[1]), 0.5 * abs(zeros[1] - zeros[0])
    mm = np.array([m])
    c2 = -piece.ddf(mm)[0] * s * s
    c1 = piece.df(mm)[0]
    c0 = piece.f(mm)[0] - c1 * m - c2
    return np.concatenate([c0, c1, c2, (m, s)])


def model_eval(kind: int, c: np.ndarray, u: np.ndarray):
    """Points, first and second derivatives (n, 2) of a closed-form piece at ``u`` (n,);
    ``c`` = (c0x, c0y, c1x, c1y, c2x, c2y, m, s)."""
    m, s = float(c[6]), float(c[7])
    c = np.asarray(c[:6], float).reshape(3, 2)
    u = np.asarray(u, float)[:, None]
    if kind == TRIG:
        cu, su = np.cos(u), np.sin(u)
        return c[0] + c[1] * cu + c[2] * su, -c[1] * su + c[2] * cu, -c[1] * cu - c[2] * su
    if kind == GAUSS:
        w = u - m
        g = np.exp(-(w * w) / (2.0 * s * s))
        g1, g2 = -w / (s * s) * g, (w * w / s**4 - 1.0 / (s * s)) * g
        return c[0] + c[1] * u + c[2] * g, c[1] + c[2] * g1, c[2] * g2
    return (
        c[0] + c[1] * u + c[2] * u * u,
        c[1] + 2.0 * c[2] * u,
        np.broadcast_to(2.0 * c[2], (len(u), 2)),
    )
