"""explore_object's argument checks: every bad argument is named, before anything runs."""

from __future__ import annotations

import math

import pytest

from planner.errors import InvalidParameter
from planner.exploration.planar import explore_object
from planner.exploration.planar.arguments import check_arguments
from planner.exploration.planar.settings import GaitSettings
from planner.geometry import shapes

DISC = shapes.circle(0.05)
OK = dict(seed=0, duration=None, settings=None, max_rotation=2 * math.pi, use_prior=True,
          on_progress=None)  # fmt: skip


@pytest.mark.parametrize(
    ("change", "name"),
    [
        ({"mu": 0.0}, "mu"),
        ({"mu": -1}, "mu"),
        ({"mu": math.nan}, "mu"),
        ({"mu": math.inf}, "mu"),
        ({"seed": -1}, "seed"),
        ({"seed": 1.5}, "seed"),
        ({"seed": True}, "seed"),
        ({"duration": 0.0}, "duration"),
        ({"duration": -1.0}, "duration"),
        ({"duration": 1e-4}, "duration"),  # shorter than the 2 ms simulator step
        ({"duration": math.nan}, "duration"),
        ({"max_rotation": 0.0}, "max_rotation"),
        ({"max_rotation": -1.0}, "max_rotation"),
        ({"settings": {"mu": 1.0}}, "settings"),
        ({"hand": "planar"}, "hand"),
        ({"use_prior": "yes"}, "use_prior"),
        ({"on_progress": 3}, "on_progress"),
        ({"profile": shapes.plane()}, "profile"),
        ({"nominal": "circle"}, "nominal"),
    ],
)
def test_each_bad_argument_is_named(change, name):
    args = {"profile": DISC, "hand": None, "mu": 1.0, "nominal": None, **OK, **change}
    with pytest.raises(InvalidParameter, match=rf"^{name}: expected"):
        check_arguments(**args)
    # and explore_object raises it before building the world (fast, no simulation)
    with pytest.raises(InvalidParameter, match=rf"^{name}: expected"):
        explore_object(**args)


@pytest.mark.parametrize(("left", "right"), [("flat", "flat"), ("round", "flat")])
def test_a_hand_with_other_fingertips_is_named(left, right):
    """The executor is written for a round right tip (and a flat or round left one): another
    hand is bad input named as such, not "the object does not fit the hand"."""
    from dataclasses import replace

    from robots.planar_hand import PlanarHand, gait_hand_params

    p = gait_hand_params(1.0)
    hand = PlanarHand(replace(p, left=replace(p.left, tip=left), right=replace(p.right, tip=right)))
    args = {"profile": DISC, "hand": hand, "mu": 1.0, "nominal": None, **OK}
    message = (rf"^hand: expected a round right fingertip and a flat or round left one "
               rf".*, got a {left} left and a {right} right fingertip$")  # fmt: skip
    with pytest.raises(InvalidParameter, match=message):
        explore_object(**args)
    check_arguments(**{**args, "hand": PlanarHand(p)})  # the gait's hand passes
    round_left = PlanarHand(replace(p, left=replace(p.left, tip="round")))
    check_arguments(**{**args, "hand": round_left})  # and one with a round left tip


def test_good_arguments_are_converted():
    mu, seed, duration, max_rotation = check_arguments(
        DISC, None, 1, shapes.circle(0.05), **{**OK, "seed": 3.0, "duration": 2, "max_rotation": 1}
    )
    assert (mu, seed, duration, max_rotation) == (1.0, 3, 2.0, 1.0)
    assert isinstance(mu, float) and isinstance(seed, int) and isinstance(duration, float)
    # unbounded runs are allowed, and the duration floor follows the settings' step
    out = check_arguments(DISC, None, 0.5, None, **{**OK, "duration": math.inf,
                                                    "max_rotation": math.inf})  # fmt: skip
    assert out[2] == math.inf and out[3] == math.inf
    fine = GaitSettings(dt=1e-4, control_rate=1000.0)
    assert check_arguments(DISC, None, 1.0, None, **{**OK, "settings": fine,
                                                     "duration": 1e-4})[2] == 1e-4  # fmt: skip


def test_an_object_beyond_the_workspace_does_not_fit():
    # a 60 cm disc: no fingertip reaches it (plan_gait used to crash on it)
    with pytest.raises(InvalidParameter, match="does not fit"):
        explore_object(shapes.circle(0.3), duration=0.1)


@pytest.mark.parametrize("duration", [0.002, 0.01])
def test_the_shortest_runs_end_by_their_duration(duration):
    # one and five simulator steps: the metrics of a trace shorter than their smoothing
    # windows used to crash (np.convolve 'same' returns the longer operand's length)
    r = explore_object(DISC, duration=duration)
    assert r.status == "ok" and r.reason == f"duration {duration:g} s reached"
    assert len(r.phases) == 1 and r.phases[0].kind == 1
    assert r.phases[0].end == pytest.approx(duration)
    assert len(r.trace["t"]) == round(duration / 0.002)
    assert r.features == ()


