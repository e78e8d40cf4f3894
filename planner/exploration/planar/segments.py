"""Planning of one phase into a :class:`~.phase_segment.Segment` (re-done at every phase start
from the current sensed estimate; §2.2.2-2.2.3).

* phase 1: the rolling NLP (:class:`planner.trajectory.RollingNLP`) from the sensed state;
  object pose and fingertip contact locations are interpolated between its knots; a startup
  segment ramps the internal force and lifts the object off the palm;
* phases 2/3: the exploring finger's contact runs along the estimated outline (the nominal
  circle about the estimated centre) from where it is to its next grasp angle, on a quintic
  (startup) profile; its orientation is interpolated to the four-region preference (round
  tip) or follows the surface (flat pad, which slides); the holding finger keeps its contact
  and ramps to the holding force, the explorer's normal force ramps to 0.3 N.
"""

from __future__ import annotations

import bisect
import math

import numpy as np

from planner.errors import InvalidParameter
from planner.exploration.planar.heuristics import pad_angle, regrasp_orientation
from planner.exploration.planar.phase_segment import Segment
from planner.exploration.planar.sensing import round_contact_arclength
from planner.trajectory import ForceRamp, QuinticSpline

#: largest change of the round exploring tip's orientation in one phase [rad] (the faults
#: that made it 0 this morning were the simulator's open-outline corner bug)
MAX_REORIENT = 0.6


def _interp(times: np.ndarray, values: np.ndarray):
    """Piecewise-linear ``t -> (value, rate)`` through knots (held outside), as lists of
    floats (plain Python: it runs in every control step)."""
    ts = [float(x) for x in times]
    vs = np.asarray(values, float).tolist()
    n = len(ts)

    def f(t: float):
        k = min(max(bisect.bisect_left(ts, t) - 1, 0), n - 2)  # == clip(searchsorted - 1)
        a, b = vs[k], vs[k + 1]
        h = ts[k + 1] - ts[k]
        w = min(max((t - ts[k]) / h, 0.0), 1.0)
        inside = ts[0] <= t <= ts[-1]
        return (
            [x + w * (y - x) for x, y in zip(a, b, strict=True)],
            [(y - x) / h if inside else 0.0 for x, y in zip(a, b, strict=True)],
        )

    T, V = np.asarray(ts), np.asarray(vs)

    def many(t: np.ndarray):
        k = np.clip(np.searchsorted(T, t, side="left") - 1, 0, n - 2)
        a, b = V[k], V[k + 1]
        h = (T[k + 1] - T[k])[:, None]
        w = np.clip((t[:, None] - T[k][:, None]) / h, 0.0, 1.0)
        inside = ((T[0] <= t) & (t <= T[-1]))[:, None]
        return a + w * (b - a), np.where(inside, (b - a) / h, 0.0)

    f.many = many  # (m,) times -> values (m, k) and rates (m, k), the same numbers
    return f


def _ramp_many(ramp: ForceRamp, t: np.ndarray) -> np.ndarray:
    """``ForceRamp.__call__`` (scalar ends) at the times ``t`` (m,) [s], same arithmetic."""
    s = np.clip(t / ramp.duration, 0.0, 1.0)
    w = s**3 * (10.0 - 15.0 * s + 6.0 * s * s)
    return float(ramp.start) * (1.0 - w) + float(ramp.end) * w


def _quintic_many(spline: QuinticSpline):
    """:meth:`QuinticSpline.scalar` of a 1-D spline for arrays of times: ``t (m,) -> (x, v,
    a)``, each (m,), the same arithmetic."""
    c0, c1, c2, c3, c4, c5 = (float(x) for x in spline.coefficients[:, 0])
    T = spline.duration
    v_end, a_end = spline.scalar()(T)[1:]

    def at(t: np.ndarray):
        t = np.clip(t, 0.0, T)
        p = c0 + t * (c1 + t * (c2 + t * (c3 + t * (c4 + t * c5))))
        v = c1 + t * (2 * c2 + t * (3 * c3 + t * (4 * c4 + t * 5 * c5)))
        a = 2 * c2 + t * (6 * c3 + t * (12 * c4 + t * 20 * c5))
        end = t >= T
        return p, np.where(end, v_end, v), np.where(end, a_end, a)

    return at


