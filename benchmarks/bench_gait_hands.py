"""Map-space study: which hands of this finger design turn the §2.3.1 batch (issue 11).

The executed gait does not turn the batch's squares (``bench_gait.py``). Is that the hand we
chose (the thesis gives no dimensions: ``robots/planar_hand/params.py``) or the squares?
This study asks map space, which bounds the executor (``bench_gait.py``: the executor's full
turns are map space's at its planning friction but for one object): for every hand of a grid
around the gait's hand -- the fingers' base half-spacing, the first link's length, the
first joint's range (the other links and joints those of
``robots.planar_hand.gait_hand_params``, the left finger the right one's mirror image) and
the left fingertip (the flat pad carrying the 8x8 array, as on the gait's hand, or a round
tip of 2.5 cm, the right one's, or of 1.5 cm: the thesis, §2.3.2, found "the combination of
one flat fingertip and one 2.5 cm radius fingertip was fairly restrictive" and wished for a
curved 1.5 cm tactile fingertip) -- and for three cases -- the contact friction ``mu = 1``
with force closure alone (as ``plan_gait``; the thesis' Fig. 2.12 simulation: a grasp on
the cones' edge counts), the executor's planning friction (``mu (1 - friction_margin)`` =
0.8), and that friction with the executor's phase-1 stability threshold
(``GaitSettings.min_epsilon``) -- how many of each family's objects turn a full turn from
the resting pose
(:func:`planner.exploration.planar.start_reach.start_reach`: every start grasp and handoff,
5 deg grid).

One row per hand and case: full turns per family (``k/N``), the hand's parameters, and
``gait_hand`` = yes for the gait's geometry (its bases, links and joint ranges; with the flat
left pad it is the hand the executor uses). Pure map space (no simulation): 2-4 s per hand
and case on a 2-core machine (the 648 tasks in 19 min, 23 min with the test suite running
beside it).

Run: ``python benchmarks/bench_gait_hands.py [--quick] [--jobs N] [--out DIR]`` (``--quick``:
the gait's geometry with each left tip, every 4th object).
"""

from __future__ import annotations

import itertools
import multiprocessing as mp
import sys
import time
from dataclasses import dataclass, replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from _common import arg_parser, load_average, write_report  # noqa: E402
from bench_gait import objects  # noqa: E402

from robots.planar_hand import GAIT_LOWER_DEG, GAIT_UPPER_DEG  # noqa: E402

#: the grid: fingers' base half-spacing [m], first link length [m], joint-1 lower and upper
#: limit of the right finger [deg] (the gait's hand: 0.10 m, 0.10 m, -40 deg, 90 deg)
BASE_X = (0.06, 0.08, 0.10, 0.12)
LINK1 = (0.08, 0.10, 0.12)
JOINT1_LOWER = (-40.0, -65.0, -90.0)
JOINT1_UPPER = (90.0, 120.0)
#: the left fingertips: None = the flat pad (the gait's hand), else a round tip's radius [m]
LEFT_TIPS = (None, 0.025, 0.015)


def tip_name(radius: float | None) -> str:
    """A left fingertip in words: ``"flat pad"`` (``radius`` None), ``"round 2.5 cm"``."""
    return "flat pad" if radius is None else f"round {100 * radius:g} cm"


