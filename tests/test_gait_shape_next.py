"""The right tip's regrasp over the far corner onto the next face
(pivot_planning.next_face): closed forms on a tilted square and a hexagon."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.exploration.planar import pivot_reach as pr
from planner.exploration.planar.outline_pose import Outline
from planner.exploration.planar.pivot_planning import next_face
from planner.exploration.planar.shape_tracking import ShapeTracker
from planner.geometry import shapes
from robots.planar_hand import PlanarHand

A = 0.03  # half-width of the 6 cm square [m]


def _tracker(outline: Outline, pose) -> ShapeTracker:
    return ShapeTracker(outline, pose, PlanarHand())


def _rot(theta: float) -> np.ndarray:
    return pr.rotation(theta)


def _ends(face) -> np.ndarray:
    return np.array([face.start, face.start + face.length * face.tangent])


@pytest.mark.parametrize("deg", [0.0, -20.0, -42.0])
def test_next_face_of_the_right_face_is_the_top_face(deg):
    """The 6 cm square standing ``deg`` over on its palm corner: beyond the right face's
    far (upper) end lies the top face, its normal the turned +y, its ends the upper
    corners."""
    theta = math.radians(deg)
    outline = Outline.from_profile(shapes.rounded_rectangle(2 * A, 2 * A, 0.0))
    k = np.array([A, 0.0])
    centre = pr.pivoted(np.array([0.0, A]), k, theta)
    tr = _tracker(outline, (centre[0], centre[1], theta))
    W = outline.posed(tr.pose)
    br, top_r, top_l = (
        pr.pivoted(np.array(p), k, theta) for p in ([A, 0], [A, 2 * A], [-A, 2 * A])
    )
    right = pr.Face.between(br, top_r, W.mean(axis=0))
    assert np.allclose(right.start, br, atol=1e-12)  # d runs up from the palm corner
    nxt = next_face(tr, right)
    assert nxt is not None
    np.testing.assert_allclose(nxt.normal, _rot(theta) @ [0.0, 1.0], atol=1e-9)
    assert nxt.length == pytest.approx(2 * A, abs=1e-9)
    ends = _ends(nxt)
    assert min(np.linalg.norm(ends - top_r, axis=1)) < 1e-9
    assert min(np.linalg.norm(ends - top_l, axis=1)) < 1e-9


def test_next_face_of_a_hexagon_turns_by_60_degrees():
    """A regular hexagon of side 4 cm resting on a face: the face beyond the lower-right
    face's far end has its normal turned 60 deg counter-clockwise."""
    R = 0.04
    ang = -0.5 * np.pi + np.pi / 6 - 2 * np.pi * np.arange(6) / 6  # clockwise, on an edge
    profile = shapes.polygon(R * np.column_stack([np.cos(ang), np.sin(ang)]))
    outline = Outline.from_profile(profile)
    h = R * math.cos(math.pi / 6)
    tr = _tracker(outline, (0.0, h, 0.0))
    W = outline.posed(tr.pose)
    k = pr.palm_corner(W)
    upper = np.array([R, h])  # the rightmost vertex
    face = pr.Face.between(k, upper, W.mean(axis=0))
    nxt = next_face(tr, face)
    assert nxt is not None
    a0 = math.atan2(face.normal[1], face.normal[0])
    a1 = math.atan2(nxt.normal[1], nxt.normal[0])
    assert math.remainder(a1 - a0, 2 * math.pi) == pytest.approx(math.pi / 3, abs=1e-9)
    assert nxt.length == pytest.approx(R, abs=1e-9)


def test_no_next_face_beyond_a_rounded_corner():
    """A rounded corner (radius 1.6 cm) between the faces: the outline there is no
    straight face of at least ``MIN_FACE``."""
    outline = Outline.from_profile(shapes.rounded_rectangle(0.08, 0.08, 0.016))
    tr = _tracker(outline, (0.0, 0.04, 0.0))
    W = outline.posed(tr.pose)
    face = pr.Face.between(np.array([0.04, 0.016]), np.array([0.04, 0.064]), W.mean(axis=0))
    assert next_face(tr, face) is None


def test_the_move_around_a_corner_keeps_the_tip_on_its_circle():
    """``_around``: from ``T0`` straight to ``corner + r m0``, on the circle of radius r
    about the corner to ``corner + r m1`` (a quarter turn for a square), then straight to
    ``T1``; the fractions run over its length."""
    from planner.exploration.planar.pivot_planning import _around

    r = 0.025
    c = np.array([0.03, 0.06])
    m0, m1 = np.array([1.0, 0.0]), np.array([0.0, 1.0])
    T0 = c + r * m0 + np.array([0.0, -0.02])  # 2 cm below, on the right face's offset line
    T1 = c + r * m1 + np.array([-0.01, 0.0])  # 1 cm left, on the top face's offset line
    T, t = _around(T0, T1, (c, m0), m1, r, 400)
    length = 0.02 + 0.5 * math.pi * r + 0.01
    np.testing.assert_allclose(np.diff(t), 1 / 399)
    d = np.linalg.norm(T - c, axis=1)
    arc = (t * length > 0.02 + 2e-3) & (t * length < 0.02 + 0.5 * math.pi * r - 2e-3)
    # on the chords of 6 arc pieces (15 deg each): between r cos(7.5 deg) and r
    assert arc.sum() > 100
    assert np.all(d[arc] <= r + 1e-12) and np.all(d[arc] >= r * math.cos(math.radians(7.5)))
    np.testing.assert_allclose(T[-1], T1, atol=1e-15)
    assert np.all(T[arc, 0] >= c[0] - 1e-12) and np.all(T[arc, 1] >= c[1] - 1e-12)


@pytest.mark.parametrize("turns", [-1, 1, 2])
def test_a_square_on_its_next_face_plans_as_at_the_start(turns):
    """The tracker's pose a quarter turn on (the global fit's symmetric pose: the square
    lying on its next face) poses the same world polygon, so the face under the round tip,
    the palm corner and the next face are the start's."""
    from planner.exploration.planar.outline_pose import symmetric_pose
    from planner.exploration.planar.pivot_planning import tip_face

    outline = Outline.from_profile(shapes.rounded_rectangle(2 * A, 2 * A, 0.0))
    start = np.array([0.004, A, 0.0])
    hand = PlanarHand()
    r = hand.params.right.tip_radius
    from types import SimpleNamespace

    est = SimpleNamespace(
        pad_touch=True, tips=np.array([[-A + 0.004, 0.03], [A + 0.004 + r, 0.025]]),
        phi=np.array([-0.5 * math.pi, 0.0]), u=0.0, normal_force=np.array([1.0, 1.0]),
    )  # fmt: skip
    faces = []
    for pose in (start, symmetric_pose(outline, start, turns, 4)):
        tr = _tracker(outline, pose)
        face, d0 = tip_face(tr, est)
        nxt = next_face(tr, face)
        W = outline.posed(tr.pose)
        faces.append((face.start, face.normal, face.length, d0, nxt.normal, pr.palm_corner(W)))
    for a, b in zip(*faces, strict=True):
        np.testing.assert_allclose(a, b, atol=1e-12)
