"""Explicit rolling (thesis §2.2.2, Figs. 2.8-2.10): the contact locations on both fingertips
are commanded independently of the object pose, which the object impedance holds still.

The commanded locations are sinusoids about the start contacts (``amplitude`` [m] on the
flat pad, the same arclength on the round tip, half a period apart); the fingertip
orientations follow from pure rolling on the nominal object (eq. 2.4: ``d phi = du / R`` on
the pad, ``d phi = -ds (R + r) / (r R)`` on the round tip), and the rolling PD (eq. 2.8)
corrects the sensed contact locations towards the commands.
"""

from __future__ import annotations

import math
import time

import numpy as np

from planner.exploration.planar.controller import GaitController
from planner.exploration.planar.objects import mean_radius
from planner.exploration.planar.phase_segment import Segment
from planner.exploration.planar.result import ExplorationResult, PhaseRecord
from planner.exploration.planar.sensing import round_contact_arclength
from planner.exploration.planar.settings import GaitSettings
from planner.exploration.planar.setup import build_world
from planner.trajectory import ForceRamp


def explicit_rolling(
    profile,
    hand=None,
    mu: float = 1.0,
    *,
    amplitude: float = 0.004,
    period: float = 2.0,
    duration: float = 4.0,
    seed: int = 0,
    settings: GaitSettings | None = None,
) -> ExplorationResult:
    """Run the explicit-rolling experiment of Figs. 2.9/2.10 on ``profile``.

    Returns:
        an :class:`ExplorationResult` with one phase-1 record; ``trace`` holds the
        commanded (``u_des``, ``sR_des``) and sensed (``u``, ``sR``) contact locations.
    """
    from planner import checks

    checks.positive("amplitude", amplitude, "m")
    checks.positive("period", period, "s")
    checks.positive("duration", duration, "s")
    wall0 = time.perf_counter()
    s = settings or GaitSettings(mu=float(mu))
    if hand is None:
        from robots.planar_hand import PlanarHand

        hand = PlanarHand(friction=float(mu))
    R = mean_radius(profile)
    world, _ = build_world(profile, hand, mu, R, None, s, seed)
    ctrl = GaitController(hand, s, R, world.gravity)
    obs = world.observe()
    e = ctrl.sensing.update(obs, "palm")
    r = hand.params.right.tip_radius
    q0 = obs.q
    u0 = e.u
    phi0 = np.array([q0[0:3].sum(), q0[3:6].sum()])
    s0 = round_contact_arclength(e.beta[1], phi0[1], r)
    w = 2 * math.pi / period
    pose0 = (float(e.centre[0]), float(e.centre[1]) + 0.001, 0.0)

    def rolling(t):
        a = amplitude * math.sin(w * t)
        ad = amplitude * w * math.cos(w * t)
        b = amplitude * math.sin(w * t + math.pi / 2) - amplitude
        bd = amplitude * w * math.cos(w * t + math.pi / 2)
        k = (R + r) / (r * R)
        phi = np.array([phi0[0] + a / R, phi0[1] - b * k])
        phid = np.array([ad / R, -bd * k])
        return u0 + a, s0 + b, phi, phid

    ramp = ForceRamp(0.0, s.internal_force, s.startup_time)
    seg = Segment(
        kind=1,
        duration=duration,
        pose=lambda t: (pose0, (0.0, 0.0, 0.0)),
        rolling=rolling,
        hold_force=lambda t: float(ramp(t)),
    )
    ctrl.start(seg, world.time)
    log = world.run(duration, ctrl, control_rate=s.control_rate, stop=ctrl.stop)
    from planner.exploration.planar.controller import trace_arrays

    trace = trace_arrays(ctrl)
    a = np.unwrap(log.poses["object"][:, 2])
    event = ctrl.event or ("sim fault" if log.status == "failed" else "time limit")
    rec = PhaseRecord(1, False, 0.0, world.time, float(a[-1] - a[0]), 0.0, event)
    failed = log.status == "failed" or event in ("contact lost",)
    return ExplorationResult(
        status="failed" if failed else "ok",
        reason=(log.reason or event) if failed else "explicit rolling finished",
        phases=(rec,),
        rotation=float(a[-1] - a[0]),
        coverage=float("nan"),
        contact_coverage=float("nan"),
        min_epsilon=float("nan"),
        features=(),
        log=log,
        trace=trace,
        timings={
            "wall_s": time.perf_counter() - wall0,
            "control_step_us": list(1e6 * np.asarray(ctrl.step_times)),
        },  # fmt: skip
    )


__all__ = ["explicit_rolling"]