def phase1_segment(
    plan, est, q, theta0: float, settings, hand, lift: float, squeeze: float | None = None
) -> Segment:
    """The phase-1 segment following ``plan`` (a :class:`RollingPlan`) from the sensed
    estimate ``est`` and joint angles ``q`` [rad]; ``theta0`` is the rotation estimate,
    ``lift`` [m] raises the pose reference off the palm, ``squeeze`` is the internal force
    [N] ramped to (default ``settings.internal_force``; :mod:`.carry_squeeze`)."""
    s = settings
    rot = abs(plan.rotation)
    T_move = max(rot / s.rotation_speed, 0.1)
    ts = s.startup_time + np.linspace(0.0, T_move, len(plan.theta))
    ts = np.concatenate([[0.0], ts])
    pose = np.column_stack([plan.centre, theta0 + plan.theta])
    pose = np.vstack([[est.centre[0], est.centre[1], theta0], pose])
    pose[1:, 1] += lift
    pose_f = _interp(ts, pose)
    r = hand.params.right.tip_radius
    phiR = plan.q[:, 3:6].sum(axis=1)
    sR = np.array(
        [round_contact_arclength(b, p, r) for b, p in zip(plan.beta[:, 1], phiR, strict=True)]
    )
    phis = np.column_stack([plan.q[:, 0:3].sum(axis=1), phiR])
    roll = np.column_stack([plan.u, sR, phis])
    roll = np.vstack([roll[0], roll])
    roll_f = _interp(ts, roll)

    def rolling(t):
        v, rate = roll_f(t)
        return v[0], v[1], v[2:4], rate[2:4]

    def rolling_many(t):
        v, rate = roll_f.many(t)
        return np.column_stack([v, rate[:, 2:4]])

    rolling.many = rolling_many  # (m,) -> (m, 6): u, s, phi (2), phid (2)
    f0 = float(max(min(est.normal_force), 0.0))
    ramp = ForceRamp(f0, s.internal_force if squeeze is None else squeeze, s.startup_time)
    return Segment(
        kind=1,
        duration=float(ts[-1]) + 0.05,
        pose=pose_f,
        rolling=rolling,
        hold_force=_ramp_function(ramp),
        theta0=theta0,
    )


def _ramp_function(ramp: ForceRamp):
    """``t -> float(ramp(t))`` with its ``many`` twin."""

    def f(t: float) -> float:
        return float(ramp(t))

    f.many = lambda t: _ramp_many(ramp, t)
    return f


def friction_lag(settings) -> float:
    """How far [m] the sliding explorer's contact trails its command: the tangential
    fingertip impedance (``tip_kp`` [N/m]) must pull the Coulomb friction ``mu f_n`` [N]
    along. Measured on the 10 cm ball: 5-7 mm (5-8 deg) behind, so phase 3 ended with the
    flat pad tilted on the ball and the pad-based centre estimate 7 mm off. The executor
    leads the command by this much while the contact moves (friction feed-forward)."""
    return settings.mu * settings.explore_force / settings.tip_kp


#: in a back-stroke the pad's centre trails its contact by this much less than the pad's
#: half-width [m]: the pad touches with its trailing edge, its body away from the feature
#: it approaches (centred, a 20 mm pad tangent to the 10 cm ball met the ridge's wall
#: with its edge 9-11 deg before its contact could get there)
EDGE_MARGIN = 1.5e-3