@pytest.mark.parametrize("name", ["profile", "nominal"])
def test_an_array_outline_is_refused_in_one_short_line(name):
    """An (N, 2) point array instead of a Profile: refused naming the argument and the
    array's shape, in one line (the message used to print the whole array)."""
    import numpy as np

    pts = 0.04 * np.c_[np.cos(np.linspace(0, 6.2, 200)), np.sin(np.linspace(0, 6.2, 200))]
    args = {"profile": DISC, "nominal": None, name: pts}
    with pytest.raises(InvalidParameter) as err:
        explore_object(args["profile"], nominal=args["nominal"], duration=0.1)
    msg = str(err.value)
    assert msg.startswith(f"{name}: expected a closed planar Profile")
    assert "an array of shape (200, 2)" in msg and "\n" not in msg
    assert msg.endswith("(for (N, 2) vertices [m] use planner.geometry.polygon(points))")
    # the hint's advice works: the same points as a polygon are accepted
    from planner.geometry import polygon

    args[name] = polygon(pts)
    r = explore_object(args["profile"], nominal=args["nominal"], duration=0.01)
    assert r.status == "ok"


@pytest.mark.parametrize("value", ["circle", 3, None, [[0.0, 1.0], [2.0]]])
def test_a_non_outline_profile_gets_no_vertex_hint(value):
    with pytest.raises(InvalidParameter) as err:
        explore_object(value)
    assert "polygon(points)" not in str(err.value)


def test_the_start_grasp_is_searched_with_the_planners_friction():
    """The start grasp (setup.build_world) lies within the planner's cones, ``settings.mu``
    with its reserve, not the world's true friction: a planner that assumes mu 0.5 on a
    world of mu 1 grasps as it would on a world of mu 0.5 (the circle: 0 deg right tip
    where mu 1 puts it 15 deg up), and one that assumes too little friction for any start
    grasp is told so, with the cones it searched."""
    from planner.exploration.planar.setup import build_world
    from robots.planar_hand import PlanarHand, gait_hand_params

    hand = PlanarHand(gait_hand_params(1.0))

    def beta(true_mu, planner_mu):
        s = GaitSettings(mu=planner_mu)
        return build_world(DISC, hand, true_mu, 0.05, None, s, 0, dry=True)[1]["beta"]

    assert beta(1.0, 0.5) == beta(0.5, 0.5)
    assert beta(1.0, 0.5) != beta(1.0, 1.0)
    # the 0.8 cone of the default reserve admits the right tip 15 deg above the centre
    assert math.degrees(beta(1.0, 1.0)[1]) == pytest.approx(15.0)
    with pytest.raises(InvalidParameter, match=r"does not fit.*mu 0\.08: the planner's mu 0\.1"):
        explore_object(DISC, mu=1.0, settings=GaitSettings(mu=0.1), duration=0.1)


def test_a_round_left_tip_with_a_posed_outline_is_named():
    """The posed-outline planner is written for the flat pad: a round left tip with a
    non-round nominal is bad input naming ``nominal``; a round nominal passes."""
    from dataclasses import replace

    from robots.planar_hand import PlanarHand, gait_hand_params

    p = gait_hand_params(1.0)
    hand = PlanarHand(replace(p, left=replace(p.left, tip="round")))
    square = shapes.rounded_rectangle(0.08, 0.08, 0.01)
    with pytest.raises(InvalidParameter, match=r"^nominal: a hand with a round left tip "):
        explore_object(square, hand=hand, mu=1.0, nominal=square, **OK)
    check_arguments(square, hand, 1.0, shapes.circle(0.045), **OK)
    check_arguments(square, PlanarHand(p), 1.0, square, **OK)  # the pad poses it


@pytest.mark.parametrize(
    ("change", "name"),
    [
        ({"object_kp": (-80.0, 80.0, 0.8)}, "object_kp[0]"),
        ({"object_kv": (3.0, 3.0, -0.02)}, "object_kv[2]"),
        ({"object_kp": (80.0, 80.0)}, "object_kp"),
        ({"hold_kp": -0.3}, "hold_kp"),
        ({"hold_kv": -5.0}, "hold_kv"),
        ({"rolling_gains": (1.0, -0.05, 0.04)}, "rolling_gains[1]"),
        ({"rolling_gains": (1.0, 0.05, 0.0)}, "rolling_gains[2] (max_moment)"),
    ],
)
def test_a_bad_gain_is_named_by_the_settings(change, name):
    """Gains are checked where they are given (a negative one pushes away from its
    reference; a zero saturation switches eq. 2.8 off), not deep in the controller."""
    with pytest.raises(InvalidParameter) as err:
        GaitSettings(**change)
    assert str(err.value).startswith(f"{name}: ")
    assert len(str(err.value).splitlines()) == 1


def test_zero_gains_are_allowed():
    """A gain of 0 switches its term off (the theta stiffness of a grasp that may turn)."""
    s = GaitSettings(object_kp=(80.0, 80.0, 0.0), rolling_gains=(0.0, 0.0, 0.04), hold_kp=0.0)
    assert s.object_kp[2] == 0.0 and s.rolling_gains[0] == 0.0 and s.hold_kp == 0.0


@pytest.mark.parametrize("name", ["profile", "nominal"])
def test_an_open_outline_is_refused_by_name_not_by_its_repr(name):
    """An open Profile (a surface, not an object) is named by its name and size, in one line
    (the message used to cut the Profile's repr of nested floats at 80 characters)."""
    from planner.geometry import shapes

    wire = shapes.polyline([[0.0, 0.0], [0.05, 0.01], [0.1, 0.0]])
    args = {"profile": DISC, "nominal": None, name: wire}
    with pytest.raises(InvalidParameter) as err:
        explore_object(args["profile"], nominal=args["nominal"], duration=0.1)
    assert str(err.value).startswith(f"{name}: expected a closed planar Profile (")
    assert str(err.value).endswith("got an open Profile 'polyline' of 2 pieces")
