"""Tests of robots.sensors: OWTS eqs. C.1-C.3, sampling/calibration, tactile array, gauges."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from robots.sensors import (
    OWTS,
    Encoder,
    ForceSensor,
    OWTSSampler,
    Potentiometer,
    RadialNonlinearity,
    TactileArray,
    fit_nonlinearity,
)


def _normal(theta, phi):
    return np.array([np.cos(phi) * np.sin(theta), np.sin(phi) * np.sin(theta), np.cos(theta)])


def _random_normals(rng, n, max_theta):
    th = np.arccos(rng.uniform(np.cos(max_theta), 1.0, n))
    ph = rng.uniform(-np.pi, np.pi, n)
    return np.column_stack([np.cos(ph) * np.sin(th), np.sin(ph) * np.sin(th), np.cos(th)])


@settings(max_examples=60, deadline=None)
@given(
    st.floats(0.0, np.deg2rad(75.0)),
    st.floats(-np.pi, np.pi),
    st.floats(0.004, 0.02),
    st.floats(-0.1, 0.1),
    st.floats(-0.1, 0.1),
    st.floats(0.05, 1.0),
)
@example(1e-7, 0.3, 0.008, 0.1, -0.1, 0.5)  # arccos(n_z) lost ~eps/theta = 4e-11 here
@example(1e-9, -2.0, 0.004, -0.1, 0.1, 0.05)
def test_owts_round_trip(theta, phi, radius, xo, yo, intensity):
    s = OWTS(radius=radius, offsets=(xo, yo))
    n = _normal(theta, phi)
    v = s.voltages_from_contact(n, intensity)
    assert v.shape == (4,) and np.all(v >= 0)
    assert np.isclose(v.sum(), 5.0 * intensity)
    p, m = s.contact_from_voltages(v)
    np.testing.assert_allclose(m, n, atol=1e-12)
    np.testing.assert_allclose(p, radius * n, atol=1e-12 * radius)


@pytest.mark.parametrize("theta", [1e-12, 1e-9, 1e-7, 1e-5])
def test_owts_inverse_keeps_precision_near_the_pole(theta):
    """Near the pole the polar angle must come from atan2(sin, cos), not arccos(n_z).

    ``n_z = cos(theta)`` rounds to a multiple of eps, so ``arccos(n_z)`` carries an absolute
    error of ~eps/theta; the recovered tangential components then have a *relative* error
    of ~eps/theta^2. With atan2 the round trip is exact to a few ulps at every angle.
    """
    s = OWTS(offsets=(0.05, -0.03))
    n = _normal(theta, 0.7)
    _, m = s.contact_from_voltages(s.voltages_from_contact(n, 0.5))
    np.testing.assert_allclose(m[:2], n[:2], rtol=1e-6, atol=1e-15)


def test_owts_equations_c1_c3_by_hand():
    s = OWTS(radius=0.008, psd_side=0.01, scale=300.0, offsets=(0.05, -0.02))
    v = np.array([1.0, 0.6, 1.2, 0.7])
    S = v.sum()
    xd = ((v[0] - v[1] + v[2] - v[3]) / S - 0.05) * 0.005
    yd = ((-v[0] + v[1] + v[2] - v[3]) / S + 0.02) * 0.005
    phi, theta = np.arctan2(yd, xd), 300.0 * np.hypot(xd, yd)
    p, n = s.contact_from_voltages(v)
    np.testing.assert_allclose(n, _normal(theta, phi), atol=1e-15)
    np.testing.assert_allclose(p, 0.008 * _normal(theta, phi), atol=1e-15)
    det = s.detection(v)
    assert np.isclose(det.x[0], xd) and np.isclose(det.theta[0], theta)


def test_owts_no_contact_and_field_of_detection():
    s = OWTS()
    p, n = s.contact_from_voltages(np.zeros(4))
    np.testing.assert_array_equal(n, 0.0)
    np.testing.assert_array_equal(p, 0.0)
    np.testing.assert_array_equal(s.voltages_from_contact(np.zeros(3)), 0.0)
    np.testing.assert_array_equal(s.voltages_from_contact(_normal(np.deg2rad(80), 0.3)), 0.0)
    pole = s.contact_from_voltages(s.voltages_from_contact([0, 0, 1.0]))[1]
    np.testing.assert_allclose(pole, [0, 0, 1.0], atol=1e-15)
    batch = s.contact_from_voltages(np.zeros((5, 4)))[1]
    assert batch.shape == (5, 3) and not batch.any()


def test_owts_bad_input():
    s = OWTS()
    with pytest.raises(InvalidParameter, match=r"shape \(4,\)"):
        s.contact_from_voltages([1.0, 2.0])
    with pytest.raises(InvalidParameter, match="intensity"):
        s.voltages_from_contact([0, 0, 1.0], intensity=2.0)
    with pytest.raises(InvalidParameter, match="radius"):
        OWTS(radius=0.0)
    with pytest.raises(InvalidParameter, match="does not fit on the PSD"):
        OWTS(scale=100.0)


def test_sampler_noise_quantization_and_seed():
    s = OWTS()
    n = _random_normals(np.random.default_rng(0), 3000, np.deg2rad(60))
    a = OWTSSampler(s, np.random.default_rng(7)).sample(n)
    b = OWTSSampler(s, np.random.default_rng(7)).sample(n)
    np.testing.assert_array_equal(a, b)
    lsb = OWTSSampler(s, np.random.default_rng(0)).lsb
    np.testing.assert_allclose(a / lsb, np.round(a / lsb), atol=1e-9)
    _, m = s.contact_from_voltages(a)
    err = np.rad2deg(np.arccos(np.clip(np.sum(m * n, axis=1), -1, 1)))
    # 0.5 deg per axis: the angular error is Rayleigh-like, median ~0.59 deg, ~all within 2 deg
    assert 0.4 < np.median(err) < 0.8
    assert np.quantile(err, 0.99) < 2.0


def test_calibration_recovers_nonlinearity_and_offsets():
    true = OWTS(offsets=(0.04, -0.03))
    nl = RadialNonlinearity(0.15, -0.06, true.field_of_detection / true.scale)
    rng = np.random.default_rng(1)
    n = _random_normals(rng, 2000, np.deg2rad(72))
    raw = OWTSSampler(true, rng, nonlinearity=nl, noise_angle=np.deg2rad(0.2)).sample(n)
    cal = fit_nonlinearity(OWTS(), n, raw)
    assert cal.nonlinearity.k1 == pytest.approx(0.15, abs=0.01)
    assert cal.nonlinearity.k2 == pytest.approx(-0.06, abs=0.01)
    np.testing.assert_allclose(cal.offsets, (0.04, -0.03), atol=2e-3)
    fitted = OWTS(offsets=cal.offsets)
    _, m = fitted.contact_from_voltages(cal.nonlinearity.correct(fitted, raw))
    _, m0 = OWTS().contact_from_voltages(raw)
    err = lambda mm: np.rad2deg(np.arccos(np.clip(np.sum(mm * n, 1), -1, 1))).mean()  # noqa: E731
    assert err(m) < 0.5 < 2.0 < err(m0)


def test_sheath_bias_grows_with_tangential_force():
    s = OWTS()
    n = np.tile([0.0, 0.0, 1.0], (3, 1))
    ft = np.array([[0.0, 0, 0], [0.5, 0, 0], [1.0, 0, 0]])
    v = OWTSSampler(s, np.random.default_rng(0), noise_angle=0.0, bits=24, sheath_gain=0.1).sample(
        n, tangential_force=ft
    )
    _, m = s.contact_from_voltages(v)
    bias = np.arctan2(m[:, 0], m[:, 2])
    np.testing.assert_allclose(bias, [0.0, 0.05, 0.1], atol=1e-4)


def test_tactile_sphere_localization_and_force():
    arr = TactileArray()
    rng = np.random.default_rng(2)
    centers = rng.uniform(-0.006, 0.006, size=(50, 2))
    imgs = arr.sphere_images(centers, 0.05, 0.3)
    assert imgs.shape == (50, 8, 8)
    for c, img in zip(centers, imgs, strict=True):
        r = arr.read(img)
        assert r.in_contact
        assert np.linalg.norm(r.centroid - c) < 1e-3  # ~1 mm localization (§2.3.2)
        assert r.force == pytest.approx(0.3, rel=0.1)
    single = arr.sphere_images(centers[0], 0.05, 0.3)
    np.testing.assert_allclose(single, imgs[0])


def test_tactile_ridge_is_sharper_than_sphere():
    """Fig. 2.14: the ball's round blob turns into a line when the ridge is under the pad."""
    arr = TactileArray()
    ball = arr.sphere_images([0.0, 0.0], 0.05, 0.3)
    ridge = arr.ridge_image([0.0, 0.0], 0.0, 0.002, 0.3)

    def spreads(img):
        w = img / img.sum()
        su = np.sqrt(w.sum(0) @ arr.u**2 - (w.sum(0) @ arr.u) ** 2)
        sv = np.sqrt(w.sum(1) @ arr.v**2 - (w.sum(1) @ arr.v) ** 2)
        return su, sv

    bu, bv = spreads(ball)
    ru, rv = spreads(ridge)
    assert np.isclose(bu, bv, rtol=0.05)  # round
    assert ru > 3 * rv  # a line along u, narrow across
    assert ridge.max() > 0 and arr.read(ridge).force == pytest.approx(0.3, rel=0.15)
    assert not arr.read(np.zeros((8, 8))).in_contact
    with pytest.raises(InvalidParameter, match="shape"):
        arr.read(np.zeros((4, 4)))
    with pytest.raises(InvalidParameter, match="forces"):
        arr.sphere_images([0, 0], 0.05, -1.0)