def contact_stroke(b0: float, b1: float, via: float | None, radius: float, speed: float):
    """The explorer's contact angle ``tm -> (beta, rate, accel)`` [rad, rad/s, rad/s^2] from
    ``b0`` to ``b1`` (through ``via`` when given), quintic pieces at rest at their ends,
    the time [s] it reaches ``via`` (or ``b1``) and its duration [s] (``radius`` [m],
    ``speed`` [m/s])."""
    stops = [b0, b1] if via is None else [b0, via, b1]
    pieces, splines, times = [], [], [0.0]
    for a, b in zip(stops, stops[1:], strict=False):
        T = max(abs(b - a) * radius / speed, 0.05)
        splines.append(QuinticSpline.between([a], [b], T))
        pieces.append(splines[-1].scalar())
        times.append(times[-1] + T)
    many = [_quintic_many(x) for x in splines]
    if len(pieces) == 1:
        pieces[0] = _with_many(pieces[0], many[0])
        return pieces[0], times[-1], times[-1]
    split = times[1]

    def path(tm: float):
        return pieces[0](tm) if tm < split else pieces[1](tm - split)

    def path_many(tm: np.ndarray):
        first, second = many[0](tm), many[1](tm - split)
        return tuple(np.where(tm < split, x, y) for x, y in zip(first, second, strict=True))

    path.many = path_many
    return path, split, times[-1]


def _with_many(f, many):
    """``f`` (a scalar callable) wrapped so that it carries ``many``."""

    def g(t):
        return f(t)

    g.many = many
    return g


def explore_segment(
    kind: int,
    est,
    q,
    target_beta: float,
    theta0: float,
    settings,
    hand,
    travel: float = 0.35,
    via: float | None = None,
    edge: bool = True,
    lead_end: bool = False,
):
    """The phase-2 (``kind`` 2: right explores) or phase-3 (left explores) segment that
    moves the explorer's contact from its sensed angle to ``target_beta`` [rad] (a round
    tip turned to the §2.2.3 orientation on the way, the flat pad lying on the outline);
    ``travel`` [rad] is the contact travel expected in the next phase 1 (for the
    orientation heuristic). ``via`` [rad]: a back-stroke, to ``via`` and back to
    ``target_beta``; in phase 3 the pad's centre trails its contact (:data:`EDGE_MARGIN`)
    so that its edge reaches the far side of a feature the pad jumped over, and with
    ``edge`` False the contact stays centred on the pad (an overlap stroke,
    :mod:`.stroke_overlap`); in phase 2 the round tip's contact simply goes there and back
    (:func:`.corner_probe.top_sweep_back`). ``lead_end`` (phase 3 without ``via``): the
    pad's centre trails its contact by the same margin, its leading end first (the approach
    to a known wall, :func:`.corner_probe.approach_segment`), ramped in with the startup."""
    s = settings
    k = 1 if kind == 2 else 0
    radius = float(np.linalg.norm(est.p[k] - est.centre))
    b0 = float(est.beta[k])
    b1 = b0 + math.atan2(math.sin(target_beta - b0), math.cos(target_beta - b0))
    trail = 0.0
    lead = lead_end and kind == 3 and via is None and b1 != b0
    if via is not None:
        via = b0 + math.atan2(math.sin(via - b0), math.cos(via - b0))
        # the pad's centre on the tangent, on the side the pad comes from
        if edge and kind == 3:
            trail = math.copysign(hand.params.left.pad_half_width - EDGE_MARGIN, b0 - via)
    else:
        via = None
        if lead:
            trail = -math.copysign(hand.params.left.pad_half_width - EDGE_MARGIN, b1 - b0)
    path, _, T_move = contact_stroke(b0, b1, via, radius, s.explore_speed)
    T = s.startup_time + T_move
    c = est.centre.copy()
    r = hand.params.right.tip_radius
    if k == 1 or hand.params.left.round_radius:
        side = "right" if k == 1 else "left"
        phi0 = float(q[3 * k : 3 * k + 3].sum())
        # §2.2.3: the orientation that keeps the finger farthest from its joint limits over
        # the new grasp and the next rotation (without it the right finger started phase 1
        # near its joint-1 stop and every rotation ended at its workspace limit after ~7 deg)
        phi1 = regrasp_orientation(hand, c, radius, b1, travel, finger=side)
        turn = math.atan2(math.sin(phi1 - phi0), math.cos(phi1 - phi0))
        phi1 = phi0 + float(np.clip(turn, -MAX_REORIENT, MAX_REORIENT))

        def phi_of(t, b):
            w = min(max((t - s.startup_time) / T_move, 0.0), 1.0)
            return phi0 + w * (phi1 - phi0)

        def phi_many(t, b):
            return phi0 + np.clip((t - s.startup_time) / T_move, 0.0, 1.0) * (phi1 - phi0)
    else:
        phi0 = float(q[0:3].sum())

        def phi_of(t, b):
            return pad_angle(b, phi0)

        def phi_many(t, b):  # pad_angle: round() and np.round both round half to even
            phi = b + 0.5 * math.pi
            return phi + 2 * math.pi * np.round((phi0 - phi) / (2 * math.pi))

    lag = friction_lag(s) * math.copysign(1.0, b1 - b0)
    cx, cy = float(c[0]), float(c[1])
    w_speed = radius / s.explore_speed

    def explore(t: float):
        tm = t - s.startup_time
        b, bd, _ = path(tm)
        cb, sb = math.cos(b), math.sin(b)
        w = min(max(min(tm, T_move - tm) / s.startup_time, 0.0), 1.0)
        if via is None:  # (an end-first stroke: its centre trails the contact)
            ahead = w * (lag + trail) if lead else w * lag
        else:  # the friction lead follows the motion (it flips at the turn); the trail
            ahead = min(max(bd * w_speed, -1.0), 1.0) * abs(lag) + w * trail
        p = (cx + radius * cb - ahead * sb, cy + radius * sb + ahead * cb)
        v = (-radius * bd * sb, radius * bd * cb)
        return p, v, phi_of(t, b)

    def explore_many(t: np.ndarray) -> np.ndarray:
        tm = t - s.startup_time
        b, bd, _ = path.many(tm)
        cb, sb = np.cos(b), np.sin(b)
        w = np.clip(np.minimum(tm, T_move - tm) / s.startup_time, 0.0, 1.0)
        if via is None:
            ahead = w * (lag + trail) if lead else w * lag
        else:
            ahead = np.clip(bd * w_speed, -1.0, 1.0) * abs(lag) + w * trail
        return np.column_stack([cx + radius * cb - ahead * sb, cy + radius * sb + ahead * cb,
                                -radius * bd * sb, radius * bd * cb, phi_many(t, b)])  # fmt: skip

    explore.many = explore_many  # (m,) -> (m, 5): p (2), v (2), phi

    holder = 0 if kind == 2 else 1
    f_hold0 = float(max(est.normal_force[holder], 0.0))
    f_hold = s.left_hold_force if holder == 0 else s.hold_force
    hold = ForceRamp(f_hold0, f_hold, s.startup_time)
    f_exp0 = float(max(est.normal_force[k], 0.0))
    fexp = ForceRamp(f_exp0, s.explore_force, s.startup_time)
    phiR = float(q[3:6].sum())
    keep = (float(est.u), round_contact_arclength(est.beta[1], phiR, r),
            [float(q[0:3].sum()), phiR], [0.0, 0.0])  # fmt: skip

    def rolling(t):
        return keep

    row = [keep[0], keep[1], *keep[2], *keep[3]]
    rolling.many = lambda t: np.tile(row, (len(t), 1))
    return Segment(
        kind=kind,
        duration=T + 0.02,
        explore=explore,
        rolling=rolling,
        hold_force=_ramp_function(hold),
        explore_force=_ramp_function(fexp),
        theta0=theta0,
        target=b1,
    )


