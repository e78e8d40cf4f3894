"""Motion primitives of the explorer, as generators of plate-frame velocities (§4.2-4.4).

Each primitive is a generator that reads ``ex.est`` (the latest estimate of
:class:`~planner.exploration.surface.runtime.ExplorerController`) and yields the desired
contact-point velocity in the plate plane [m/s] (a (2,) array or a pair of floats) once per
servo period; it returns its result through ``StopIteration`` (``res = yield from
move_to(...)``). The hybrid law turns the velocity into the desired position of eq. 4.9 and
presses with the normal force. The loops run once per millisecond of simulated time: they work
on Python floats, not on small numpy arrays.
"""

from __future__ import annotations

import numpy as np

from planner.errors import ContactLost
from planner.exploration.surface.runtime import PHASE

__all__ = ["approach", "idle", "move_to", "sweep"]

ZERO = np.zeros(2)
GAIN = 10.0  # [1/s] position gain of the point-to-point and cross-track corrections


def idle(ex, seconds: float, rate: float = 1000.0):
    """Hold still for ``seconds`` [s]."""
    ex.phase = PHASE["idle"]
    for _ in range(max(1, int(seconds * rate))):
        yield ZERO


def approach(ex, timeout: float = 1.5, settle: int = 40):
    """Press down (open-loop normal force) until the OWTS reports ``settle`` contact steps.

    Raises:
        ContactLost: no contact within ``timeout`` [s] (the plate is out of reach).
    """
    ex.phase = PHASE["approach"]
    t0, run = ex.est.t, 0
    while run < settle:
        run = run + 1 if ex.est.in_contact else 0
        if ex.est.t - t0 > timeout:
            raise ContactLost(f"no contact with the plate within {timeout:g} s of pressing down")
        yield ZERO
    ex.ctl.reanchor()
    yield ZERO


def move_to(ex, target, speed: float, tol: float = 4e-4, phase: str = "move", timeout=None):
    """Slide to ``target`` (2,) [m] at up to ``speed`` [m/s]; returns whether it arrived."""
    ex.phase = PHASE[phase]
    target = np.asarray(target, float)
    t_end = ex.est.t + (timeout if timeout is not None else 3.0 + 3.0 * _dist(ex, target) / speed)
    gu, gv = float(target[0]), float(target[1])
    while True:
        est = ex.est
        c = est.centre
        du, dv = gu - float(c[0]), gv - float(c[1])
        n = float(np.hypot(du, dv))  # not math.hypot: it rounds differently
        if n < tol:
            return True
        if est.t > t_end:
            ex.event("move_timeout", f"could not reach {target.round(4).tolist()} m", gap=n)
            return False
        m = min(speed, GAIN * n)
        yield du / n * m, dv / n * m


def _dist(ex, target) -> float:
    return float(np.hypot(*(np.asarray(target) - ex.est.uv)))


def sweep(ex, a, b, speed: float, phase: str = "search", detector=None, every: int = 20):
    """Slide along the segment ``a -> b`` (2,) [m] (moving to ``a`` first).

    The recorder range starts where the finger starts making progress along ``a -> b``: on
    a slope the move to ``a`` overshoots it (the desired position of eq. 4.9 runs ahead of
    the lagging finger), and the way back over the overshoot would read as the crossing
    doubling back on itself (a tent's end slopes then cancel, ``identify``'s crease cue).

    Args:
        detector: optional ``detector(k0, k) -> detection | None`` called every ``every``
            steps with the recorder range of this sweep; a detection ends the sweep.

    Returns:
        ``(k0, k1, detection)``: the recorder range of the sweep and the detection (or None).
    """
    a, b = np.asarray(a, float), np.asarray(b, float)
    yield from move_to(ex, a, speed)
    ex.phase = PHASE[phase]
    L = float(np.hypot(*(b - a)))
    if L < 1e-9:
        return ex.rec.n, ex.rec.n, None
    d = (b - a) / L
    du, dv = float(d[0]), float(d[1])  # along; the cross-track direction is (-dv, du)
    au, av, bu, bv = float(a[0]), float(a[1]), float(b[0]), float(b[1])
    k0, i = ex.rec.n, 0
    lowest = np.inf  # least progress along a -> b so far [m]
    t_end = ex.est.t + 3.0 + 2.0 * L / speed
    while True:
        est = ex.est
        c = est.centre
        cu, cv = float(c[0]), float(c[1])
        if not ((bu - cu) * du + (bv - cv) * dv > 2e-4 and est.t < t_end):
            break
        done = (cu - au) * du + (cv - av) * dv
        if done < lowest:  # still coming back from an overshoot past ``a``
            lowest, k0 = done, max(ex.rec.n - 1, k0)
        e = GAIN * ((cu - au) * -dv + (cv - av) * du)
        yield speed * du + e * dv, speed * dv - e * du
        i += 1
        if detector is not None and i % every == 0:
            hit = detector(k0, ex.rec.n)
            if hit is not None:
                return k0, ex.rec.n, hit
    if detector is not None:
        hit = detector(k0, ex.rec.n, flush=True)
        if hit is not None:
            return k0, ex.rec.n, hit
    return k0, ex.rec.n, None
