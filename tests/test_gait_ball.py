"""ball_with_ridge fidelity (issue 11): the statics of the phase-2 hold that set the sign of
Fig. 2.14's tangential force, the rotation estimate of phase 2 (rolling on the holding pad),
the ridge's image located at the pad's end and weighted by when it was seen, and the
shadows of the fingertips beside the ridge (closed forms)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.errors import InvalidParameter
from planner.exploration.planar.angles import circular_median
from planner.exploration.planar.metrics import (
    PAD_CENTROID_EDGE,
    held_pad_rolling,
    held_tip_centre_x,
    line_like_rows,
    object_rotation,
    pad_rolling,
    pad_shadow,
    round_tip_shadow,
    tip_rolling,
)
from planner.exploration.planar.plots import fig214_measures
from planner.exploration.planar.segments import hold_tangential_force, palm_moment
from planner.exploration.planar.sensed_features import pad_end_contact, sighting_weight

R = 0.05


def _polar(beta: float, radius: float = R, centre=(0.0, R)) -> np.ndarray:
    return np.array([centre[0] + radius * math.cos(beta), centre[1] + radius * math.sin(beta)])


# --------------------------------------------------------------------- hold statics
def test_the_moment_free_hold_presses_along_the_chord_to_the_palm():
    """With nothing else on the ball, the holder's force lies along the chord to the palm
    contact: T / N = tan((beta - pi/2) / 2) (inscribed angle), 2 N -> 0.73 N at 130 deg."""
    for beta in np.radians([100.0, 130.0, 160.0, 200.0, 250.0]):
        T = hold_tangential_force(beta, 1.0, 0.0, R)
        assert T == pytest.approx(math.tan((beta - math.pi / 2) / 2))
        # the same from the chord's direction in the contact frame
        L, P = _polar(beta), np.array([0.0, 0.0])
        chord = (P - L) / np.linalg.norm(P - L)
        n = -np.array([math.cos(beta), math.sin(beta)])
        t = np.array([-math.sin(beta), math.cos(beta)])
        assert T == pytest.approx((chord @ t) / (chord @ n))
    assert 2.0 * math.cos(math.radians(20)) * hold_tangential_force(
        math.radians(130), 1.0, 0.0, R
    ) == pytest.approx(2.0 * math.sin(math.radians(20)))


@settings(max_examples=60, deadline=None, derandomize=True)
@given(
    beta=st.floats(math.radians(95), math.radians(240)),
    beta_e=st.floats(math.radians(-60), math.radians(70)),
    n_hold=st.floats(0.1, 3.0),
    f_n=st.floats(0.0, 1.0),
    f_t=st.floats(-1.0, 1.0),
    mass=st.floats(0.0, 0.2),
)
def test_the_hold_balances_the_ball_on_the_palm(beta, beta_e, n_hold, f_n, f_t, mass):
    """With T from :func:`hold_tangential_force`, the palm's force found from the force
    balance leaves no moment about the centre: the ball is in equilibrium."""
    c = np.array([0.0, R])
    E = _polar(beta_e)
    ne, te = (
        -np.array([math.cos(beta_e), math.sin(beta_e)]),
        np.array([-math.sin(beta_e), math.cos(beta_e)]),
    )
    Fe = f_n * ne + f_t * te
    M = palm_moment(E, Fe, c, R)
    T = hold_tangential_force(beta, n_hold, M, R)
    L = _polar(beta)
    Fl = n_hold * -np.array([math.cos(beta), math.sin(beta)]) + T * np.array(
        [-math.sin(beta), math.cos(beta)]
    )
    gravity = np.array([0.0, -9.81 * mass])
    Fp = -(Fe + Fl + gravity)  # the palm's force at (0, 0)

    def moment(p, f):
        return (p[0] - c[0]) * f[1] - (p[1] - c[1]) * f[0]

    total = moment(E, Fe) + moment(L, Fl) + moment(np.zeros(2), Fp) + moment(c, gravity)
    assert total == pytest.approx(0.0, abs=1e-12)


def test_the_hold_force_sets_the_sign_of_the_tangential_force():
    """T changes sign where N |cos beta| = M / R: below it the explorer's drag sets it.
    Measured on ball_with_ridge (last 0.2 s of phase 2): beta 140 deg, M / R 0.7 N, so
    the threshold is 0.9 N; 2 N gave T = +0.5 N, 0.7 N gave -0.1 N (the trace: -0.100)."""
    beta, m = math.radians(140.0), 0.7
    threshold = m / abs(math.cos(beta))
    assert threshold == pytest.approx(0.914, abs=1e-3)
    assert hold_tangential_force(beta, threshold, m * R, R) == pytest.approx(0.0, abs=1e-12)
    assert hold_tangential_force(beta, 2.0, m * R, R) > 0.4
    assert -0.11 < hold_tangential_force(beta, 0.7, m * R, R) < -0.09
    with pytest.raises(InvalidParameter, match="beta_hold"):
        hold_tangential_force(-math.pi / 2, 1.0, 0.0, R)


def test_palm_moment_closed_form():
    c = np.array([0.3, R])
    # a horizontal force at the top of the ball: lever 2R about the palm contact
    assert palm_moment(c + [0.0, R], [1.0, 0.0], c, R) == pytest.approx(-2 * R)
    assert palm_moment(c + [R, 0.0], [0.0, 2.0], c, R) == pytest.approx(2 * R)
    assert palm_moment(c - [0.0, R], [5.0, 7.0], c, R) == pytest.approx(0.0)


# --------------------------------------------------------------------- rotation estimate
R_TIP = 0.025


def _rolling_on_the_pad(turn: np.ndarray) -> dict:
    """A ball turning by ``turn`` (N,) [rad] while rolling up a fixed vertical pad at its
    left (its centre rises by R turn, as on a ball lifted off the palm)."""
    n = turn.size
    cy = R + R * turn
    nL = np.tile([-1.0, 0.0], (n, 1))  # outward object normal at the pad
    pL = np.column_stack([np.full(n, -R), cy])
    axis = np.column_stack([-nL[:, 1], nL[:, 0]])  # the pad's u axis (-n_y, n_x)
    u = (pL - pL[0]) @ axis[0]  # the contact's place on the pad: -R turn
    return {"t": np.linspace(0, 1, n), "kind": np.full(n, 2), "cx": np.zeros(n), "cy": cy,
            "pLx": pL[:, 0], "pLy": pL[:, 1], "nLx": nL[:, 0], "nLy": nL[:, 1], "u": u,
            "pad_touch": np.ones(n), "theta": np.zeros(n)}  # fmt: skip


def _dragged_on_the_palm(turn: np.ndarray, tilt: float, edge: float = 0.00875) -> dict:
    """A ball on the palm (centre ``(0, R)``, sliding on it) turned by ``turn`` (N,) [rad]
    by a pad at polar angle ``pi + tilt`` that rolls with it (no slip at the pad: the pad
    moves along its axis, the contact's place on it is ``-R turn``); the tactile centroid
    sticks at +-``edge`` [m], and the sensed contact and pad-based centre are built on it
    as the sensing does (``p_L = pad origin + u axis``, ``c = p_L - R n_L``)."""
    n = turn.size
    nL = np.tile([-math.cos(tilt), -math.sin(tilt)], (n, 1))
    axis = np.column_stack([-nL[:, 1], nL[:, 0]])
    contact = np.array([0.0, R]) + R * nL  # fixed in the world
    u_true = -R * turn
    origin = contact - u_true[:, None] * axis
    u = np.clip(u_true, -edge, edge)
    pL = origin + u[:, None] * axis
    c = pL - R * nL
    return {"t": np.linspace(0, 1, n), "kind": np.full(n, 2), "cx": c[:, 0], "cy": c[:, 1],
            "pLx": pL[:, 0], "pLy": pL[:, 1], "nLx": nL[:, 0], "nLy": nL[:, 1], "u": u,
            "pad_touch": np.ones(n), "theta": np.zeros(n)}  # fmt: skip


def _rolling_between_the_fingers(turn: np.ndarray, beta_r: float = 0.3) -> dict:
    """Phase 1: a ball (centre ``(0, R)``) turned by ``turn`` [rad] between the pad of
    :func:`_rolling_on_the_pad`'s kind (here it moves along its axis, the centre stays) and
    the round right tip at polar angle ``beta_r``, both rolling without slip: two circles in
    external contact turn oppositely, ``d(phi_R) = -(R / r) d(turn)``, and the tip-frame
    arclength comes from the sensing's ``round_contact_arclength``."""
    from planner.exploration.planar.sensing import round_contact_arclength

    tr = _dragged_on_the_palm(turn, 0.0, edge=1.0)
    phi = 0.4 - (R / R_TIP) * turn
    pR = _polar(beta_r)
    tr.update(kind=np.full(turn.size, 1), pRx=np.full(turn.size, pR[0]),
              pRy=np.full(turn.size, pR[1]),
              sR=np.array([round_contact_arclength(beta_r, p, R_TIP) for p in phi]))  # fmt: skip
    return tr


def test_phase2_rotation_rolls_on_the_holding_pad():
    """A ball rolling on the holding pad with the contact inside the tactile array: the
    rolling on the pad says the turn (the palm's -dx / R would say 0)."""
    turn = np.linspace(0.0, 0.1, 21)  # the contact moves 5 mm: inside the array
    tr = _rolling_on_the_pad(turn)
    np.testing.assert_allclose(pad_rolling(tr, R) - pad_rolling(tr, R)[0], turn, atol=1e-12)
    np.testing.assert_allclose(object_rotation(tr, R), turn, atol=1e-12)


@settings(max_examples=30, deadline=None)
@given(st.floats(0.1, 0.6), st.floats(-0.5, 0.5), st.sampled_from([1.0, -1.0]))
def test_a_dragged_ball_is_read_past_the_arrays_edge(total, tilt, sign):
    """A held ball dragged round on the palm until the contact runs off the tactile array:
    the centroid sticks at the outermost taxel and the pad's rolling reads too little
    (``PAD_CENTROID_EDGE``); from the palm and the pad's line the turn is exact."""
    turn = sign * np.linspace(0.0, total, 41)
    tr = _dragged_on_the_palm(turn, tilt)
    held = held_pad_rolling(tr, R)
    np.testing.assert_allclose(held - held[0], turn, atol=1e-9)
    pad = pad_rolling(tr, R)  # stops where the centroid sticks: 8.75 mm, 0.175 rad
    np.testing.assert_allclose(pad - pad[0], np.clip(turn, -0.175, 0.175), atol=1e-9)


def test_a_held_ball_is_read_from_the_centroid_inside_the_array():
    """Inside the array the tactile centroid is the contact, even with the ball off the
    palm (lifted: the palm's contact would be wrong)."""
    turn = np.linspace(0.0, 0.12, 13)  # 6 mm < PAD_CENTROID_EDGE
    tr = _rolling_on_the_pad(turn)
    assert np.abs(tr["u"]).max() < PAD_CENTROID_EDGE
    held = held_pad_rolling(tr, R)
    np.testing.assert_allclose(held - held[0], turn, atol=1e-12)


def test_phase1_rotation_averages_the_two_rolling_fingertips():
    """Both fingertips roll without slip (eq. 2.4): the pad's ``beta_L - u / R`` and the
    tip's ``beta_R + s_R / R`` each say the turn (from the phase's second row,
    ``PHASE1_SKIP``); a tactile centroid jump (the ridge under the pad) counts half."""
    turn = np.linspace(0.0, -0.3, 31)
    tr = _rolling_between_the_fingers(turn)
    tip = tip_rolling(tr, R)
    np.testing.assert_allclose(tip - tip[0], turn, atol=1e-12)
    from_second = np.r_[0.0, turn[1:] - turn[1]]
    np.testing.assert_allclose(object_rotation(tr, R), from_second, atol=1e-12)
    jumped = {**tr, "u": tr["u"] + np.where(np.arange(31) >= 15, 0.003, 0.0)}
    th = object_rotation(jumped, R)
    np.testing.assert_allclose(th[-1] - from_second[-1], -0.5 * 0.003 / R, atol=1e-12)


def test_rotation_is_chained_over_phases():
    """Phase 1 adds both fingertips' rolling, phase 2 the pad's, phase 3 the palm's
    (-dx / R), each from its own first row (phase 1 from its second, ``PHASE1_SKIP``; not
    from the last phase's readings); rows without the pad hold its value."""
    tr1 = _rolling_between_the_fingers(np.linspace(0.0, -0.3, 5))
    tr1["u"] = tr1["u"] + 0.004  # the centroid of phase 1 differs from phase 2's last one
    tr2 = _rolling_on_the_pad(np.linspace(0.0, 0.05, 5))
    tr2["pad_touch"][2] = 0.0
    tr2["u"][2] = 99.0  # a non-touching row's u is stale
    cx3 = np.linspace(0.0, -R * 0.02, 4)  # phase 3: rolls left on the palm by 0.02 rad
    n3 = 4
    tr = {
        "t": np.linspace(0, 1, 14),
        "kind": np.r_[np.full(5, 1), np.full(5, 2), np.full(n3, 3)],
        "theta": np.r_[np.full(5, -0.1), np.full(5, 7.0), np.full(n3, 7.0)],
        "cx": np.r_[tr1["cx"], tr2["cx"], cx3],
        "cy": np.r_[tr1["cy"], tr2["cy"], np.full(n3, R)],
    }
    for k in ("pLx", "pLy", "nLx", "nLy", "u", "pad_touch"):
        other = {"nLx": -1.0, "pLx": -R, "pLy": R, "pad_touch": 1.0}.get(k, 0.0)
        tr[k] = np.r_[tr1[k], tr2[k], np.full(n3, other)]
    for k in ("pRx", "pRy", "sR"):
        tr[k] = np.r_[tr1[k], np.full(5 + n3, np.nan)]
    th = object_rotation(tr, R)
    turn1 = np.linspace(0.0, -0.3, 5)
    np.testing.assert_allclose(th[:5], -0.1 + np.r_[0.0, turn1[1:] - turn1[1]], atol=1e-12)
    expect2 = -0.325 + np.linspace(0.0, 0.05, 5)
    expect2[2] = expect2[1]  # held while the pad does not touch
    np.testing.assert_allclose(th[5:10], expect2, atol=1e-12)
    np.testing.assert_allclose(th[-n3:], -0.275 + np.linspace(0.0, 0.02, n3), atol=1e-12)


def _rolling_on_the_palm(turn: np.ndarray, lift: np.ndarray, pad_at: float = 2.6) -> dict:
    """Phase 3: a ball on the palm rolling by ``turn`` (N,) [rad] (centre ``(-R turn, R)``),
    held by the round right tip whose centre estimate (``cx``) is ``lift`` (N,) [m] off (a
    ridge under the tip), explored by the pad touching it at polar angle ``pad_at`` [rad]
    with its contact at the pad's middle (``u = 0``), clean round images."""
    n = turn.size
    x = -R * turn
    nL = np.tile([math.cos(pad_at), math.sin(pad_at)], (n, 1))
    pL = np.column_stack([x, np.full(n, R)]) + R * nL
    return {"t": np.linspace(0, 1, n), "kind": np.full(n, 3), "cx": x + lift,
            "cy": np.full(n, R), "pLx": pL[:, 0], "pLy": pL[:, 1], "nLx": nL[:, 0],
            "nLy": nL[:, 1], "u": np.zeros(n), "pad_touch": np.ones(n),
            "theta": np.zeros(n)}  # fmt: skip


@settings(max_examples=40, deadline=None)
@given(
    h=st.floats(1e-3, 3.5e-3),
    sign=st.sampled_from([1.0, -1.0]),
    start=st.integers(0, 30),
    width=st.integers(1, 25),
    total=st.floats(-0.2, 0.2),
)
def test_a_bump_under_the_holding_tip_is_taken_out_of_phase_3(h, sign, start, width, total):
    """The holding tip's centre lifted by ``h`` (1-3.5 mm, a ridge under the tip) over any
    window shorter than half the phase, at its start, middle or end: corrected by the
    pad's centre, phase 3's rotation is the palm's roll exactly (uncorrected it is off by
    h / R, 1.1-4 deg)."""
    n = 61
    turn = np.linspace(0.0, total, n)
    lift = np.zeros(n)
    lift[start : start + width] = sign * h
    tr = _rolling_on_the_palm(turn, lift)
    no_line = np.zeros(n, bool)
    cx = held_tip_centre_x(tr, R, no_line)
    np.testing.assert_allclose(cx, -R * turn, atol=1e-12)
    # without images (nothing tells a ridge under the pad) the tip's centre stands
    np.testing.assert_allclose(object_rotation(tr, R), turn - (lift - lift[0]) / R, atol=1e-12)
    tr_img = {**tr, "image_t": tr["t"][::5], "images": np.ones((len(tr["t"][::5]), 8, 8))}
    th = object_rotation(tr_img, R)  # round images: the correction applies
    np.testing.assert_allclose(th, turn, atol=1e-12)


def test_the_tip_centre_stays_where_the_pad_cannot_tell():
    """Rows where the pad's image is line-like (a ridge under the pad), its centroid lies
    past PAD_CENTROID_EDGE, or it does not touch keep the tip's centre; with fewer than 10
    clean rows nothing is corrected; a departure within TIP_LIFT is noise, kept."""
    from planner.exploration.planar.metrics import TIP_LIFT

    n = 40
    lift = np.r_[np.zeros(20), np.full(20, 2e-3)]
    tr = _rolling_on_the_palm(np.linspace(0.0, 0.1, n), lift)
    line = np.r_[np.zeros(30, bool), np.ones(10, bool)]
    cx = held_tip_centre_x(tr, R, line)
    np.testing.assert_allclose(cx[:30], -R * np.linspace(0.0, 0.1, n)[:30], atol=1e-12)
    np.testing.assert_allclose(cx[30:], tr["cx"][30:], atol=0)
    edge = {**tr, "u": np.where(np.arange(n) >= 30, PAD_CENTROID_EDGE + 1e-4, 0.0)}
    np.testing.assert_allclose(held_tip_centre_x(edge, R, np.zeros(n, bool))[30:],
                               tr["cx"][30:], atol=0)  # fmt: skip
    few = {**tr, "pad_touch": np.r_[np.ones(9), np.zeros(n - 9)]}
    np.testing.assert_array_equal(held_tip_centre_x(few, R, np.zeros(n, bool)), tr["cx"])
    small = _rolling_on_the_palm(np.zeros(n), np.r_[np.zeros(20), np.full(20, 0.9 * TIP_LIFT)])
    np.testing.assert_array_equal(held_tip_centre_x(small, R, np.zeros(n, bool)), small["cx"])


def test_line_like_rows_take_the_nearest_image():
    """Each trace row reads the image nearest in time: round (one taxel) or line-like
    (a row of 8 taxels: elongation 8); None without images."""
    line_img = np.zeros((8, 8))
    line_img[3, :] = 1.0
    dot = np.zeros((8, 8))
    dot[3, 3] = 1.0
    tr = {"t": np.array([0.0, 0.01, 0.024, 0.026, 0.05]), "image_t": np.array([0.0, 0.02, 0.03]),
          "images": np.stack([dot, line_img, dot])}  # fmt: skip
    np.testing.assert_array_equal(line_like_rows(tr), [False, True, True, False, False])
    assert line_like_rows({"t": tr["t"]}) is None


# --------------------------------------------------------------------- image ridges
def test_an_edge_in_the_outer_column_is_placed_at_the_pad_end():
    """u in the outer of 8 columns of the 20 mm pad (> 7.5 mm) moves to the pad's end
    along the pad's axis (-n_y, n_x); inner contacts stay."""
    n = np.array([[0.0, -1.0], [0.0, -1.0], [-1.0, 0.0]])
    tr = {"u": np.array([0.00875, 0.004, -0.00875]), "pLx": np.zeros(3), "pLy": np.zeros(3),
          "nLx": n[:, 0], "nLy": n[:, 1]}  # fmt: skip
    x, y = pad_end_contact(tr, 8, 0.01)
    axis = np.column_stack([-n[:, 1], n[:, 0]])
    np.testing.assert_allclose(np.c_[x, y][0], 0.00125 * axis[0], atol=1e-15)
    np.testing.assert_allclose(np.c_[x, y][1], [0.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(np.c_[x, y][2], -0.00125 * axis[2], atol=1e-15)


def test_early_sightings_outweigh_late_ones():
    """Weights 1 / (1 + (turned / 90 deg)^2): the first sighting (turned 0.5 rad) outweighs
    five after the full turn (6.4 rad); equal weights give the plain median."""
    assert sighting_weight(0.0) == 1.0
    assert sighting_weight(math.pi / 2) == pytest.approx(0.5)
    a = np.radians([167.9, 165.0, 165.2, 165.1, 164.9, 165.3])
    w = np.array([sighting_weight(0.5)] + [sighting_weight(6.4)] * 5)
    assert math.degrees(circular_median(a, w)) == pytest.approx(167.9)
    b = np.radians([10.0, 12.0, 20.0])
    assert math.degrees(circular_median(b, np.ones(3))) == pytest.approx(12.0)
    # across +-pi
    c = np.radians([179.0, -179.0, -178.0])
    assert math.degrees(circular_median(c, np.ones(3))) == pytest.approx(-179.0)


# --------------------------------------------------------------------- shadows
def test_round_tip_shadow_closed_form():
    """The tip touching the circle and the step's corner: triangle (R + h, R + r, r).
    The 25 mm tip at the 3 mm ridge of the 10 cm ball: 10.8 deg; a flat step on a large
    circle tends to the flat-floor shadow sqrt(2 r h - h^2)."""
    assert math.degrees(round_tip_shadow(0.05, 0.003, 0.025)) == pytest.approx(10.807, abs=1e-3)
    big = 100.0
    s = round_tip_shadow(big, 0.003, 0.025) * big
    assert s == pytest.approx(math.sqrt(2 * 0.025 * 0.003 - 0.003**2), rel=1e-3)
    assert round_tip_shadow(0.05, 0.0, 0.025) == pytest.approx(0.0, abs=1e-6)


def test_pad_shadow_closed_form():
    """Centred 20 mm pad: atan(10 / 50) = 11.3 deg; pad end 1.5 mm ahead: 1.7 deg; a pad
    longer than the corner's tangent distance sqrt(53^2 - 50^2) = 17.6 mm stops there."""
    assert math.degrees(pad_shadow(0.05, 0.003, 0.01)) == pytest.approx(11.310, abs=1e-3)
    assert math.degrees(pad_shadow(0.05, 0.003, 0.0015)) == pytest.approx(1.718, abs=1e-3)
    corner = math.sqrt(0.053**2 - 0.05**2)
    assert pad_shadow(0.05, 0.003, 0.05) == pytest.approx(math.atan(corner / 0.05))


# --------------------------------------------------------------------- Fig. 2.14 measures
def test_fig214_counts_sign_changes_at_the_2_to_3_switches():
    """Two 2 -> 3 switches, the tangential force flips at the first only: "1/2"; the
    tangential force at the ridge vs off it (medians of |f_t|), images round vs line."""
    t = np.arange(0.0, 4.0, 0.01)
    kind = np.select([t < 1, t < 2, t < 3], [2, 3, 2], 3)
    # normal along -x (n = (1, 0) outward), tangent (n_y, -n_x) = (0, -1): f_t = -fLy
    ft = np.select([t < 1, t < 2, t < 3], [0.1, -0.3, -0.2], -0.3)
    ft = np.where((t > 1.5) & (t < 1.6), -0.8, ft)  # the pad on the ridge
    n = t.size
    pad = np.where((t > 1.5) & (t < 1.6), 0.0, math.radians(90.0))  # ridge at 0 rad
    trace = {"t": t, "kind": kind, "nLx": np.ones(n), "nLy": np.zeros(n), "fLx": -0.3 * np.ones(n),
             "fLy": -ft, "pad_touch": np.ones(n), "pLx": R * np.cos(pad), "pLy": R * np.sin(pad),
             "cx": np.zeros(n), "cy": np.zeros(n), "theta": np.zeros(n)}  # fmt: skip
    line = np.zeros((8, 8))
    line[3:5, 7] = 1.0
    round_ = np.zeros((8, 8))
    round_[3:5, 3:5] = 1.0
    trace["image_t"] = np.array([1.55, 1.8])
    trace["images"] = np.array([line, round_])
    ph = [
        SimpleNamespace(kind=k, phase=k, start=float(a), end=float(a + 1))
        for a, k in enumerate((2, 3, 2, 3))
    ]
    res = SimpleNamespace(trace=trace, phases=ph)
    m = fig214_measures(res, 0.0)
    assert m["tangential_sign_changes_2to3"] == "1/2"
    assert m["tangential_at_ridge_N"] == pytest.approx(0.8)
    assert m["tangential_off_ridge_N"] == pytest.approx(0.3)
    assert m["tactile_elongation_at_ridge"] == pytest.approx(2.0)
    assert m["tactile_elongation_off_ridge"] == pytest.approx(1.0)


def test_ridge_coverage_splits_the_untouched_cells_by_the_shadow():
    """Ridge at 170 deg, walls at 168/172 deg, 10 deg of shadow: cells 172-182 and 158-168
    are shadowed; a gap at 173-182 lies in it (coverage outside the shadow stays 1), a
    gap at 90-92 does not."""
    from planner.exploration.planar.metrics import ridge_coverage

    mask = np.ones(360, bool)
    mask[173:182] = False
    out = ridge_coverage(mask, math.radians(170), math.radians(2), math.radians(10))
    assert out["uncovered_deg"] == [[173.0, 182.0]]
    assert out["shadow_cells"] == 20
    assert out["coverage_outside_shadow"] == 1.0
    mask[90:92] = False
    out = ridge_coverage(mask, math.radians(170), math.radians(2), math.radians(10))
    assert out["uncovered_deg"] == [[90.0, 92.0], [173.0, 182.0]]
    assert out["coverage_outside_shadow"] == pytest.approx(338 / 340)


def test_binned_median_equals_numpy_per_bin():
    """One sort gives np.median(values[keys == k]) for every occupied key, bit for bit."""
    from planner.exploration.planar.macro import binned_median

    rng = np.random.default_rng(3)
    for n in (1, 2, 7, 100, 1000):
        keys, values = rng.integers(0, 25, n), rng.normal(size=n)
        occupied, med = binned_median(keys, values)
        np.testing.assert_array_equal(occupied, np.unique(keys))
        np.testing.assert_array_equal(med, [np.median(values[keys == k]) for k in occupied])
    occupied, med = binned_median(np.zeros(0, int), np.zeros(0))
    assert occupied.size == 0 and med.size == 0


def test_outline_bins_match_the_per_bin_loop():
    """Vectorized binning = the per-bin loop it replaced (median radius, mean angle, mean
    normal), to rounding."""
    from planner.exploration.planar.metrics import BIN_ANGLE, outline_bins

    rng = np.random.default_rng(4)
    ang = np.sort(rng.uniform(0.0, 0.5, 300)) + rng.normal(0.0, 0.003, 300)
    P = np.c_[np.cos(ang), np.sin(ang)] * (R + rng.normal(0.0, 1e-4, 300))[:, None]
    N = P / np.linalg.norm(P, axis=1)[:, None] + rng.normal(0.0, 0.01, (300, 2))
    a = np.unwrap(np.arctan2(P[:, 1], P[:, 0]))
    k = np.floor((a - a.min()) / BIN_ANGLE).astype(int)
    occ = np.unique(k)
    rad = np.array([np.median(np.hypot(*P[k == i].T)) for i in occ])
    mean = np.array([np.mean(a[k == i]) for i in occ])
    nrm = np.array([N[k == i].mean(axis=0) for i in occ])
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    pts, normals = outline_bins(P, N)
    np.testing.assert_allclose(pts, np.c_[rad * np.cos(mean), rad * np.sin(mean)], atol=1e-15)
    np.testing.assert_allclose(normals, nrm, atol=1e-15)


# --------------------------------------------------------------------- vectorized references
def _est(beta_left: float, beta_right: float = 0.4):
    c = np.array([0.0, R])
    p = np.array([_polar(beta_left), _polar(beta_right)])
    return SimpleNamespace(
        centre=c, p=p, beta=np.array([beta_left, beta_right]), normal_force=np.array([0.3, 1.1]),
        u=0.001, tips=p, n=-(p - c) / R,
    )  # fmt: skip


def _scalar_rows(seg, tl):
    from planner.exploration.planar.phase_segment import references

    return np.array([[seg.hold_force(t), *references(seg, t)] for t in tl])


@pytest.mark.parametrize("kind", [2, 3])
@pytest.mark.parametrize("via", [None, 2.2])
def test_explore_segment_references_vectorized_equal_the_callables(kind, via):
    """Phases 2/3 (and the back-stroke's two pieces): the table of
    :func:`segment_references` holds the scalar callables' numbers (to 1e-15; bit for bit
    where numpy's and libm's cos/sin agree)."""
    from planner.exploration.planar.segments import explore_segment, segment_references
    from planner.exploration.planar.settings import GaitSettings
    from robots.planar_hand import PlanarHand

    s = GaitSettings()
    seg = explore_segment(kind, _est(2.6), np.full(6, 0.2), 2.3, 0.1, s, PlanarHand(), via=via)
    tl = np.r_[-0.01, 0.0, np.linspace(0.0, seg.duration + 0.1, 397), s.startup_time]
    table = segment_references(seg, tl)
    assert table.shape == (tl.size, 23)
    np.testing.assert_allclose(table, _scalar_rows(seg, tl), rtol=0, atol=1e-15)


def test_phase1_segment_references_vectorized_equal_the_callables():
    from planner.exploration.planar.segments import phase1_segment, segment_references
    from planner.exploration.planar.settings import GaitSettings
    from robots.planar_hand import PlanarHand

    rng = np.random.default_rng(5)
    k = 7
    centre = np.c_[rng.normal(0, 1e-3, k), R + rng.normal(0, 1e-3, k)]
    beta = np.c_[np.linspace(2.6, 2.3, k), np.linspace(0.4, 0.1, k)]
    q = rng.normal(0.0, 0.5, (k, 6))
    plan = SimpleNamespace(rotation=-0.4, theta=np.linspace(0.0, -0.4, k), centre=centre,
                           q=q, beta=beta, u=np.linspace(0, 0.01, k))  # fmt: skip
    s = GaitSettings()
    seg = phase1_segment(plan, _est(2.6), np.zeros(6), 0.3, s, PlanarHand(), lift=0.0015)
    tl = np.r_[-0.01, np.linspace(0.0, seg.duration + 0.2, 501)]
    np.testing.assert_allclose(
        segment_references(seg, tl), _scalar_rows(seg, tl), rtol=0, atol=1e-15
    )


def test_references_of_plain_callables_are_called_row_by_row():
    from planner.exploration.planar.controller import Segment
    from planner.exploration.planar.segments import segment_references

    seg = Segment(
        kind=3, duration=1.0, hold_force=lambda t: 2 * t, explore_force=lambda t: 0.3,
        explore=lambda t: ((t, 1.0), (0.5, 0.0), -t),
    )  # fmt: skip
    tl = np.array([0.0, 0.5])
    table = segment_references(seg, tl)
    np.testing.assert_allclose(table, _scalar_rows(seg, tl), rtol=0, atol=1e-15)
    assert table[1, 0] == 1.0 and table[1, 15] == 1.0 and table[1, 1] == 0.0


def test_curvature_features_need_the_smoothing_window_inside_the_pass():
    """A detection nearer an end of the pass than three of the detector's largest scales
    (EDGE_ARC = 2.25 mm for the 3 mm virtual tip) sees the padding: dropped."""
    from planner.exploration.planar.metrics import EDGE_ARC, inside_pass
    from planner.exploration.planar.pad_trace import VIRTUAL_RADIUS

    assert EDGE_ARC == pytest.approx(3 * VIRTUAL_RADIUS / 4)
    a = np.radians(np.linspace(20.0, 40.0, 81))
    pts = R * np.c_[np.cos(a), np.sin(a)]
    at = [R * np.array([math.cos(math.radians(x)), math.sin(math.radians(x))])
          for x in (21.1, 28.9, 38.0, 37.0)]  # fmt: skip
    kept = inside_pass([(p, 1) for p in at], pts)
    # 1.1 deg (0.96 mm) and 2.0 deg (1.75 mm) from an end: dropped; 8.9 and 3 deg: kept
    assert [round(math.degrees(math.atan2(p[1], p[0])), 1) for p, _ in kept] == [28.9, 37.0]
    assert inside_pass([], pts) == []


def test_circular_groups_split_at_gaps_and_join_across_pi():
    """Sorted angles split where they differ by the gap or more; the first and last group
    are one across +-pi; items are grouped by their angle key."""
    from planner.exploration.planar.angles import circular_groups

    a = np.radians([-179.0, -170.0, 10.0, 12.0, 175.0]).tolist()
    groups = circular_groups(a, math.radians(8.0))
    assert [np.degrees(g).round(6).tolist() for g in groups] == [
        [175.0, -179.0],
        [-170.0],
        [10.0, 12.0],
    ]
    items = [(x, i) for i, x in enumerate(a)]
    keyed = circular_groups(items, math.radians(8.0), angle=lambda it: it[0])
    assert [[i for _, i in g] for g in keyed] == [[4, 0], [1], [2, 3]]
    assert circular_groups([], 0.1) == []
    assert circular_median(np.radians([175.0, -179.0])) == pytest.approx(math.radians(178.0))
