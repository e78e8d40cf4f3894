"""Record the gait controller's inputs and outputs on a real run, and replay them.

A recording is a list of *windows*, each starting at a phase start: the sensing update the
phase machine does before planning (``("sense", obs, source)``), the phase start
(``("start", segment values, t)``) and the first control calls of the phase
(``("call", t, obs)``), with the state carried over from the previous phase (the pad
contact location ``u`` and the last good command). The segment's reference callables are
recorded as their values at every time the controller asked for, so a replay needs neither
the planner nor the simulator. Outputs: the torques, the trace row and the event of every
call.

The data file was first recorded with the controller as it was before its hot path was
compiled (commit 252cf84); the compiled controller reproduced it to 1e-9 until phase 1's
rolling reference moved to the phase's own first reading (2026-11-24), when it was
re-recorded with the then scenario's GaitSettings and hand (stored in the file), call by
call. Regenerate it only when the controller's behaviour is meant to change::

    python tests/gait_replay.py record tests/data/gait_controller_replay.pkl.gz
"""

from __future__ import annotations

import dataclasses
import gzip
import math
import pickle
import sys
from pathlib import Path

import numpy as np

DATA = Path(__file__).parent / "data" / "gait_controller_replay.pkl.gz"
_FIELDS = ("pose", "rolling", "explore", "hold_force", "explore_force")


def _obs_dict(obs) -> dict:
    tactile = None if obs.tactile is None else {k: np.array(v) for k, v in obs.tactile.items()}
    return {"t": float(obs.t), "q": np.array(obs.q), "qd": np.array(obs.qd),
            "fingers": tuple(obs.fingers), "tip_forces": np.array(obs.tip_forces),
            "tactile": tactile}  # fmt: skip


def observation(d: dict):
    """The :class:`planner.sim.Observation` of a recorded dict."""
    from planner.sim import Observation

    return Observation(**d)


def _copy(v):
    if isinstance(v, tuple):
        return tuple(_copy(x) for x in v)
    if isinstance(v, np.ndarray):
        return v.copy()
    return v


def record(path: Path, calls_per_window: int = 250, duration: float = 6.0) -> dict:
    """Run ``scenarios/ball_with_ridge.yaml`` for ``duration`` [s] with the current
    controller and save the first ``calls_per_window`` calls of every phase."""
    from planner.exploration.planar import controller as ctl
    from planner.exploration.planar import machine
    from planner.kinds.gait import _hand
    from planner.scenario import load_scenario

    windows: list[dict] = []
    setup: dict = {}

    class Recording(ctl.GaitController):
        def __init__(self, hand, settings, radius, gravity):
            super().__init__(hand, settings, radius, gravity)
            setup.update(radius=float(radius), gravity=np.array(gravity, float),
                         settings=dataclasses.asdict(settings),
                         hand=dataclasses.asdict(hand.params))  # fmt: skip
            self._in_call = False
            self._pending_sense = None
            inner = self.sensing.update

            def update(obs, source="auto"):
                if not self._in_call:
                    self._pending_sense = (_obs_dict(obs), source)
                return inner(obs, source)

            self.sensing.update = update

        def start(self, segment, t):
            values = {f: {} for f in _FIELDS}
            wrapped = {}
            for f in _FIELDS:
                fn = getattr(segment, f)
                if fn is None:
                    wrapped[f] = None
                    continue

                def rec(tl, fn=fn, store=values[f]):
                    out = fn(tl)
                    store[float(tl)] = _copy(out)
                    return out

                wrapped[f] = rec
            seg = ctl.Segment(kind=segment.kind, duration=segment.duration,
                              theta0=segment.theta0, **wrapped)  # fmt: skip
            windows.append({
                "present": [f for f in _FIELDS if getattr(segment, f) is not None],
                "pre": {"u": float(self.sensing.est.u), "last_tau": self._last_tau.copy()},
                "sense": self._pending_sense, "t0": float(t), "kind": segment.kind,
                "duration": segment.duration, "theta0": segment.theta0, "values": values,
                "calls": [],
            })  # fmt: skip
            super().start(seg, t)

        def __call__(self, t, obs):
            self._in_call = True
            try:
                tau = super().__call__(t, obs)
            finally:
                self._in_call = False
            w = windows[-1]
            if len(w["calls"]) < calls_per_window:
                w["calls"].append({"t": float(t), "obs": _obs_dict(obs), "tau": tau.copy(),
                                   "trace": tuple(float(x) for x in self.trace[-1]),
                                   "event": self.event})  # fmt: skip
            return tau

    from planner.exploration.planar.gait_loop import GaitLoop

    cfg = load_scenario(Path(__file__).parent.parent / "scenarios" / "ball_with_ridge.yaml")
    saved, saved_usable = machine.GaitController, GaitLoop.usable
    machine.GaitController = Recording
    # call by call: the compiled phase loop calls the controller's kernel past __call__
    GaitLoop.usable = staticmethod(lambda fast, ctrl, stop: False)
    try:
        machine.explore_object(cfg.object.profile(), hand=_hand(cfg), mu=cfg.mu,
                               nominal=cfg.nominal.profile(), seed=0, duration=duration,
                               settings=cfg.settings(),
                               max_rotation=math.radians(cfg.max_rotation_deg))  # fmt: skip
    finally:
        machine.GaitController = saved
        GaitLoop.usable = staticmethod(saved_usable)
    for w in windows:  # keep only the values the recorded calls asked for
        used = {c["t"] - w["t0"] for c in w["calls"]}
        w["values"] = {f: {k: v for k, v in d.items() if k in used} for f, d in w["values"].items()}
    data = {"scenario": "ball_with_ridge", "duration": duration, "windows": windows, **setup}
    path.parent.mkdir(parents=True, exist_ok=True)
    with gzip.open(path, "wb") as fh:
        pickle.dump(data, fh, protocol=4)
    return data