def test_gauges():
    rng = np.random.default_rng(3)
    fs = ForceSensor()
    f = fs.measure(np.full(5000, 0.3), rng)
    np.testing.assert_allclose(f / 0.02, np.round(f / 0.02), atol=1e-9)
    assert abs(f.mean() - 0.3) < 0.002
    enc = Encoder(resolution=0.001)
    assert enc.measure(0.0105) == pytest.approx(0.010)
    pot = Potentiometer(noise_std=0.0)
    assert abs(pot.measure(0.5, rng) - 0.5) <= pot.resolution / 2
    with pytest.raises(InvalidParameter, match="resolution"):
        ForceSensor(resolution=0.0)


def test_ridge_crossing_changes_sphere_pattern_to_ridge():
    from robots.sensors import ridge_crossing_images

    arr = TactileArray()
    offsets = np.linspace(-0.015, 0.015, 7)
    rc = ridge_crossing_images(arr, offsets, force=0.3)
    assert rc.images.shape == (7, 8, 8)
    np.testing.assert_array_equal(rc.on_ridge, np.abs(offsets) <= 0.01)
    for k in range(7):
        r = arr.read(rc.images[k])
        assert r.in_contact
        if abs(offsets[k]) < 0.0075:  # a line at the pad edge is partly off the taxels
            assert r.force == pytest.approx(0.3, rel=0.15)
        if rc.on_ridge[k]:  # a line along v at the ridge position
            assert abs(r.centroid[0] - offsets[k]) < 1.5e-3
            assert (rc.images[k] > 0).any(axis=1).all()
        else:  # the ball's blob at the pad centre
            assert np.linalg.norm(r.centroid) < 1e-3


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: OWTS(radius=-0.008), r"radius: expected a finite number > 0 \[m\], got -0.008"),
        (lambda: OWTS(field_of_detection=2.0), r"field_of_detection: expected .*\[rad\], got 2.0"),
        (lambda: OWTS(offsets=(0.0, np.nan)), "offsets: expected finite values"),
        (lambda: TactileArray(rows=0), "rows: expected an integer >= 1, got 0"),
        (lambda: TactileArray(spread=-1e-3), r"spread: expected .* >= 0 \[m\], got -0.001"),
        (lambda: ForceSensor(noise_std=-1.0), r"noise_std: expected .* >= 0 \[N\], got -1.0"),
        (lambda: Potentiometer(bits=30), r"bits: expected a number in \[1, 24\], got 30"),
    ],
)
def test_sensor_settings_name_value_unit_and_expectation(make, match):
    with pytest.raises(InvalidParameter, match=match):
        make()
