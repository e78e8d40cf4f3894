"""The gait's fast paths compute what the reference paths compute.

* the compiled phase loop (:mod:`planner.exploration.planar.gait_loop`: the controller's
  calls and the per-step :class:`PhaseStop` inside the planar world's compiled loop)
  against the reference loop (``loop="python"``: one Python controller call and one
  ``stop`` call per step) on phases of ``ball_with_ridge``: the same log, trace, images,
  events, fallbacks and generator state, to the bit (where NumPy's ufuncs round as the C
  library does; else in a child process that pins NumPy to its baseline code:
  :mod:`numpy_libm`);
* the simulator's compiled tactile image against the NumPy reference
  (:meth:`TactileImages._image_reference`) on the gait's world;
* a short ``explore_object`` run: the compiled run loop and the Python reference loop give
  the same phases, trace and log.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from planner.exploration.planar import controller_kernel as ck
from planner.exploration.planar import explore_object
from planner.exploration.planar.controller import GaitController
from planner.exploration.planar.gait_loop import PhaseStop
from planner.exploration.planar.machine import HOLD_SLIP, _Runner
from planner.exploration.planar.setup import build_world, gait_prior

SCENARIO = Path(__file__).parents[1] / "scenarios" / "ball_with_ridge.yaml"


def _config():
    from planner.kinds.gait import Config

    return Config.model_validate({"name": "ball", **yaml.safe_load(SCENARIO.read_text())})


#: the watched points of a :class:`PhaseStop` (``holder`` of phases 2/3 as the machine has
#: it: the left fingertip in phase 2, the right one in phase 3)
WATCH = {"both": (True, True), "centre": (True, False), "tip": (False, True)}


def _phases(loop: str, seed: int, kinds=(1, 2), seconds: float = 0.5, slip: float = HOLD_SLIP,
            watch: str = "both"):  # fmt: skip
    """Run the first phases of ``ball_with_ridge`` (planned as the machine plans them) with
    :class:`PhaseStop` (watching ``watch``: :data:`WATCH`) through
    ``world.run(..., loop=loop)``."""
    from planner.exploration.planar.objects import mean_radius
    from planner.trajectory import RollingNLP

    cfg = _config()
    s, hand, profile = cfg.settings(), cfg.hand.hand(cfg.mu), cfg.object.profile()
    R = mean_radius(cfg.nominal.profile())
    prior, _ = gait_prior(cfg.nominal.profile(), R, hand, cfg.mu)
    world, start = build_world(profile, hand, cfg.mu, R, prior, s, seed)
    ctrl = GaitController(hand, s, R, world.gravity)
    runner = _Runner(world, ctrl, RollingNLP(hand, knots=s.nlp_knots), s, hand, start, None,
                     2 * math.pi)  # fmt: skip
    logs, stops, progress = [], [], []
    for kind in kinds:
        est = ctrl.sensing.update(world.observe(), {1: "auto", 2: "pad", 3: "palm"}[kind])
        seg = runner._plan(kind, est, world.observe().q)[0]
        ctrl.start(seg, world.time)
        centre, tip = WATCH[watch]
        holder = (0 if kind == 2 else 1) if tip else None
        stop = PhaseStop(ctrl, slip if kind != 1 else None, progress.append, holder, centre)
        logs.append(world.run(seconds, ctrl, control_rate=s.control_rate, stop=stop, loop=loop))
        stops.append((stop.moved, None if stop.c0 is None else stop.c0.tolist(), ctrl.event))
    return logs, stops, ctrl, world, progress


@pytest.mark.parametrize("seed", [0, 1])
def test_compiled_phases_equal_the_reference_loop(seed, request):
    """To the bit, where NumPy's ufuncs round as the C library the kernels call does;
    elsewhere (AVX-512 NumPy: ``exp``, ``arctan2``, ``hypot`` differ in the last bit, and
    the runs by 1e-12 rad after 80 ms) in a child process with NumPy's SIMD dispatch off
    (:mod:`numpy_libm`)."""
    from numpy_libm import needs_baseline_rerun, rerun_with_baseline_numpy
    from test_sim_fast_run import assert_same_log

    if needs_baseline_rerun():
        proc = rerun_with_baseline_numpy(request.node.nodeid)
        assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
        return
    fast = _phases("auto", seed)
    ref = _phases("python", seed)
    for la, lb in zip(fast[0], ref[0], strict=True):
        assert_same_log(la, lb)
    assert fast[1] == ref[1]
    ca, cb = fast[2], ref[2]
    assert ca.trace == cb.trace
    assert len(ca.images) == len(cb.images) > 0
    for (ta, ia), (tb, ib) in zip(ca.images, cb.images, strict=True):
        assert ta == tb
        np.testing.assert_array_equal(ia, ib)
    assert ca.fallbacks == cb.fallbacks
    state = np.r_[0 : ck.K_STEP_FN, ck.K_TAU_BOUND : ck.N_KS]  # not the step's C addresses
    np.testing.assert_array_equal(ca._ks[state], cb._ks[state])
    assert fast[3].rng.random() == ref[3].rng.random()  # the same draws of the generator
    assert fast[4] and fast[4][-1] == ref[4][-1]  # progress reached the same end time
    assert len(ca.step_times) == len(ca.trace)


@pytest.mark.parametrize("watch", sorted(WATCH))
def test_phase_stop_ends_a_phase_when_the_held_object_moves(watch):
    """A hold slip of 0.1 mm: the phase-2 run ends with "object moved" in both loops, at
    the same step, whichever points the check watches."""
    ends = []
    for loop in ("auto", "python"):
        logs, stops, *_ = _phases(loop, 0, kinds=(1, 2), seconds=1.0, slip=1e-4, watch=watch)
        ends.append((logs[-1].t[-1], logs[-1].reason, stops[-1][0], len(logs[-1].t)))
    assert ends[0] == ends[1]
    assert ends[0][1] == "object moved" and ends[0][2] is True


class _FakeCtrl:
    """What a :class:`PhaseStop` reads: the sensing buffer and the controller's event."""

    def __init__(self) -> None:
        from types import SimpleNamespace

        from planner.exploration.planar.sensing import N_BUF

        self.sensing = SimpleNamespace(est=SimpleNamespace(buffer=np.zeros(N_BUF)))

    def stop(self, t, world):
        return None

    def move(self, what: str, dx: float) -> None:
        from planner.exploration.planar.sensing import B_C, B_TIPS

        i = B_C.start if what == "centre" else B_TIPS.start + 2 * int(what[-1])
        self.sensing.est.buffer[i] += dx


