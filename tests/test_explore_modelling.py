"""Feature skeletons of traced outlines (planner.exploration.surface.modelling): closed forms.

A traced outline is the fingertip centre read through quantized joint encoders: runs of
samples drifting a little off the level line, then a jump back (a sawtooth across the
outline). The skeleton of a stadium is its centre segment, of a disc its centre.
"""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import example, given, settings
from hypothesis import strategies as st

from planner.exploration.surface.modelling import SIGNIFICANCE, THIN, feature_model

STEP = 1e-5  # [m] the trace's sample spacing (10 mm/s at 1 kHz)


def _stadium(half: float, rho: float) -> tuple[np.ndarray, np.ndarray]:
    """Outline samples (M, 2) [m] of the points within ``rho`` of the segment
    (-half, 0)-(half, 0), in trace order, and their outward unit normals (M, 2)."""
    x = np.arange(-half, half, STEP)
    t = np.arange(-np.pi / 2, np.pi / 2, STEP / rho)
    one = np.ones_like(x)
    cap = np.column_stack([np.cos(t), np.sin(t)])
    normals = np.vstack([np.column_stack([0 * x, -one]), cap, np.column_stack([0 * x, one]), -cap])
    centres = np.vstack([np.column_stack([x, 0 * x]), np.tile([half, 0.0], (len(t), 1))])
    centres = np.vstack([centres, -centres])
    return centres + rho * normals, normals


def _sawtooth(n: int, wavelength: float, amplitude: float, phase: float) -> np.ndarray:
    """(n,) offsets [m] across the outline of samples every ``STEP``: drift, then jump."""
    return amplitude * (np.mod(np.arange(n) * STEP / wavelength + phase, 1.0) - 0.5)


@settings(max_examples=12, deadline=None)
@given(
    half=st.floats(0.003, 0.008),
    rho=st.floats(0.0015, 0.0045),
    wavelength=st.floats(2e-4, 8e-4),
    amplitude=st.floats(5e-6, 4e-5),
    phase=st.floats(0.0, 1.0),
    angle=st.floats(0.0, np.pi),
)
@example(half=0.007, rho=0.0043, wavelength=6e-4, amplitude=3e-5, phase=0.0, angle=0.0)
def test_traced_stadium_skeleton_is_its_whole_centre_segment(
    half, rho, wavelength, amplitude, phase, angle
):
    """The pruning shortens each end by at most the significance tolerance (plus the
    sawtooth and the thinning); the axis does not break (a traced ridge's skeleton was 5 mm
    of its 14.6 mm: the noise estimate missed the encoders' sawtooth)."""
    pts, normals = _stadium(half, rho)
    pts = pts + _sawtooth(len(pts), wavelength, amplitude, phase)[:, None] * normals
    c, s = np.cos(angle), np.sin(angle)
    rot = np.array([[c, -s], [s, c]])
    sk = feature_model("ridge", [pts @ rot.T], True)
    local = sk.points @ rot  # back in the stadium's frame
    tol = SIGNIFICANCE + amplitude + THIN
    segment = shapely.LineString([(-half, 0.0), (half, 0.0)])
    assert shapely.hausdorff_distance(shapely.MultiPoint(local), segment) <= tol
    assert local[:, 0].min() <= -half + tol and local[:, 0].max() >= half - tol
    assert sk.n_components == 1 and not sk.has_loop


@settings(max_examples=12, deadline=None)
@given(
    rho=st.floats(0.0015, 0.0045),
    wavelength=st.floats(2e-4, 6e-4),
    amplitude=st.floats(5e-6, 4e-5),
    phase=st.floats(0.0, 1.0),
)
def test_traced_disc_skeleton_is_its_centre(rho, wavelength, amplitude, phase):
    t = np.arange(0.0, 2 * np.pi, STEP / rho)
    normals = np.column_stack([np.cos(t), np.sin(t)])
    r = rho + _sawtooth(len(t), wavelength, amplitude, phase)
    sk = feature_model("bump", [r[:, None] * normals], True)
    assert np.hypot(*sk.points.T).max() <= SIGNIFICANCE + amplitude
