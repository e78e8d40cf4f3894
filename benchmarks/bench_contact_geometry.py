"""Planar contact search per step: the Python path against the compiled kernel (issue #15).

Run: ``python benchmarks/bench_contact_geometry.py [--quick] [--out DIR]``.

For hand scenes (two fingertips, the palm, one object) it times, warm, one whole contact
search (every body pair, the step's margins) by

* ``python``: :func:`planner.sim.planar.stepper.find_contacts` (pure Python, the reference);
* ``ContactSearch``: :class:`planner.sim.planar.contact_search.ContactSearch` called from
  Python (buffers reused, a new result array per call);
* ``contacts_into (Python call)``: the compiled kernel called from Python on caller buffers;
* ``contacts_into (inside numba)``: the same kernel called from a numba loop (no dispatch):
  what a compiled step pays;

and checks that both paths give the same candidates (``max |diff|``). The issue's budget for
the geometry is 5-10 µs per step (the whole step <= 50 µs for 20x real time at dt = 1 ms).
Compile time is measured separately in a fresh process with an empty numba cache (cold) and
again with that cache filled (``cache=True``: what every later process pays).
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _common import ROOT, arg_parser, time_call, write_report  # noqa: E402

BUDGET = "<= 5-10"


def _hand_world(obj: str, left: str, right: str):
    """A world with the hand's fingertips touching ``obj`` held at (0, 0.12)."""
    from planner.geometry import shapes
    from planner.sim.planar.world import PlanarWorld
    from robots.planar_hand import PlanarHand

    hand = PlanarHand(left_tip=left, right_tip=right, friction=1.0)
    profiles = {
        "ball": (shapes.circle(0.03), 0.03),
        "box": (shapes.rounded_rectangle(0.06, 0.04, 0.004), 0.03),
        "polygon": (
            shapes.polygon([(-0.03, -0.02), (0.03, -0.025), (0.028, 0.02), (-0.025, 0.03)]),
            0.03,
        ),
        "ellipse": (shapes.ellipse(0.03, 0.02), 0.03),
    }
    prof, half = profiles[obj]
    q = []
    for name, side, tip in (("left", -1.0, left), ("right", 1.0, right)):
        f = hand.params.finger(name)
        off = f.tip_radius if tip == "round" else 0.0
        point = np.array([side * (half + off), 0.12])
        angle = None if tip == "round" else side * math.pi / 2
        q.append(hand.inverse_kinematics(name, point, angle=angle))
    world = PlanarWorld()
    world.add_hand(hand, np.concatenate(q))
    world.add_body(prof, (0.0, 0.12, 0.0), 0.1, friction=1.0, name=obj)
    return world


def _poses(world) -> np.ndarray:
    from planner.sim.planar.bodies import FIXED, FREE

    tips = world.hand.frames(world.q)[1]
    rows = []
    for b in world.bodies:
        rows.append(
            b.pose if b.kind == FIXED else world._x[b.index] if b.kind == FREE else tips[b.index]
        )
    return np.array(rows, float)


def _numba_loop():
    from numba import njit

    from planner.sim.planar.geometry_kernel import contacts_into

    @njit
    def loop(F, I, poses, pairs, margins, out, counts, reps):  # noqa: E741
        s = 0
        for _ in range(reps):
            s += contacts_into(F, I, poses, pairs, margins, out, counts)
        return s

    return loop