def load(path: Path = DATA) -> dict:
    """The recording saved by :func:`record`."""
    with gzip.open(path, "rb") as fh:
        return pickle.load(fh)


def replay_segment(window: dict):
    """A :class:`~planner.exploration.planar.phase_segment.Segment` whose callables return
    the recorded values (KeyError for a time that was not recorded)."""
    from planner.exploration.planar.phase_segment import Segment

    fns = {}
    for f in _FIELDS:
        store = window["values"][f]
        fns[f] = store.__getitem__ if f in window["present"] else None
    return Segment(kind=window["kind"], duration=window["duration"], theta0=window["theta0"],
                   **fns)  # fmt: skip


def make_controller(data: dict, cls=None):
    """A fresh controller (``cls``, default :class:`GaitController`) with the settings and
    hand of the recording."""
    from planner.control.internal_force import InternalForceGains
    from planner.exploration.planar.controller import GaitController
    from planner.exploration.planar.settings import GaitSettings
    from robots.planar_hand import PlanarHand
    from robots.planar_hand.params import FingerParams, HandParams

    s = dict(data["settings"])
    s["internal_gains"] = InternalForceGains(**s["internal_gains"])
    h = dict(data["hand"])
    hand = PlanarHand(HandParams(left=FingerParams(**h.pop("left")),
                                 right=FingerParams(**h.pop("right")), **h))  # fmt: skip
    return (cls or GaitController)(hand, GaitSettings(**s), data["radius"], data["gravity"])


def replay(ctrl, data: dict):
    """Feed every window of ``data`` to ``ctrl``; yields ``(call, tau, trace row, event)``."""
    for w in data["windows"]:
        ctrl.sensing.est.u = w["pre"]["u"]
        ctrl._last_tau = w["pre"]["last_tau"].copy()
        if w["sense"] is not None:
            obs, source = w["sense"]
            ctrl.sensing.update(observation(obs), source)
        ctrl.start(replay_segment(w), w["t0"])
        for c in w["calls"]:
            tau = np.array(ctrl(c["t"], observation(c["obs"])))
            yield c, tau, ctrl.trace[-1], ctrl.event


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    if len(sys.argv) == 3 and sys.argv[1] == "record":
        d = record(Path(sys.argv[2]))
        print(f"{len(d['windows'])} windows, {sum(len(w['calls']) for w in d['windows'])} calls")
        for w in d["windows"]:
            print(f"  phase {w['kind']} at t={w['t0']:.3f}: {len(w['calls'])} calls")
    else:
        print(__doc__)
