"""2-D object profiles as exact geometry (thesis §3.2.1, §3.4).

A :class:`Profile` is a chain of exact pieces (:mod:`planner.geometry.primitives`). Open
profiles run in +x with the material below; closed profiles run clockwise (material on the
right of travel). The outward normal is the left normal of the direction of travel and the
curvature is signed outward-positive (convex > 0, thesis eq. 3.17). Sharp corners are
sampled as *fans*: the same point repeated with its normal turning from one side's normal to
the other's, curvature ±inf (convex +inf, concave -inf). Offsetting the samples along their
normals then gives the exact parallel curve, fans included (Fig. 3.2).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from planner.geometry.features import CurvatureFeature, threshold_runs
from planner.geometry.primitives import Arc, Line, Piece, joint_turn, left_normal


@dataclass(frozen=True)
class CurveSamples:
    """Samples of a profile.

    Attributes:
        points: (N, 2) positions [m].
        normals: (N, 2) outward unit normals.
        curvature: (N,) outward curvature [1/m]; ±inf on corner fans.
        s: (N,) arclength from the start [m] (fan samples share their corner's s).
        corner: (N,) True on corner-fan samples.
    """

    points: np.ndarray
    normals: np.ndarray
    curvature: np.ndarray
    s: np.ndarray
    corner: np.ndarray


#: former name of the profile's ground-truth features, kept for :mod:`planner.geometry.curves`
ProfileFeature = CurvatureFeature


@dataclass(frozen=True)
class Profile:
    """An exact 2-D profile: a chain of pieces, open or closed.

    Attributes:
        pieces: the pieces in traversal order; consecutive pieces share end points.
        closed: whether the last piece ends at the first one's start.
        name: a label for plots and reports.
        exact_polar: optional closed-form ``theta -> (points, normals)`` used by
            :meth:`point_at_polar_angle` (circles, ellipses).
    """

    pieces: tuple[Piece, ...]
    closed: bool = False
    name: str = "profile"
    exact_polar: object = field(default=None, compare=False, repr=False)
    _cache: dict = field(default_factory=dict, compare=False, repr=False)

    @cached_property
    def piece_lengths(self) -> np.ndarray:
        return np.array([p.length for p in self.pieces])

    @property
    def length(self) -> float:
        """Total arclength [m]."""
        return float(self.piece_lengths.sum())

    @cached_property
    def joint_turns(self) -> np.ndarray:
        """Turning angle at the end of each piece [rad] (left/concave positive); the last
        entry is the closing joint for closed profiles and 0 for open ones."""
        n = len(self.pieces)
        out = np.zeros(n)
        for i in range(n - 1 + int(self.closed)):
            out[i] = joint_turn(self.pieces[i], self.pieces[(i + 1) % n])
        out[np.abs(out) < 1e-9] = 0.0
        return out

    def _stretch(self, i: int, offset: float | None) -> float:
        """Largest factor 1 + offset |k| by which offsetting piece i stretches it."""
        if not offset:
            return 1.0
        piece = self.pieces[i]
        if isinstance(piece, Line):
            return 1.0
        if isinstance(piece, Arc):
            kmax = 1.0 / piece.radius
        else:
            _, _, k = piece.evaluate(np.linspace(0.0, self.piece_lengths[i], 513))
            kmax = float(np.max(np.abs(k)))
        return 1.0 + offset * kmax

    def sample(self, spacing: float, fan_radius: float | None = None) -> CurveSamples:
        """Sample the profile at about ``spacing`` [m] along each piece.

        Args:
            spacing: maximum distance between samples along a piece [m].
            fan_radius: the offset the samples are meant for [m]: curved pieces are sampled
                finely enough that their offset by ``fan_radius`` keeps about ``spacing``,
                and corner fans get samples every ``spacing / fan_radius`` [rad]; default:
                fans every 5°.

        Returns:
            :class:`CurveSamples`; for closed profiles the first point is not repeated.
        """
        if not spacing > 0:
            raise InvalidParameter(f"spacing must be > 0 [m], got {spacing!r}")
        key = (float(spacing), fan_radius)
        if key in self._cache:
            return self._cache[key]
        dphi = np.deg2rad(5.0) if not fan_radius else min(spacing / fan_radius, np.deg2rad(5))
        pts, tans, ks, ss, corner = [], [], [], [], []
        s0 = 0.0
        n = len(self.pieces)
        turns = self.joint_turns
        for i, piece in enumerate(self.pieces):
            L = self.piece_lengths[i]
            m = max(1, int(np.ceil(L * self._stretch(i, fan_radius) / spacing)))
            sig = np.linspace(0.0, L, m + 1)
            if i > 0 and turns[i - 1] == 0.0:
                sig = sig[1:]  # the joint point was emitted by the previous piece
            if i == n - 1 and self.closed and turns[i] == 0.0:
                sig = sig[:-1]  # closes smoothly onto the first point
            p, t, k = piece.evaluate(sig)
            pts.append(p)
            tans.append(t)
            ks.append(k)
            ss.append(s0 + sig)
            corner.append(np.zeros(len(sig), bool))
            s0 += L
            turn = turns[i]
            if turn != 0.0:
                # fan: the corner point with the tangent turning strictly between the
                # incoming (end of this piece) and outgoing (start of the next) tangents
                _, t_end, _ = piece.evaluate(np.array([L]))
                a0 = np.arctan2(t_end[0, 1], t_end[0, 0])
                cnt = max(2, int(np.ceil(abs(turn) / dphi)))
                ang = a0 + turn * np.arange(1, cnt) / cnt
                end_pt, _, _ = piece.evaluate(np.array([L]))
                pts.append(np.repeat(end_pt, len(ang), axis=0))
                tans.append(np.stack([np.cos(ang), np.sin(ang)], axis=-1))
                ks.append(np.full(len(ang), -np.inf if turn > 0 else np.inf))
                ss.append(np.full(len(ang), s0))
                corner.append(np.ones(len(ang), bool))
        P = np.concatenate(pts)
        T = np.concatenate(tans)
        K = np.concatenate(ks)
        S = np.concatenate(ss)
        C = np.concatenate(corner)
        out = CurveSamples(P, left_normal(T), K, S, C)
        if len(self._cache) < 8:
            self._cache[key] = out
        return out

    # ------------------------------------------------------------------ queries
    def evaluate(self, s: np.ndarray | float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Points (n, 2), outward normals (n, 2) and curvature (n,) at arclengths ``s`` [m].

        At a joint the later piece is used. ``s`` is clipped to [0, length].
        """
        s = np.atleast_1d(np.asarray(s, float))
        edges = np.concatenate([[0.0], np.cumsum(self.piece_lengths)])
        idx = np.clip(np.searchsorted(edges, s, side="right") - 1, 0, len(self.pieces) - 1)
        P = np.empty((len(s), 2))
        N = np.empty((len(s), 2))
        K = np.empty(len(s))
        for i in np.unique(idx):
            m = idx == i
            sig = np.clip(s[m] - edges[i], 0.0, self.piece_lengths[i])
            p, t, k = self.pieces[i].evaluate(sig)
            P[m], N[m], K[m] = p, left_normal(t), k
        return P, N, K

    def transformed(self, angle: float = 0.0, offset=(0.0, 0.0)) -> Profile:
        """The profile rotated by ``angle`` [rad] about the origin, then translated by
        ``offset`` (2,) [m]."""
        c, s_ = np.cos(angle), np.sin(angle)
        R = np.array([[c, -s_], [s_, c]])
        d = np.asarray(offset, float)
        return Profile(tuple(p.transformed(R, d) for p in self.pieces), self.closed, self.name)

    def curvature_features(self, tip_radius: float) -> list[CurvatureFeature]:
        """Ground-truth curvature features for a fingertip of radius ``tip_radius`` [m]
        (Definition 1: regions with k > 1/r_f or k < -1/r_f).

        Arcs are exact; sharp corners are features of zero length; smooth parametric pieces
        are resolved on a fine grid (1e-4 of the piece length) with linear interpolation of
        the threshold crossings. Adjacent features of equal sign are merged.
        """
        thr = 1.0 / checks.positive("tip_radius", tip_radius, "m")
        raw: list[list] = []  # [sign, start, end, peak, peak_k]
        s0 = 0.0
        n = len(self.pieces)
        for i, piece in enumerate(self.pieces):
            L = self.piece_lengths[i]
            if isinstance(piece, Arc):
                k = -np.sign(piece.sweep) / piece.radius
                if abs(k) > thr:
                    raw.append([int(np.sign(k)), s0, s0 + L, s0 + L / 2, k])
            elif not isinstance(piece, Line):
                raw += _parametric_features(piece, s0, L, thr)
            s0 += L
            turn = self.joint_turns[i]
            if turn != 0.0 and (i < n - 1 or self.closed):
                sign = -1 if turn > 0 else 1
                at = s0 if i < n - 1 else 0.0
                raw.append([sign, at, at, at, sign * np.inf])
        raw.sort(key=lambda f: f[1])
        merged: list[list] = []
        for f in raw:
            if merged and merged[-1][0] == f[0] and f[1] - merged[-1][2] <= 1e-12:
                prev = merged[-1]
                if abs(f[4]) > abs(prev[4]):
                    prev[3], prev[4] = f[3], f[4]
                prev[2] = max(prev[2], f[2])
            else:
                merged.append(list(f))
        out = []
        for sign, a, b, pk, kk in merged:
            pos, _, _ = self.evaluate(pk)
            out.append(
                CurvatureFeature(
                    sign=int(sign),
                    start=float(a),
                    end=float(b),
                    peak=float(pk),
                    position=pos[0].copy(),
                    peak_curvature=float(kk),
                )
            )
        return out

    def point_at_polar_angle(self, theta) -> tuple[np.ndarray, np.ndarray]:
        """Points and outward normals at polar angles ``theta`` [rad] about the origin.

        For closed profiles star-shaped about the object frame's origin: the contact angle
        convention of the grasp maps (counter-clockwise from the object x-axis). Computed on
        a dense table (length/20000 spacing) with linear interpolation.

        Returns:
            (points (n, 2) [m], outward unit normals (n, 2)).
        """
        if not self.closed:
            raise InvalidParameter("point_at_polar_angle needs a closed profile")
        theta = np.atleast_1d(np.asarray(theta, float))
        if self.exact_polar is not None:
            return self.exact_polar(theta)
        if "polar" not in self._cache:
            smp = self.sample(self.length / 20000.0)
            # one sample per point: a sharp corner gets the bisector of its fan's normals
            P, N = smp.points, smp.normals
            # a point repeats within round-off (a fan, a corner where two pieces meet,
            # the closing sample): 1e-12 of the length, not exact equality (pieces ending
            # at a sharp corner meet 1e-18 m apart)
            tol = 1e-12 * self.length
            new = np.ones(len(P), bool)
            new[1:] = np.hypot(*(P[1:] - P[:-1]).T) > tol
            if np.hypot(*(P[-1] - P[0])) <= tol:  # the closing sample is the first one
                new[-1] = False
            grp = np.cumsum(new) - 1
            Nsum = np.zeros((int(grp[-1]) + 1, 2))
            np.add.at(Nsum, grp, N)
            P = P[new]
            N = Nsum / np.linalg.norm(Nsum, axis=1, keepdims=True)
            phi = np.unwrap(np.arctan2(P[:, 1], P[:, 0]))
            if phi[-1] > phi[0]:
                raise InvalidParameter("profile is not traversed clockwise")
            order = np.argsort(phi)
            phi, P, N = phi[order], P[order], N[order]
            if np.any(np.diff(phi) <= 0):
                raise InvalidParameter("profile is not star-shaped about its origin")
            # periodic extension
            phi = np.concatenate([phi - 2 * np.pi, phi, phi + 2 * np.pi])
            P = np.concatenate([P, P, P])
            N = np.concatenate([N, N, N])
            self._cache["polar"] = (phi, P, N)
        phi, P, N = self._cache["polar"]
        th = np.mod(theta - phi[len(phi) // 3], 2 * np.pi) + phi[len(phi) // 3]
        pts = np.stack([np.interp(th, phi, P[:, 0]), np.interp(th, phi, P[:, 1])], axis=-1)
        nrm = np.stack([np.interp(th, phi, N[:, 0]), np.interp(th, phi, N[:, 1])], axis=-1)
        nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
        return pts, nrm


def _crossing_at(sig: np.ndarray, k: np.ndarray, i: int, j: int, level: float) -> float:
    """Where ``k`` (linear between samples ``i`` and ``j``) equals ``level``, in ``sig``."""
    return float(np.interp(level, [k[i], k[j]], [sig[i], sig[j]]))


def _parametric_features(piece: Piece, s0: float, length: float, thr: float) -> list[list]:
    """Definition 1 features ``[sign, start, end, peak, peak_k]`` of a smooth parametric
    piece starting at arclength ``s0`` [m], on a grid of 1e-4 of its ``length`` [m] with
    linearly interpolated threshold crossings (``thr`` = 1/r_f [1/m])."""
    sig = np.linspace(0.0, length, 10001)
    _, _, k = piece.evaluate(sig)
    last = len(k) - 1
    out = []
    for sign, a, b, j in threshold_runs(k, thr, -thr):
        sk = sign * k
        sa = sig[a] if a == 0 else _crossing_at(sig, sk, a - 1, a, thr)
        sb = sig[b] if b == last else _crossing_at(sig, sk, b + 1, b, thr)
        out.append([sign, s0 + sa, s0 + sb, s0 + sig[j], float(k[j])])
    return out
