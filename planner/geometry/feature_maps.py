"""Curvature-feature maps and macro features over a surface grid (thesis §3.2.2, Table 3.1).

Definition 1 on a grid, read with Table 3.1 (whose features are labelled by the principal
curvature that creates them, ``|k1| >= |k2|``): a sample is in a *positive* curvature feature
where ``k1 > 1/r_f`` and in a *negative* one where ``k1 < -1/r_f``; since ``|k2| <= |k1|``
every sample where some ``|k_i| > 1/r_f`` is in exactly one of them. Connected regions
(8-neighbourhood) of each sign are the curvature features; each records ``k2`` at its peak,
which tells "both principal curvatures positive" (a bump's cap) from "``k2 = ε``" (a ridge).
Definition 2: features whose distance is at most ``r_f`` form one macro feature (the
``r_f/2`` neighbourhoods of their masks touch). Classification (Table 3.1 read from §3.2.2):

* one feature: ``cusp`` (convex or concave edge);
* one ``+`` feature enclosed by a ``-`` ring, or between two ``-`` features: ``bump`` when the
  second principal curvature at its peak exceeds ``1/r_f``, else ``ridge``;
* the mirror, one ``-`` feature inside ``+``: ``pit`` (``k2 < -1/r_f`` inside) or ``ravine``;
* one ``+`` and one ``-`` feature, neither enclosing the other: ``step``;
* anything else: ``unknown``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter


@dataclass(frozen=True)
class CurvatureRegion:
    """One curvature feature on a grid (Definition 1).

    Attributes:
        label: its label in :attr:`FeatureMap.labels` (positive: ``+`` map, negative: ``-``).
        sign: +1 (convex, ``k > 1/r_f``) or -1 (concave, ``k < -1/r_f``).
        area: area of the region in the ``(u, v)`` plane [m^2 for height fields].
        peak_curvature: most extreme ``k1`` of the region [1/m].
        peak: (2,) ``(u, v)`` of that sample.
        second_curvature: the other principal curvature at the peak [1/m] (``k2`` of the
            inner feature in Table 3.1).
        centroid: (2,) mean ``(u, v)`` of the region.
        direction: principal direction of ``k1`` at the peak (as given, e.g. (3,) world
            coordinates), or ``None`` when no directions were given.
        size: number of grid samples.
    """

    label: int
    sign: int
    area: float
    peak_curvature: float
    peak: np.ndarray
    second_curvature: float
    centroid: np.ndarray
    direction: np.ndarray | None
    size: int


@dataclass(frozen=True)
class MacroRegion:
    """A macro feature on a grid (Definition 2, Table 3.1).

    Attributes:
        kind: ``"bump", "pit", "ridge", "ravine", "step", "cusp"`` or ``"unknown"``.
        members: labels of its curvature regions (see :attr:`FeatureMap.labels`).
        centroid: (2,) area-weighted centroid of the members ``(u, v)``.
    """

    kind: str
    members: tuple[int, ...]
    centroid: np.ndarray


@dataclass(frozen=True)
class FeatureMap:
    """Curvature features and macro features of a surface grid.

    Attributes:
        u: (nu,) and v: (nv,) grid coordinates.
        tip_radius: ``r_f`` [m].
        positive: (nu, nv) int, labels ``1..`` of positive regions (``k1 > 1/r_f``; 0
            elsewhere).
        negative: (nu, nv) int, labels ``1..`` of negative regions (``k1 < -1/r_f``);
            region ``-n`` in :attr:`regions` is label ``n`` here.
        regions: curvature features; positive ones have labels ``+n``, negative ``-n``.
        macros: the macro features.
        macro_labels: (nu, nv) int, index+1 of the macro feature of each sample (0: none).
    """

    u: np.ndarray
    v: np.ndarray
    tip_radius: float
    positive: np.ndarray
    negative: np.ndarray
    regions: tuple[CurvatureRegion, ...]
    macros: tuple[MacroRegion, ...]
    macro_labels: np.ndarray


def _regions(mask, sign, k_sel, k_other, u, v, cell, dirs, ndimage):
    structure = np.ones((3, 3), dtype=bool)
    labels, n = ndimage.label(mask, structure=structure)
    if n == 0:
        return labels, []
    flat = labels.ravel()
    sizes = np.bincount(flat, minlength=n + 1)[1:]
    uu, vv = np.meshgrid(u, v, indexing="ij")
    cu = np.bincount(flat, uu.ravel(), minlength=n + 1)[1:] / sizes
    cv = np.bincount(flat, vv.ravel(), minlength=n + 1)[1:] / sizes
    # peak of each region in O(N): per-label maximum of sign*k, then its first sample
    flat_idx = np.flatnonzero(flat)
    lab = flat[flat_idx]
    val = sign * k_sel.ravel()[flat_idx]
    best = np.full(n + 1, -np.inf)
    np.maximum.at(best, lab, val)
    cand = flat_idx[val == best[lab]]
    _, first = np.unique(flat[cand], return_index=True)
    peaks = zip(*np.unravel_index(cand[first], labels.shape), strict=True)
    out = []
    for i, (pi, pj) in enumerate(peaks):
        direction = None if dirs is None else np.asarray(dirs[pi, pj], float)
        out.append(
            CurvatureRegion(
                label=sign * (i + 1),
                sign=sign,
                area=float(sizes[i] * cell),
                peak_curvature=float(k_sel[pi, pj]),
                peak=np.array([u[pi], v[pj]]),
                second_curvature=float(k_other[pi, pj]),
                centroid=np.array([cu[i], cv[i]]),
                direction=direction,
                size=int(sizes[i]),
            )
        )
    return labels, out


def curvature_feature_map(u, v, k1, k2, tip_radius: float, *, p1=None, p2=None) -> FeatureMap:
    """Curvature features (Definition 1) and macro features (Definition 2) on a grid.

    Args:
        u: (nu,) increasing grid coordinates [m for height fields]; v: (nv,) likewise.
        k1, k2: (nu, nv) principal curvatures [1/m]; re-ordered here so that
            ``|k1| >= |k2|``.
        tip_radius: ``r_f`` [m]; distances for grouping are measured in ``(u, v)``.
        p1, p2: optional (nu, nv, 3) principal directions of ``k1`` and ``k2``.

    Returns:
        The :class:`FeatureMap`.
    """
    from scipy import ndimage

    r = checks.positive("tip_radius", tip_radius, "m")
    u = checks.series("u", u, min_count=2, unit="m")
    v = checks.series("v", v, min_count=2, unit="m")
    k1 = np.asarray(k1, dtype=float)
    k2 = np.asarray(k2, dtype=float)
    for name, k in (("k1", k1), ("k2", k2)):
        if k.shape != (u.size, v.size):
            raise InvalidParameter(
                f"{name}: expected shape (len(u), len(v)) = {(u.size, v.size)} [1/m], got {k.shape}"
            )
        if not np.all(np.isfinite(k)):
            raise InvalidParameter(f"{name}: expected finite curvatures [1/m], got NaN or inf")
    du, dv = float(np.mean(np.diff(u))), float(np.mean(np.diff(v)))
    if du <= 0 or dv <= 0:
        raise InvalidParameter(
            f"u, v: expected increasing grid coordinates [m], got mean steps {du:g}, {dv:g}"
        )
    thr = 1.0 / r
    swap = np.abs(k2) > np.abs(k1)
    k1, k2 = np.where(swap, k2, k1), np.where(swap, k1, k2)
    d1 = None
    if p1 is not None and p2 is not None:
        d1 = np.where(swap[..., None], np.asarray(p2, float), np.asarray(p1, float))
    pos, pos_regions = _regions(k1 > thr, 1, k1, k2, u, v, du * dv, d1, ndimage)
    neg, neg_regions = _regions(k1 < -thr, -1, k1, k2, u, v, du * dv, d1, ndimage)
    regions = tuple(pos_regions + neg_regions)
    macros, macro_labels = _group(pos, neg, regions, r, du, dv, thr, ndimage)
    return FeatureMap(u, v, r, pos, neg, regions, macros, macro_labels)


def _group(pos, neg, regions, r, du, dv, thr, ndimage):
    union = (pos > 0) | (neg > 0)
    if not union.any():
        return (), np.zeros(pos.shape, dtype=int)
    near = ndimage.distance_transform_edt(~union, sampling=(du, dv)) <= r / 2
    groups, n = ndimage.label(near, structure=np.ones((3, 3), dtype=bool))
    by_label = {reg.label: reg for reg in regions}
    members: dict[int, list[int]] = {}
    for labels, sign in ((pos, 1), (neg, -1)):
        if labels.max() == 0:
            continue
        idx = np.arange(1, labels.max() + 1)
        first = ndimage.labeled_comprehension(groups, labels, idx, lambda a: a[0], int, 0)
        for lab, g in zip(idx, first, strict=True):
            members.setdefault(int(g), []).append(sign * int(lab))
    macros = []
    macro_labels = np.zeros(pos.shape, dtype=int)
    for k, g in enumerate(sorted(members)):
        regs = [by_label[m] for m in members[g]]
        kind = _classify(regs, pos, neg, thr, ndimage)
        w = np.array([x.area for x in regs])
        centroid = np.sum([x.centroid * a for x, a in zip(regs, w, strict=True)], 0) / w.sum()
        macros.append(MacroRegion(kind, tuple(members[g]), centroid))
        macro_labels[(groups == g) & union] = k + 1
    return tuple(macros), macro_labels


def _encloses(outer_mask: np.ndarray, inner_mask: np.ndarray, ndimage) -> bool:
    filled = ndimage.binary_fill_holes(outer_mask)
    inside = inner_mask & filled & ~outer_mask
    return bool(inside.sum() >= 0.5 * inner_mask.sum())


def _classify(regs, pos, neg, thr, ndimage) -> str:
    plus = [x for x in regs if x.sign > 0]
    minus = [x for x in regs if x.sign < 0]
    if len(regs) == 1:
        return "cusp"
    for inner, outer, inner_labels, outer_labels, names in (
        (plus, minus, pos, neg, ("bump", "ridge")),
        (minus, plus, neg, pos, ("pit", "ravine")),
    ):
        if len(inner) != 1 or not outer:
            continue
        inner_mask = inner_labels == abs(inner[0].label)
        ring = any(_encloses(outer_labels == abs(o.label), inner_mask, ndimage) for o in outer)
        if ring or len(outer) == 2:
            k2 = inner[0].second_curvature * inner[0].sign
            if k2 > thr:
                return names[0]
            return names[1] if abs(k2) <= thr else "unknown"
    if len(plus) == 1 and len(minus) == 1:
        return "step"
    return "unknown"


def multiscale_feature_maps(x, y, z, tip_radius: float, radii) -> tuple[FeatureMap, ...]:
    """Features of a height grid as fingertips of radii ``r_i >= r_f`` would see them.

    End of §3.2.2: after exploring with radius ``r_f``, only the estimated surface (eq. 3.11,
    the closing of the surface by the ``r_f`` ball) is known; features at scale ``r_i`` are
    the curvature features of that surface with threshold ``1/r_i``. ``r_i < r_f`` is not
    allowed: the unobservable regions cannot reveal finer features.

    Args:
        x: (nx,) uniform [m]; y: (ny,) uniform [m]; z: (nx, ny) heights [m].
        tip_radius: ``r_f`` of the exploring fingertip [m].
        radii: the scales ``r_i`` [m], each ``>= r_f``.

    Returns:
        One :class:`FeatureMap` per radius, in the order given.
    """
    from planner.geometry.surfaces.height_field import grid_principal_curvatures
    from planner.geometry.surfaces.offsets import offset_surfaces

    tip_radius = checks.positive("tip_radius", tip_radius, "m")
    radii = [checks.positive("radii", r, "m") for r in np.atleast_1d(radii)]
    bad = [r for r in radii if not r >= tip_radius]
    if bad:
        raise InvalidParameter(
            f"radii: expected every radius >= tip_radius = {tip_radius!r} [m] (the "
            f"unobservable regions hide finer features), got {bad}"
        )
    estimated = offset_surfaces(x, y, z, tip_radius).estimated
    k1, k2 = grid_principal_curvatures(x, y, estimated)
    return tuple(curvature_feature_map(x, y, k1, k2, r) for r in radii)


__all__ = [
    "CurvatureRegion",
    "FeatureMap",
    "MacroRegion",
    "curvature_feature_map",
    "multiscale_feature_maps",
]
