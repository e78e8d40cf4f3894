"""Fingertip traces: the one trace type of hapex and the one trace simulator (thesis
§3.2.1-3.2.2, §3.4.1-3.4.2).

A :class:`FingertipTrace` is what a fingertip sliding over a surface records: time stamps,
fingertip-centre positions (joint sensing), and optionally the tactile contact points and
contact normals. It is produced by

- :func:`simulate_trace` over a :class:`~planner.geometry.profiles.Profile` (samples at
  equal arclength of the exact traced curve, Gaussian sensor noise as in the thesis'
  apparatus: centre ±0.2 mm, contact ±0.5 mm, normal ±1°), with its ground truth
  (:class:`TraceTruth`);
- :func:`planner.detection.read_trace_file` from a user's CSV/NPZ log (no ground truth);
- (later) the contact simulator.

The ground truth of a simulation includes the *observable* features: a fingertip cannot tell
apart two same-sign features inside one unobservable region (a gap of the contact locus,
between the two contacts of an interference point, §3.2.1), nor two it passes within r_f/4
of path length; those count as one, at their mean position.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from planner import checks
from planner.errors import InvalidParameter
from planner.geometry.curves import arclength, traced_curve
from planner.geometry.features import CurvatureFeature
from planner.geometry.profiles import Profile

DEFAULT_SPEED = 0.03  # average finger speed in the experiments of §3.4.2 [m/s]
#: centre-position noise of the thesis' apparatus, 1 sigma [m] (App. B Table B.1: ~1e-4)
THESIS_CENTER_SIGMA = 1.0e-4
#: contact-position noise, 1 sigma [m] (§3.4.2: contact location within ±0.5 mm)
THESIS_CONTACT_SIGMA = 2.5e-4
#: contact-normal noise, 1 sigma [rad] (§3.4.2: the sensor error is about ±1 degree)
THESIS_NORMAL_SIGMA = float(np.deg2rad(1.0))


@dataclass(frozen=True, eq=False)
class TraceTruth:
    """The ground truth of a simulated trace.

    Attributes:
        profile: the traced object profile (open, material below / right of travel).
        s: (N,) arclength of the true fingertip-centre path at each sample [m].
        centers: (N, 2) noise-free fingertip-centre positions [m].
        contacts: (N, 2) noise-free contact points [m].
        normals: (N, 2) noise-free outward unit contact normals [-].
        features: exact curvature features of the profile for this tip radius
            (Definition 1; ``start/end/peak`` in profile arclength [m], ``position`` (2,)
            on the profile [m]).
        observable: the features as a fingertip can know them (module docstring).
        observable_index: (K,) int, the sample at which the contact point passes each
            observable feature.
        interference_points: (K, 2) interference points of the traced curve [m].
    """

    profile: Profile
    s: np.ndarray
    centers: np.ndarray
    contacts: np.ndarray
    normals: np.ndarray
    features: tuple[CurvatureFeature, ...]
    observable: tuple[CurvatureFeature, ...]
    observable_index: np.ndarray
    interference_points: np.ndarray


@dataclass(frozen=True, eq=False)
class FingertipTrace:
    """A fingertip trace in SI units (N samples, D = 2 or 3 dimensions).

    Attributes:
        t: (N,) time stamps, strictly increasing [s].
        centers: (N, D) measured fingertip-centre positions [m].
        tip_radius: fingertip radius r_f [m], or ``None`` when a data file does not say.
        contacts: (N, D) measured tactile contact points [m], or ``None``.
        normals: (N, D) measured outward unit contact normals [-], or ``None``.
        truth: the ground truth of a simulated trace, ``None`` for measured data.
        source: where the trace comes from (a file name, ``"simulation"``).
    """

    t: np.ndarray
    centers: np.ndarray
    tip_radius: float | None
    contacts: np.ndarray | None = None
    normals: np.ndarray | None = None
    truth: TraceTruth | None = None
    source: str = ""

    @property
    def true_centers(self) -> np.ndarray:
        """(N, 2) noise-free centres [m] of a simulated trace (``truth.centers``)."""
        if self.truth is None:
            raise InvalidParameter("true_centers: this trace has no ground truth (measured data)")
        return self.truth.centers


def _merged(prev: CurvatureFeature, f: CurvatureFeature) -> CurvatureFeature:
    """One feature standing for ``prev`` and ``f`` (same sign), at their mean position."""
    return CurvatureFeature(
        sign=f.sign,
        start=prev.start,
        end=f.end,
        peak=0.5 * (prev.peak + f.peak),
        position=0.5 * (np.asarray(prev.position) + np.asarray(f.position)),
    )


def _merge_in_gaps(
    truth: Sequence[CurvatureFeature], contact_u: np.ndarray, gap: float
) -> tuple[list[CurvatureFeature], list[float]]:
    """Merge same-sign features (in path order, ``peak`` in profile arclength [m]) lying in
    the same gap (a jump larger than ``gap`` [m]) of the non-decreasing profile arclength
    ``contact_u`` (M,) [m] of the contact point along a dense noise-free trace.

    Returns:
        The merged features and their coordinates (the mean of the merged ones) [m].
    """
    jumps = np.flatnonzero(np.diff(contact_u) > gap)
    gaps = [(contact_u[j], contact_u[j + 1]) for j in jumps]

    def gap_of(u: float) -> int:
        for i, (a, b) in enumerate(gaps):
            if a < u < b:
                return i
        return -1

    out: list[CurvatureFeature] = []
    out_u: list[float] = []
    last_gap = -2
    for f in truth:
        u = f.peak
        g = gap_of(u)
        if out and g >= 0 and g == last_gap and out[-1].sign == f.sign:
            f = _merged(out.pop(), f)
            u = 0.5 * (out_u.pop() + u)
        out.append(f)
        out_u.append(float(u))
        last_gap = g
    return out, out_u


def _merge_passed_together(
    feats: Sequence[CurvatureFeature], idx: np.ndarray, s: np.ndarray, gap: float
) -> tuple[tuple[CurvatureFeature, ...], np.ndarray]:
    """Same-sign features the fingertip passes within ``gap`` of path length [m] count once
    (e.g. the two bottom corners of a groove it only just touches)."""
    out: list[CurvatureFeature] = []
    out_idx: list[int] = []
    for f, i in zip(feats, idx, strict=True):
        if out and out[-1].sign == f.sign and s[i] - s[out_idx[-1]] < gap:
            f = _merged(out.pop(), f)
            i = (i + out_idx.pop()) // 2
        out.append(f)
        out_idx.append(int(i))
    return tuple(out), np.array(out_idx, dtype=int)


def observable_truth(
    truth: Sequence[CurvatureFeature],
    contact_u: np.ndarray,
    sample_u: np.ndarray,
    s: np.ndarray,
    tip_radius: float,
    *,
    gap: float,
    tie: float = 0.0,
) -> tuple[tuple[CurvatureFeature, ...], np.ndarray]:
    """The observable ground truth of a simulated trace and where the fingertip passes it.

    Args:
        truth: exact curvature features in path order (``peak`` in profile arclength [m]).
        contact_u: (M,) profile arclength of the true contact point along a dense
            noise-free trace, non-decreasing [m]; jumps larger than ``gap`` are the
            unobservable regions.
        sample_u: (N,) the same for the contact point of each trace sample [m].
        s: (N,) arclength of the fingertip-centre path at each sample [m].
        tip_radius: fingertip radius r_f [m].
        gap: smallest jump of ``contact_u`` that counts as an unobservable region [m].
        tie: coordinates within ``tie`` of a feature count as on it [m].

    Returns:
        ``(observable, index)``: the observable features and (K,) the sample at which the
        contact point passes each (the middle of the samples on it; the first sample past
        it when it lies in an unobservable region).
    """
    feats, u = _merge_in_gaps(truth, contact_u, gap)
    u = np.asarray(u, dtype=float)
    i0 = np.searchsorted(sample_u, u - tie, side="left")
    i1 = np.searchsorted(sample_u, u + tie, side="right")
    idx = np.clip((i0 + np.maximum(i1 - 1, i0)) // 2, 0, len(sample_u) - 1)
    return _merge_passed_together(feats, idx, s, tip_radius / 4)


def _noisy(C, K, N, center_sigma, contact_sigma, normal_sigma, rng):
    """Measured centres, contacts and normals: the true ones plus Gaussian noise."""
    n = len(C)
    Cm = C + rng.normal(0.0, center_sigma, (n, 2)) if center_sigma > 0 else C.copy()
    Km = K + rng.normal(0.0, contact_sigma, (n, 2)) if contact_sigma > 0 else K.copy()
    if normal_sigma > 0:
        a = rng.normal(0.0, normal_sigma, n)
        c, sn = np.cos(a), np.sin(a)
        Nm = np.stack([c * N[:, 0] - sn * N[:, 1], sn * N[:, 0] + c * N[:, 1]], axis=-1)
    else:
        Nm = N.copy()
    return Cm, Km, Nm


def _truth(profile: Profile, tip_radius: float, traced, h: float, s_samples, s_path):
    """Exact and observable features of ``profile`` for a trace sampled at arclengths
    ``s_samples`` (N,) of the dense traced curve ``traced`` (resolution ``h`` [m])."""
    keep = np.ones(len(traced.points), dtype=bool)
    keep[traced.interference_index] = False  # their "contact" is not on the profile
    smp = profile.sample(h)
    _, j = cKDTree(smp.points).query(traced.contacts[keep], workers=-1)
    contact_u = np.maximum.accumulate(smp.s[j])  # the contact never goes back
    sample_u = np.interp(s_samples, traced.s[keep], contact_u)
    feats = tuple(profile.curvature_features(tip_radius))
    observable, idx = observable_truth(
        feats, contact_u, sample_u, s_path, tip_radius, gap=max(20 * h, tip_radius / 100), tie=h
    )
    return feats, observable, idx


def simulate_trace(
    profile: Profile,
    tip_radius: float,
    *,
    spacing: float,
    center_sigma: float = 0.0,
    contact_sigma: float = 0.0,
    normal_sigma: float = 0.0,
    speed: float | None = None,
    rng: np.random.Generator | None = None,
) -> FingertipTrace:
    """A fingertip sliding over ``profile`` from end to end, sampled at equal arclength.

    Args:
        profile: the object profile (open profiles run in +x with the material below).
        tip_radius: fingertip radius r_f [m].
        spacing: distance between samples along the fingertip-centre path [m]
            (= speed / sample rate).
        center_sigma: standard deviation of the centre noise, per coordinate [m].
        contact_sigma: standard deviation of the contact-point noise, per coordinate [m].
        normal_sigma: standard deviation of the normal direction noise [rad].
        speed: finger speed for the time stamps [m/s] (default 0.03, §3.4.2).
        rng: random generator (required when any sigma > 0).

    Returns:
        A :class:`FingertipTrace` with ``truth``; for an open profile ``truth.observable``
        and ``truth.observable_index`` are filled (empty for a closed one).

    Raises:
        InvalidParameter: a bad value, noise without ``rng``, too many samples.
    """
    if not isinstance(profile, Profile):
        raise InvalidParameter(f"profile: expected a Profile, got {type(profile).__name__}")
    r = checks.positive("tip_radius", tip_radius, "m")
    center_sigma = checks.nonnegative("center_sigma", center_sigma, "m")
    contact_sigma = checks.nonnegative("contact_sigma", contact_sigma, "m")
    normal_sigma = checks.nonnegative("normal_sigma", normal_sigma, "rad")
    spacing = checks.positive("spacing", spacing, "m")
    speed = checks.positive("speed", DEFAULT_SPEED if speed is None else speed, "m/s")
    noisy = center_sigma > 0 or contact_sigma > 0 or normal_sigma > 0
    if noisy and rng is None:
        raise InvalidParameter("rng: expected a numpy Generator when noise is requested, got None")
    h = min(spacing / 4, r / 50)
    traced = traced_curve(profile, r, spacing=h)
    s_all = traced.s
    if s_all[-1] / spacing > 2_000_000:
        raise InvalidParameter(
            f"spacing: expected at most 2e6 samples over the {s_all[-1]:.4g} m trace, "
            f"got {s_all[-1] / spacing:.3g} with spacing {spacing:g} [m]"
        )
    s = np.arange(0.0, s_all[-1] + 1e-12, spacing)
    C = np.stack([np.interp(s, s_all, traced.points[:, j]) for j in range(2)], axis=-1)
    Nn = np.stack([np.interp(s, s_all, traced.normals[:, j]) for j in range(2)], axis=-1)
    Nn /= np.linalg.norm(Nn, axis=1, keepdims=True)
    K = C - r * Nn
    Cm, Km, Nm = _noisy(C, K, Nn, center_sigma, contact_sigma, normal_sigma, rng)
    s_path = arclength(C) if len(s) > 1 else s
    if profile.closed:
        feats, observable, idx = tuple(profile.curvature_features(r)), (), np.zeros(0, int)
    else:
        feats, observable, idx = _truth(profile, r, traced, h, s, s_path)
    truth = TraceTruth(
        profile, s_path, C, K, Nn, feats, observable, idx, traced.interference_points
    )
    return FingertipTrace(s / speed, Cm, r, Km, Nm, truth, "simulation")


__all__ = [
    "DEFAULT_SPEED",
    "THESIS_CENTER_SIGMA",
    "THESIS_CONTACT_SIGMA",
    "THESIS_NORMAL_SIGMA",
    "FingertipTrace",
    "TraceTruth",
    "observable_truth",
    "simulate_trace",
]