#: columns of :func:`segment_references` (the ``sv`` layout of :mod:`.controller_kernel`
#: from ``V_FDES`` to ``V_FNT``)
REFERENCE_COLUMNS = 23


def segment_references(seg: Segment, tl: np.ndarray) -> np.ndarray:
    """The references of ``seg`` at the phase times ``tl`` (m,) [s] as rows (m, 23) in the
    layout of the kernel's ``sv`` without its two times: hold force, ``has_pose, x, y,
    theta, vx, vy, omega``, ``has_roll, u, s, phi (2), phid (2)``, ``has_explore, p (2), v
    (2), phi``, ``has_force, f_n`` (what ``phase_segment.references`` packs per call).

    The segments built here evaluate them vectorized (each callable's ``many``), with the
    arithmetic of the scalar callables (equal to them bit for bit on this machine: numpy's
    and libm's cos/sin agree here); other callables are called row by row.
    """
    tl = np.asarray(tl, float)
    m = tl.size
    out = np.zeros((m, REFERENCE_COLUMNS))
    out[:, 0] = _many(seg.hold_force, tl, lambda v: [v])
    if seg.pose is not None:
        out[:, 1] = 1.0
        out[:, 2:8] = _many(seg.pose, tl, lambda v: [*v[0], *v[1]], pair=True)
    if seg.rolling is not None:
        out[:, 8] = 1.0
        out[:, 9:15] = _many(seg.rolling, tl, lambda v: [v[0], v[1], *v[2], *v[3]])
    if seg.explore is not None:
        out[:, 15] = 1.0
        out[:, 16:21] = _many(seg.explore, tl, lambda v: [*v[0], *v[1], v[2]])
    if seg.explore_force is not None:
        out[:, 21] = 1.0
        out[:, 22] = _many(seg.explore_force, tl, lambda v: [v])
    return out


