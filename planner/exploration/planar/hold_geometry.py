"""Friction-cone geometry of the gait's holds and grasps on a non-round object (§2.2.3).

The executor plans on a circle: the holder's push in phase 2/3 and the two-finger grasp of
phase 1 are checked with polar angles about the estimated centre
(``phase_planning.right_hold_angle``, :func:`.heuristics.stable_pair`). On a non-round object the
contact normals are not radial, and these angles are what the friction cones see:

* :func:`palm_press_angle`: a finger pressing the object against the palm (no moment about
  the palm contact) pushes along the chord from its contact to the palm contact; its force
  is inside the friction cone iff the chord makes less than ``atan(mu)`` with the inward
  normal. On a circle this is the inscribed angle ``(pi/2 - beta) / 2`` (the ``M = 0`` case
  of :func:`.segments.hold_tangential_force`).
* :func:`contact_line_angles`: two fingers squeezing along the line through their contacts
  (a two-contact force closure) need that line inside both cones; on a circle both angles
  are ``pi/2 - |beta_L - beta_R| / 2`` (:func:`.heuristics.stable_pair`).
* :func:`resting_contact`: a contact on the true profile resting on the palm, for the two.
* :func:`grasp_window`: the (right, left) contact-angle pairs of a resting pose where the
  right finger can hold the object on the palm, the two fingers can squeeze it, and the
  flat left pad reaches its contact.

Measured with these on ``ellipse_gait`` (12 x 10 cm, see the scenario's description): with
the ellipse standing on its end the right holder's chord makes 44 deg with its normal at
``beta`` = 20 deg where the circle model says 35 deg, and :func:`grasp_window` (press <= 34
deg, contact line <= 30 deg, 2.9 deg of pad reserve) keeps 2-6 of 195 pairs between -60 and
-120 deg (13 lying flat), all with the right contact at >= 35 deg.
"""

from __future__ import annotations

import math

import numpy as np

from planner import checks
from planner.exploration.planar.objects import rest_height


def _unit(v: np.ndarray, name: str) -> np.ndarray:
    n = float(np.hypot(v[0], v[1]))
    if not n > 1e-12:
        raise checks.InvalidParameter(f"{name}: expected a non-zero 2-D vector, got {v.tolist()}")
    return v / n


def palm_press_angle(contact, inward_normal, palm_contact) -> float:
    """Angle [rad] between a holder's inward normal at ``contact`` and the chord from
    ``contact`` to ``palm_contact`` (all (2,), world [m]; the normal need not be unit).

    The holder's force must lie along that chord for the object to stay on the palm without
    rolling (its moment about the palm contact vanishes; the explorer's drag and gravity
    add to it); it is inside a friction cone of coefficient ``mu`` iff the angle is below
    ``atan(mu)``.

    Raises:
        InvalidParameter: a zero normal, or the contact on the palm contact.
    """
    p = checks.vector("contact", contact, 2, "m")
    n = _unit(checks.vector("inward_normal", inward_normal, 2), "inward_normal")
    chord = _unit(checks.vector("palm_contact", palm_contact, 2, "m") - p, "palm_contact - contact")
    return float(math.acos(min(max(float(n @ chord), -1.0), 1.0)))


def contact_line_angles(p_left, n_left, p_right, n_right) -> tuple[float, float]:
    """Angles [rad] between the line through two contacts and each finger's inward normal
    (points (2,) [m], inward normals (2,), world). The squeeze along the line is inside both
    friction cones iff both angles are below ``atan(mu)``.

    Raises:
        InvalidParameter: zero normals or coincident contacts.
    """
    pl = checks.vector("p_left", p_left, 2, "m")
    pr = checks.vector("p_right", p_right, 2, "m")
    line = _unit(pr - pl, "p_right - p_left")
    nl = _unit(checks.vector("n_left", n_left, 2), "n_left")
    nr = _unit(checks.vector("n_right", n_right, 2), "n_right")
    a_left = math.acos(min(max(float(nl @ line), -1.0), 1.0))
    a_right = math.acos(min(max(float(-(nr @ line)), -1.0), 1.0))
    return float(a_left), float(a_right)


def resting_contact(profile, angle: float, beta: float):
    """A contact on ``profile`` turned by ``angle`` [rad] and resting on the palm (its
    lowest point at y = 0, origin above it at :func:`.objects.rest_height`).

    Args:
        profile: closed, star-shaped profile (object frame) [m].
        angle: object rotation [rad] (counter-clockwise).
        beta: world polar angle of the contact about the object origin [rad].

    Returns:
        ``(point (2,), inward normal (2,), palm contact (2,))`` in the world [m]; the palm
        contact is the lowest point of the sampled outline (0.5 mm spacing).
    """
    c, s = math.cos(angle), math.sin(angle)
    rot = np.array([[c, -s], [s, c]])
    origin = np.array([0.0, rest_height(profile, angle)])
    pts, nrm = profile.point_at_polar_angle([beta - angle])
    point = rot @ pts[0] + origin
    world = profile.sample(5e-4).points @ rot.T + origin
    palm = world[int(np.argmin(world[:, 1]))]
    return point, -(rot @ nrm[0]), np.array([float(palm[0]), 0.0])


def grasp_window(
    profile,
    hand,
    angle: float,
    mu: float,
    *,
    press_limit: float,
    line_limit: float,
    joint_reserve: float,
    step: float = math.radians(5.0),
) -> list[tuple[float, float]]:
    """World contact angles ``(beta_right, beta_left)`` [rad] (right 10-70 deg, left
    120-190 deg, every ``step``) of ``profile`` turned by ``angle`` [rad] and resting on the
    palm, at which the right finger's palm press is within ``press_limit`` of its normal,
    the contact line within ``line_limit`` of both normals (both [rad], at most
    ``atan(mu)``) and the flat left pad, lying on its contact, keeps ``joint_reserve``
    [rad] from every joint limit (the right tip's reach is not checked: it is not the
    binding one on ``ellipse_gait``).

    Raises:
        InvalidParameter: a limit beyond the friction cone ``atan(mu)``.
    """
    from planner.errors import HapexError
    from planner.exploration.planar.heuristics import pad_angle

    cone = math.atan(checks.positive("mu", mu))
    for name, v in (("press_limit", press_limit), ("line_limit", line_limit)):
        if not 0.0 < v <= cone:
            raise checks.InvalidParameter(
                f"{name}: expected in (0, atan(mu) = {cone:.4f}] [rad], got {v!r}"
            )
    lim = hand.finger_limits("left")
    mid = float(lim.sum(axis=0).mean())
    rights = np.arange(math.radians(10.0), math.radians(70.0) + 1e-9, step)
    lefts = np.arange(math.radians(120.0), math.radians(190.0) + 1e-9, step)
    out = []
    for br in rights:
        pr, nr, palm = resting_contact(profile, angle, float(br))
        if palm_press_angle(pr, nr, palm) > press_limit:
            continue
        for bl in lefts:
            pl, nl, _ = resting_contact(profile, angle, float(bl))
            if max(contact_line_angles(pl, nl, pr, nr)) > line_limit:
                continue
            try:
                q = hand.inverse_kinematics(
                    "left", pl, angle=pad_angle(math.atan2(-nl[1], -nl[0]), mid)
                )
            except HapexError:
                continue
            if float(np.min(np.minimum(q - lim[:, 0], lim[:, 1] - q))) >= joint_reserve:
                out.append((float(br), float(bl)))
    return out


__all__ = ["contact_line_angles", "grasp_window", "palm_press_angle", "resting_contact"]