def bench_scene(rows, label, world, loop, reps) -> None:
    from planner.sim.planar.contact_search import ContactSearch
    from planner.sim.planar.geometry_kernel import contacts_into
    from planner.sim.planar.packed_outlines import PackedOutlines
    from planner.sim.planar.stepper import _reach, find_contacts

    packed = PackedOutlines.from_bodies(world.bodies)
    search = ContactSearch(packed)
    poses = _poses(world)
    reach = _reach(world)
    margins = np.array([world.margin + reach[i] + reach[j] for i, j in packed.pairs])
    ref = np.array(find_contacts(world, world.margin), float).reshape(-1, 10)
    got = search(poses, margins)
    diff = float(np.max(np.abs(np.nan_to_num(ref - got, nan=0.0)), initial=0.0))
    out, counts = np.empty((64, 10)), np.empty(len(packed.pairs), np.int64)
    args = (packed.F, packed.I, poses, packed.pairs, margins, out, counts)
    loop(*args, 1)
    cases = [
        ("python find_contacts", lambda: find_contacts(world, world.margin), 1),
        ("ContactSearch", lambda: search(poses, margins), 1),
        ("contacts_into (Python call)", lambda: contacts_into(*args), 1),
        ("contacts_into (inside numba)", lambda: loop(*args, reps), reps),
    ]
    base = None
    for method, fn, per in cases:
        t = time_call(fn)
        us = t["median_s"] * 1e6 / per
        base = us if base is None else base
        rows.append(
            {
                "scene": label,
                "method": method,
                "median_us": us,
                "best_us": t["best_s"] * 1e6 / per,
                "speedup": base / us,
                "contacts": len(ref),
                "max_diff": diff,
                "budget_us": BUDGET,
            }
        )


COMPILE = """
import time
t0 = time.perf_counter()
import numpy as np
from planner.geometry import shapes
from planner.sim.planar.outline import compile_outline
from planner.sim.planar.packed_outlines import PackedOutlines
from planner.sim.planar.contact_search import find_contacts_packed
t1 = time.perf_counter()
ols = [compile_outline(shapes.circle(0.01)), compile_outline(shapes.ellipse(0.03, 0.02))]
find_contacts_packed(PackedOutlines.from_outlines(ols), np.array([[0, 0.03, 0], [0, 0, 0]]), 0.01)
print(t1 - t0, time.perf_counter() - t1)
"""


def bench_compile(rows) -> None:
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        for label in ("cold (empty numba cache)", "cached (cache=True)"):
            res = subprocess.run(
                [sys.executable, "-c", COMPILE], cwd=ROOT, env=env, capture_output=True, text=True
            )
            imp, first = (float(v) for v in res.stdout.split())
            rows.append(
                {
                    "scene": "compile (fresh process)",
                    "method": label,
                    "note": f"first call {first:.2f} s, imports {imp:.2f} s",
                }
            )


def main() -> None:
    args = arg_parser(__doc__.splitlines()[0]).parse_args()
    scenes = [("ball", "round", "round"), ("box", "flat", "round"), ("polygon", "flat", "flat")]
    scenes += [("ellipse", "round", "flat")]
    if args.quick:
        scenes = scenes[:1] + scenes[-1:]
    loop = _numba_loop()
    rows: list[dict] = []
    for obj, left, right in scenes:
        world = _hand_world(obj, left, right)
        bench_scene(rows, f"hand ({left}/{right}) + palm + {obj}", world, loop, 200)
    from planner.sim.planar import scenes as sc

    world, ctrl, _ = sc.palm_hold_slide_scene()
    for _ in range(20):
        world.step(ctrl(world.time, world.observe()))
    bench_scene(rows, "palm_hold_slide scene (t = 20 ms)", world, loop, 200)
    bench_compile(rows)
    t = time.strftime("%H:%M")
    write_report(
        "contact_geometry",
        rows,
        title="Planar contact search per step: Python vs compiled kernel",
        out=args.out,
        columns=[
            "scene",
            "method",
            "median_us",
            "best_us",
            "speedup",
            "contacts",
            "max_diff",
            "budget_us",
            "note",
        ],
        notes=[
            "warm: numba compiled and cached before timing; median/best of 7 batches",
            "speedup: against python find_contacts of the same scene; max_diff: largest "
            "|difference| of any candidate field between the two paths",
            "compile rows: a fresh process with an empty numba cache (cold), then another one"
            " with that cache filled (cache=True: what every later run pays)",
            f"measured at {t} on a machine shared by several engineers (see the load average)",
        ],
    )


if __name__ == "__main__":
    main()