def _many(f, tl: np.ndarray, flat, pair: bool = False) -> np.ndarray:
    """``f`` at every time of ``tl``: its ``many`` twin if it has one, else row by row
    (``flat`` turns one scalar result into a list of floats)."""
    many = getattr(f, "many", None)
    if many is not None:
        res = many(tl)
        return np.column_stack(res) if pair else res
    rows = np.asarray([flat(f(float(t))) for t in tl], float).reshape(tl.size, -1)
    return rows[:, 0] if rows.shape[1] == 1 else rows


def hold_tangential_force(
    beta_hold: float, normal_hold: float, moment_other: float, radius: float
) -> float:
    """The tangential force [N] a holding fingertip must apply for a round object resting
    on the palm to stay in equilibrium (phases 2/3, no rolling on the palm).

    Args:
        beta_hold: world polar angle of the holder's contact about the object centre [rad]
            (the palm contact is at ``-pi/2``, straight below the centre).
        normal_hold: the holder's normal force on the object [N] (pressing: > 0).
        moment_other: moment about the palm contact [N m] (counter-clockwise positive) of
            every other force on the object (the explorer's normal force and its friction;
            gravity acts through the centre, straight above the palm contact: none).
        radius: object radius [m].

    Returns:
        the holder's tangential force on the object along the counter-clockwise tangent
        ``(-sin beta, cos beta)`` [N].

    Moments about the palm contact ``P`` (the palm's force has none there): with ``L`` the
    holder's contact, ``n = -(cos beta, sin beta)`` and ``t = (-sin beta, cos beta)``,
    ``(L - P) x n = R cos beta`` and ``(L - P) x t = R (1 + sin beta)``, so::

        T = -(N cos beta + M / R) / (1 + sin beta)

    With ``M = 0`` this is ``T / N = tan((beta - pi/2) / 2)``: the force along the chord to
    the palm contact (the inscribed angle), the squeeze that ``holding_force`` commands.
    The commanded direction does not change ``T`` in equilibrium (the holder's stiffness
    about its anchor supplies the rest): only the normal force does. ``T`` has the sign of
    the squeeze's part while ``N |cos beta| > M / R`` (sign opposite to the explorer's
    drag below it): the sign of Fig. 2.14's phase-2 trace is set by the hold force.
    """
    c, s = math.cos(beta_hold), math.sin(beta_hold)
    if 1.0 + s <= 1e-9:
        raise InvalidParameter(
            f"beta_hold: the holder cannot sit on the palm contact, got {beta_hold!r}"
        )
    return -(normal_hold * c + moment_other / radius) / (1.0 + s)


def palm_moment(point, force, centre, radius: float) -> float:
    """Moment [N m] (counter-clockwise positive) of ``force`` (2,) [N] applied at ``point``
    (2,) [m] about the palm contact of a round object of ``radius`` [m] centred at
    ``centre`` (2,) [m] (the contact straight below the centre)."""
    px, py = point[0] - centre[0], point[1] - centre[1] + radius
    return float(px * force[1] - py * force[0])


__all__ = [
    "contact_stroke",
    "explore_segment",
    "friction_lag",
    "hold_tangential_force",
    "palm_moment",
    "phase1_segment",
    "segment_references",
]