@dataclass(frozen=True)
class HandSpec:
    """One hand of the grid (the rest of the hand is the gait's hand).

    Attributes:
        base_x: |x| of both fingers' first joints [m] (right at +base_x, left mirrored).
        link1: length of the first link of both fingers [m].
        joint1: (lower, upper) limit of the right finger's first joint [deg] (left mirrored).
        left_radius: None for the flat left pad (the gait's hand), else the radius of a round
            left tip [m].
    """

    base_x: float
    link1: float
    joint1: tuple[float, float]
    left_radius: float | None = None

    @property
    def left_tip(self) -> str:
        """The left fingertip in words (:func:`tip_name`)."""
        return tip_name(self.left_radius)

    def hand(self, mu: float):
        """The :class:`robots.planar_hand.PlanarHand` of this spec with friction ``mu``."""
        from robots.planar_hand import PlanarHand
        from robots.planar_hand.params import ranged_hand_params

        lower = (self.joint1[0], *GAIT_LOWER_DEG[1:])
        upper = (self.joint1[1], *GAIT_UPPER_DEG[1:])
        p = ranged_hand_params(lower, upper, mu, self.left_radius)
        right, left = p.right, p.left
        lengths = (self.link1, *right.lengths[1:])
        return PlanarHand(replace(
            p,
            right=replace(right, base=(self.base_x, 0.0), lengths=lengths),
            left=replace(left, base=(-self.base_x, 0.0), lengths=lengths),
        ))  # fmt: skip

    @property
    def is_gait_geometry(self) -> bool:
        """Bases, links and joint ranges are the executor's hand's (``gait_hand_params``)."""
        from robots.planar_hand.params import default_finger

        f = default_finger("right")
        return (self.base_x, self.link1) == (f.base[0], f.lengths[0]) and self.joint1 == (
            GAIT_LOWER_DEG[0], GAIT_UPPER_DEG[0])  # fmt: skip

    @property
    def is_gait_hand(self) -> bool:
        """This is the executor's hand (``gait_hand_params``: its geometry, the flat pad)."""
        return self.is_gait_geometry and self.left_radius is None


def grid(quick: bool) -> list[HandSpec]:
    """The hands of the study: the gait's geometry with each left tip first (the gait's hand
    itself first of all), then the others, flat pads first."""
    specs = [HandSpec(b, l1, (lo, hi), tip) for tip, b, l1, lo, hi in
             itertools.product(LEFT_TIPS, BASE_X, LINK1, JOINT1_LOWER, JOINT1_UPPER)]  # fmt: skip
    specs.sort(key=lambda s: not s.is_gait_geometry)
    return specs[: len(LEFT_TIPS)] if quick else specs


def study_hand(args) -> dict:
    """Full turns from rest per family for one hand and friction (a worker's task)."""
    from planner.errors import HapexError
    from planner.exploration.planar.start_reach import start_reach

    spec, mu, min_epsilon, quick = args
    hand = spec.hand(mu)
    t0 = time.perf_counter()
    turns: dict[str, list[bool]] = {}
    for obj in objects(quick):
        try:
            full = start_reach(obj.profile, hand, mu, min_epsilon=min_epsilon).full_turn
        except HapexError:  # an object that does not fit this hand
            full = False
        turns.setdefault(obj.family, []).append(full)
    row = {"benchmark": "hand", "mu": mu, "min_epsilon": min_epsilon,
           "gait_hand": "yes" if spec.is_gait_geometry else "", "left_tip": spec.left_tip,
           "base_x_cm": round(100 * spec.base_x, 1), "link1_cm": round(100 * spec.link1, 1),
           "joint1_deg": f"{spec.joint1[0]:g}..{spec.joint1[1]:g}"}  # fmt: skip
    for fam, v in turns.items():
        row[fam] = f"{sum(v)}/{len(v)}"
    row["wall_s"] = round(time.perf_counter() - t0, 2)
    return row


def _full(row: dict, family: str) -> int:
    """Full turns of ``family`` in a study row (0 when absent)."""
    return int(str(row.get(family, "0/0")).split("/")[0])


def _hands(n: int) -> str:
    return f"{n} hand" + ("s" if n > 1 else "")


