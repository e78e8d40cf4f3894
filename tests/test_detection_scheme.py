"""App. B.2 scheme, scoring, multiscale re-detection and the filter study library."""

import numpy as np
import pytest
from feature_traces import feature_trace

from planner.detection import b2_scheme, detect_multiscale, score_features
from planner.detection.filter_study import StudyTrace, grid, rate_filters
from planner.errors import InvalidParameter
from planner.geometry.features import CurvatureFeature

R = 0.01


def test_modified_curvature_is_curvature_times_speed_cubed():
    # a clockwise circle of radius rho traversed at constant speed: k = +1/rho (convex)
    rho, n = 0.02, 400
    th = np.linspace(np.pi, 0, n)
    res = b2_scheme(rho * np.cos(th), rho * np.sin(th), R, sigma=0)
    inner = res.curvature[5:-5]
    assert np.allclose(inner, 1 / rho, rtol=1e-3)
    speed = 2 * rho * np.sin(np.pi / (n - 1))  # |x(i+1) - x(i-1)|
    assert np.allclose(res.modified[5:-5], speed**3 / rho, rtol=1e-3)
    # the sign printed in App. B.2 step 4 (x'y'' + y'x'') is not rotation invariant;
    # the implemented numerator of eq. (B.5) is:
    rot = b2_scheme(rho * np.cos(th + 1.0), rho * np.sin(th + 1.0), R, sigma=0)
    assert np.allclose(rot.modified[5:-5], res.modified[5:-5], rtol=1e-9)


def test_b2_on_a_filtered_wire_finds_three_features():
    tr = feature_trace(
        "wire",
        0.65e-3,
        angle=np.pi / 4,
        length=0.02,
        spacing=2e-4,
        center_sigma=1e-4,
        contact_sigma=0.0,
        normal_sigma=0.0,
    )
    obs = tr.truth.observable
    study = StudyTrace(
        tr.t, tr.centers, tuple(f.sign for f in obs), tuple(tr.t[tr.truth.observable_index])
    )
    (good,) = rate_filters([study], grid(["gaussian"], [25], [8]), R, (R / 2) / 0.03)
    (raw,) = rate_filters([study], grid(["none"], [1], [1]), R, (R / 2) / 0.03)
    assert good.errors <= 1
    assert raw.errors > good.errors + 5  # unfiltered data: many false positives


def test_b2_bad_arguments():
    x = np.linspace(0, 1, 50)
    with pytest.raises(InvalidParameter, match="decimate"):
        b2_scheme(x, x, R, decimate=0)
    with pytest.raises(InvalidParameter, match="only"):
        b2_scheme(x, x, R, decimate=20)
    with pytest.raises(InvalidParameter, match="samples"):
        b2_scheme(x, x[:40], R)


def _f(sign, x):
    return CurvatureFeature(sign=sign, start=x, end=x, peak=x, position=np.array([x, 0.0]))


def test_scoring_counts():
    truth = [_f(-1, 0.0), _f(1, 0.01), _f(-1, 0.02)]
    det = [_f(-1, 0.001), _f(1, 0.013), _f(1, 0.05), _f(1, 0.021)]
    sc = score_features(det, truth, 0.005)
    assert (sc.tp, sc.fp, sc.fn) == (2, 2, 1)
    assert sc.precision == pytest.approx(0.5) and sc.recall == pytest.approx(2 / 3)
    assert sc.f1 == pytest.approx(2 * 0.5 * (2 / 3) / (0.5 + 2 / 3))
    assert sc.localization == pytest.approx(0.002)
    empty = score_features([], [], 0.005)
    assert empty.f1 == 1.0 and np.isnan(empty.localization)
    assert score_features([], truth, 0.005).f1 == 0.0
    with pytest.raises(InvalidParameter, match="tolerance"):
        score_features(det, truth, 0.0)


def test_multiscale_step():
    tr = feature_trace("step", 2e-3, center_sigma=1e-4, contact_sigma=0.0, normal_sigma=0.0)
    ms = detect_multiscale(tr.centers, R, [0.015, 0.025])
    for ri, fs in ms.items():
        assert "".join("+" if f.sign > 0 else "-" for f in fs) == "-+", ri
    with pytest.raises(InvalidParameter, match="smaller than tip_radius"):
        detect_multiscale(tr.centers, R, [0.005])