@pytest.mark.parametrize(
    ("holder", "centre", "moves", "moved"),
    [
        (1, True, ["centre"], False),  # the centre estimate jumped on a flat face
        (1, True, ["tip1"], False),  # the holding fingertip rolled ahead of the object
        (1, True, ["tip0", "centre"], False),  # the other (exploring) fingertip
        (1, True, ["tip1", "centre"], True),  # both: the object was dragged
        (None, True, ["centre"], True),
        (0, False, ["tip0"], True),
        (0, False, ["centre", "tip1"], False),
    ],
)
def test_phase_stop_needs_every_watched_point_to_move(holder, centre, moves, moved):
    ctrl = _FakeCtrl()
    stop = PhaseStop(ctrl, 0.01, None, holder, centre)
    assert stop(0.0, None) is None  # the first call takes the reference
    for what in moves:
        ctrl.move(what, 0.0101)
    assert (stop(0.001, None) == "object moved") is moved
    assert stop.moved is moved


def test_phase_stop_arguments():
    with pytest.raises(ValueError, match="holder must be None, 0 or 1"):
        PhaseStop(_FakeCtrl(), 0.01, None, 2)
    with pytest.raises(ValueError, match="watches the centre, a holding fingertip or both"):
        PhaseStop(_FakeCtrl(), 0.01, None, None, False)


def test_simulated_pad_image_equals_the_numpy_reference():
    logs, _, ctrl, world, _ = _phases("auto", 0, kinds=(1,), seconds=0.2)
    a, b = world.observe().tactile, world.observe().tactile
    img = a["left"]
    assert img.sum() > 0, "the pad touches the ball"
    np.testing.assert_array_equal(img, b._image_reference("left"))


def test_short_gait_compiled_equals_python_loop(monkeypatch):
    """explore_object for 0.6 s: the planar world's compiled run loop (as the gait uses it
    today, with the machine's per-step stop) against the reference loop."""
    from planner.sim.planar.world import PlanarWorld

    cfg = _config()
    kw = dict(hand=cfg.hand.hand(cfg.mu), mu=cfg.mu, nominal=cfg.nominal.profile(), seed=0,
              duration=0.6, settings=cfg.settings())  # fmt: skip
    fast = explore_object(cfg.object.profile(), **kw)
    monkeypatch.setattr(PlanarWorld, "compiled_loop", lambda self, state: None)
    ref = explore_object(cfg.object.profile(), **kw)
    assert [(p.kind, p.start, p.end, p.event) for p in fast.phases] == [
        (p.kind, p.start, p.end, p.event) for p in ref.phases
    ]
    for key in ("t", "theta", "fnL", "u", "pLx"):
        np.testing.assert_array_equal(fast.trace[key], ref.trace[key])
    np.testing.assert_array_equal(fast.trace["images"], ref.trace["images"])
    np.testing.assert_array_equal(fast.log.q, ref.log.q)
    assert (fast.status, fast.rotation, fast.coverage) == (ref.status, ref.rotation, ref.coverage)


def test_gauge_noise_drawn_ahead_equals_one_draw_per_reading():
    """GaugeNoise hands out the readings one draw per call would give and leaves the
    generator where those draws leave it (also across blocks and repeated syncs)."""
    from planner.sim.planar.sensing import GaugeNoise

    ref, rng = np.random.default_rng(3), np.random.default_rng(3)
    noise = GaugeNoise(rng, 0.01)
    for n in (5, GaugeNoise.BLOCK + 7, 0, 1):
        for _ in range(n):
            np.testing.assert_array_equal(noise.take(), ref.normal(0.0, 0.01, (2, 2)))
        noise.sync()
        assert rng.bit_generator.state == ref.bit_generator.state
    assert rng.random() == ref.random()