def summary(rows: list[dict], families: list[str]) -> list[str]:
    """Notes: per friction, stability threshold and left fingertip, the gait's geometry and
    the hands that turn the most squares."""
    notes = []
    cases = sorted({(r["mu"], r["min_epsilon"]) for r in rows}, key=lambda c: (-c[0], c[1]))
    tips = list(dict.fromkeys(r.get("left_tip", "flat pad") for r in rows))
    for (mu, eps), tip in itertools.product(cases, tips):
        at = [r for r in rows if (r["mu"], r["min_epsilon"], r.get("left_tip", "flat pad"))
              == (mu, eps, tip)]  # fmt: skip
        if not at:
            continue
        case = f"mu {mu:g}" + (f", epsilon >= {eps:g}" if eps else "")
        if len(tips) > 1:
            case += f", left {tip}"
        gait = [r for r in at if r["gait_hand"]]
        if gait:
            counts = ", ".join(f"{f} {gait[0][f]}" for f in families)
            whose = "hand" if tip == "flat pad" else "geometry"
            notes.append(f"{case}, the gait's {whose}: {counts}")
        for fam in (f for f in families if f.startswith("square")):
            best = max(_full(r, fam) for r in at)
            n = str(at[0][fam]).split("/")[1]
            hands = [r for r in at if _full(r, fam) == best]
            line = f"{case}, {fam}: at most {best}/{n} full turns over the {_hands(len(at))}"
            if best:
                h = hands[0]
                line += (f" ({_hands(len(hands))}, e.g. base {h['base_x_cm']:g} cm, link 1 "
                         f"{h['link1_cm']:g} cm, joint 1 {h['joint1_deg']} deg)")  # fmt: skip
            notes.append(line)
    return notes


def main() -> None:
    from planner.exploration.planar.settings import GaitSettings

    p = arg_parser(__doc__.splitlines()[0])
    p.add_argument("--jobs", type=int, default=2, help="worker processes")
    args = p.parse_args()
    if args.jobs < 1:
        p.error(f"--jobs: {args.jobs}: expected at least 1")
    t0 = time.perf_counter()
    s = GaitSettings(mu=1.0)
    cases = ((1.0, 0.0), (s.planning_mu, 0.0), (s.planning_mu, s.min_epsilon))
    tasks = [(spec, *case, args.quick) for case in cases for spec in grid(args.quick)]
    with mp.get_context("fork").Pool(args.jobs) as pool:
        rows = []
        for i, row in enumerate(pool.imap(study_hand, tasks), 1):
            rows.append(row)
            print(f"\r{i}/{len(tasks)} hands", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    families = list(dict.fromkeys(o.family for o in objects(args.quick)))
    notes = summary(rows, families) + [
        "full turns from the resting pose in map space (planar/start_reach.py: every start "
        "grasp and handoff, 5 deg grid, pure rolling); the hands: the gait's hand "
        f"(robots.planar_hand.gait_hand_params: joints {list(GAIT_LOWER_DEG)} .. "
        f"{list(GAIT_UPPER_DEG)} deg, bases at +-10 cm, links 10/6/4 cm) with base "
        f"half-spacing {[round(100 * b) for b in BASE_X]} cm, link 1 "
        f"{[round(100 * v) for v in LINK1]} cm, joint 1 from {list(JOINT1_LOWER)} to "
        f"{list(JOINT1_UPPER)} deg (left finger mirrored), left tip "
        f"{[tip_name(r) for r in LEFT_TIPS]} (the right tip round "
        f"2.5 cm); mu {s.planning_mu:g} = the executor's "
        "planning friction (GaitSettings.friction_margin), min_epsilon "
        f"{s.min_epsilon:g} its phase-1 stability threshold (GaitSettings.min_epsilon; 0: "
        "force closure only, as plan_gait)",
        f"total wall {time.perf_counter() - t0:.0f} s, {args.jobs} worker processes; load "
        f"average at the end {load_average()}",
    ]
    cols = ["benchmark", "mu", "min_epsilon", "left_tip", "gait_hand", "base_x_cm", "link1_cm",
            "joint1_deg", *families, "wall_s"]  # fmt: skip
    write_report("bench_gait_hands", rows, title="hapex map-space hand study (issue 11, "
                 "§2.3.1 batch)", out=args.out, notes=notes, columns=cols)  # fmt: skip


if __name__ == "__main__":
    main()
