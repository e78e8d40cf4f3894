"""Benchmark of the executed grasp gait (issue 11): the §2.3.1 batch of objects executed by
``planner.exploration.explore_object`` side by side with ``planner.grasp.plan_gait``'s
map-space verdicts, the phase-1 NLP timings, and optionally the ball-with-ridge run.

Rows:

* ``batch`` (§2.3.1): >= 30 objects - circles, squares sharp and rounded, ellipses 1.1-4:1,
  polygons; half-sizes (radius, half-width, semi-major axis) 2-8 cm - each executed for a
  bounded simulated time (``--duration``, hard wall cap ``--wall-cap`` per object) with
  its outcome (status, reason, rotation, coverage, phases, transitions 4) and the verdict:
  ``full turn`` (360 deg), ``turning`` (still turning the object clockwise when the time
  ran out: at least ``--min-rotation`` deg, or a completed cycle that kept its progress -
  two phase-1 rotations of >= 5 deg each and >= :data:`CYCLE_NET_DEG` deg net: a gait whose
  phases 2/3 give back what its phases 1 turned is not turning the object), ``stalled``
  (ok but neither), ``failed`` (the gait ended with a reason), ``does not fit`` (no start
  grasp: bad input of the gait kind), ``wall cap`` or ``not run`` (over the total
  ``--budget``). The executor *succeeds* on ``full turn`` / ``turning``; ``agree``
  compares that with plan_gait's verdict on the same (true) object, hand and mu;
  ``rest_turn_deg`` / ``rest_blocking``: how far map-space gaits can turn the object from
  where it rests unturned, searched over every start grasp and handoff
  (:mod:`planner.exploration.planar.start_reach`), and the constraint that stops them
  (``rest_turn_reserve_deg``: with the friction and the phase-1 stability threshold the
  executor plans with). Every run then
  goes on up to ``--full-turn`` simulated seconds (default 120; the verdict columns stay
  its state at ``--duration``, which is what a run of that length gives): ``full_turn_s``
  says when it had turned the object 360 deg (blank: never), ``run_end`` how it ended -
  "turning" at 10 s is a promise, this column says whether it was kept;
* ``nlp build`` / ``nlp solve``: the CasADi rolling NLP (targets <= 200 ms, <= 30 ms warm);
* ``ball_with_ridge`` (``--ball S``): the bundled scenario's object for S simulated seconds.

The objects run in parallel worker processes (``--jobs``, forked after a warm-up run so
the compiled kernels are shared; a worker over its wall cap is killed and reported).

The executor's model of each object (``--nominal``, column ``model``): ``circle`` (a
feature-less circle of the object's area, refitted to what the fingers sensed: the issue's
planner, which knows only a nominal shape) and ``true`` (the object's outline, posed from the
sensed contacts at every phase start, as the §2.3.1 simulation modelled the shape); by
default both. Every object runs with each model for ``--seeds`` sensor-noise seeds (default
3; column ``seed``): verdicts on non-round objects flip with the noise, so an object
succeeds when most of its seeds do, and the notes count objects and runs (on 2026-11-25
at 88f1ca3, NumPy at AVX-512: the circle model succeeded on 10 of 32 objects, 32 of 96
runs; the true outline on 9, 26 runs: rounded squares 2/5 with either model; given
120 s, full turns on 9 and 7 objects, 25 and 20 runs: circles, the 1.1:1 ellipse and two
circle-model rounded-square runs. Before 88f1ca3 a completed cycle counted as turning
whatever its net turn: 11 and 10 objects, 35 and 27 runs, the same runs otherwise).
The notes' family lines also count how far map space turns each object from rest with the
executor's planning friction and phase-1 stability threshold (``rest_turn_reserve_deg``;
plan_gait has the full mu and force closure alone): full turns on the circles, the 1.1:1
ellipse and 2 of the 5 polygons only, the rounded squares 20-85 deg, and a disagreement
names it.
``--only square,gon``
runs the objects whose name or family contains one of the substrings. ``--phase-log``
prints every object's phases measured against the truth after the table
(:func:`planner.exploration.planar.phase_log.phase_rows`: true vs sensed rotation, the
centre estimate's error, each contact's ``|T| / N``).

Run: ``python benchmarks/bench_gait.py [--quick] [--duration S] [--jobs N] [--seeds N]
[--full-turn S] [--ball S] [--nominal circle,true] [--only SUBSTRINGS] [--phase-log]
[--left-tip R] [--gravity G]`` (about 3 min on 2 cores with the defaults, 2026-11-24).
``--gravity 0`` runs the batch in a horizontal hand (report ``bench_gait_g0``).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # one thread per worker: the cores go to the workers

import math  # noqa: E402
import multiprocessing as mp  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).parent))
from _common import arg_parser, load_average, write_report  # noqa: E402
from plot_gait_batch import plot, read_batch, stamp  # noqa: E402

#: net clockwise rotation [deg] a run's two completed phase-1 rotations must have kept to
#: count as "turning" below ``--min-rotation`` (twice the 5 deg each must turn)
CYCLE_NET_DEG = 10.0
#: joint ranges of the batch hand (right finger; the left mirrors it) [deg]: the gait's
#: hand, ``explore_object``'s default (``robots.planar_hand.GAIT_LOWER_DEG`` / ``_UPPER_DEG``)
from robots.planar_hand import GAIT_LOWER_DEG as HAND_LOWER_DEG  # noqa: E402
from robots.planar_hand import GAIT_UPPER_DEG as HAND_UPPER_DEG  # noqa: E402


@dataclass(frozen=True)
class BatchObject:
    """One object of the batch: name, family, half-size [cm] and its profile."""

    name: str
    family: str
    size_cm: float
    profile: object


def _polygon(n: int, radius: float):
    """Regular sharp n-gon of circumradius ``radius`` [m] resting on an edge."""
    from planner.geometry import shapes

    ang = -0.5 * np.pi + np.pi / n - 2 * np.pi * np.arange(n) / n  # clockwise
    return shapes.polygon(radius * np.column_stack([np.cos(ang), np.sin(ang)]))


def objects(quick: bool) -> list[BatchObject]:
    """The §2.3.1 batch (32 objects; every 4th with ``quick``)."""
    from planner.geometry import shapes

    out = [BatchObject(f"circle r={r}cm", "circle", r, shapes.circle(r / 100))
           for r in (2, 3, 4, 5, 6, 7, 8)]  # fmt: skip
    for h in (2, 3, 4, 5, 6, 8):
        w = 2 * h / 100
        out.append(BatchObject(f"square {2 * h}cm sharp", "square sharp", h,
                               shapes.rounded_rectangle(w, w, 0.0)))  # fmt: skip
    for h in (3, 4, 5, 6, 7):
        w = 2 * h / 100
        out.append(BatchObject(f"square {2 * h}cm rounded", "square rounded", h,
                               shapes.rounded_rectangle(w, w, w / 5)))  # fmt: skip
    # the bundled ellipse_gait (11 x 10 cm): where the executor's eccentricity ends
    out.append(BatchObject("ellipse 1.1:1 a=5.5cm", "ellipse 1.1:1", 5.5,
                           shapes.ellipse(0.055, 0.05)))  # fmt: skip
    for a in (5, 7):
        for ratio in (1.5, 2, 3, 4):
            out.append(BatchObject(f"ellipse {ratio:g}:1 a={a}cm", f"ellipse {ratio:g}:1", a,
                                   shapes.ellipse(a / 100, a / 100 / ratio)))  # fmt: skip
    for n, r in ((3, 8), (5, 6), (6, 4), (6, 6), (8, 5)):
        out.append(BatchObject(f"{n}-gon R={r}cm", "polygon", r, _polygon(n, r / 100)))
    return out[::4] if quick else out


def batch_hand(mu: float = 1.0, left_tip: float | None = None):
    """The gait's hand with friction ``mu`` [-] (``robots.planar_hand.gait_hand_params``);
    with ``left_tip`` [m] a round left tip of that radius instead of the flat pad."""
    from robots.planar_hand import PlanarHand, gait_hand_params

    return PlanarHand(gait_hand_params(mu, left_tip))


def map_verdict(profile, hand, mu: float) -> tuple[bool, str]:
    """``plan_gait`` on the true object: (a cyclic gait exists, its reason if not)."""
    from planner.errors import HapexError
    from planner.grasp import plan_gait

    try:
        g = plan_gait(profile, hand, mu, resolution=72)
    except HapexError as exc:
        return False, f"error: {exc}"
    return bool(g.feasible), g.reason


def rest_reach(profile, hand, mu: float) -> dict:
    """Map space from the resting pose (:func:`planner.exploration.planar.start_reach.
    start_reach`, every start grasp and handoff): ``rest_turn_deg`` (360 for a full turn)
    and ``rest_blocking`` (what stops it) with ``mu`` and force closure alone (as
    plan_gait), and ``rest_turn_reserve_deg`` with what the executor plans with: the
    friction ``mu (1 - GaitSettings.friction_margin)`` and grasps above its phase-1
    stability threshold ``GaitSettings.min_epsilon``."""
    from planner.errors import HapexError
    from planner.exploration.planar.settings import GaitSettings
    from planner.exploration.planar.start_reach import start_reach

    s = GaitSettings(mu=mu)
    try:
        sr = start_reach(profile, hand, mu)
        sr_reserve = start_reach(profile, hand, s.planning_mu, min_epsilon=s.min_epsilon)
    except HapexError as exc:
        return {"rest_turn_deg": "", "rest_turn_reserve_deg": "", "rest_blocking": f"error: {exc}"}
    why = sr.blocking or (sr_reserve.blocking and f"with mu {s.planning_mu:g} and epsilon >= "
                          f"{s.min_epsilon:g}: {sr_reserve.blocking}")  # fmt: skip
    return {"rest_turn_deg": round(math.degrees(sr.rotation)),
            "rest_turn_reserve_deg": round(math.degrees(sr_reserve.rotation)),
            "rest_blocking": why}  # fmt: skip


def run_object(
    obj: BatchObject,
    duration: float,
    min_rotation_deg: float,
    mu: float,
    nominal: str = "circle",
    phase_log: bool = False,
    map_space: bool = True,
    seed: int = 0,
    full_turn: float = 0.0,
    left_tip: float | None = None,
    gravity: float | None = None,
) -> dict:
    """Execute one object (in a worker process); the batch row. ``nominal``: the planner's
    model, ``"circle"`` (a feature-less circle of the object's area) or ``"true"`` (the
    object's outline, posed from the sensed contacts: the §2.3.1 simulation modelled it).
    ``phase_log``: the row's ``phase_log`` holds one line per phase (:func:`phase_rows`).
    ``map_space``: with the map-space columns (:data:`MAP_COLUMNS`; the same for every
    model of an object, so :func:`bench_batch` has them computed once per object).
    ``seed``: the sensor-noise seed of the run (verdicts on non-round objects depend on
    it: :func:`bench_batch` runs ``--seeds`` of them). ``full_turn`` [s] > ``duration``:
    the same run goes on up to ``full_turn`` simulated seconds (or the full turn, or its
    failure); the verdict columns stay those at ``duration`` (the run is deterministic, so
    they are what a run of ``duration`` gives) and :func:`long_columns` adds how the longer
    run ended. ``left_tip`` [m]: a round left tip of that radius (:func:`batch_hand`).
    ``gravity`` [m/s^2]: towards the palm (``GaitSettings.gravity``; None: its default, a
    vertical hand; 0: a horizontal one)."""
    from planner.exploration import explore_object
    from planner.exploration.planar.setup import check_fits

    hand = batch_hand(mu, left_tip)
    row = {"benchmark": "batch", "object": obj.name, "family": obj.family, "model": nominal,
           "seed": seed, "size_cm": obj.size_cm}  # fmt: skip
    if map_space:
        feasible, why_map = map_verdict(obj.profile, hand, mu)
        row.update(plan_gait="gait" if feasible else "no gait", plan_gait_reason=why_map,
                   **rest_reach(obj.profile, hand, mu))  # fmt: skip
    why = check_fits(obj.profile, mu, hand)
    if why:
        row.update(verdict="does not fit", status="-", reason=why)
        return row
    t0, c0 = time.perf_counter(), time.process_time()
    model = obj.profile if nominal == "true" else None
    run_for = max(duration, full_turn)
    res = explore_object(obj.profile, hand=hand, mu=mu, nominal=model, duration=run_for,
                         seed=seed, settings=gait_settings(mu, gravity))  # fmt: skip
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    sim = float(res.log.t[-1]) if len(res.log.t) else 0.0
    turns = TurnSeries.of(res)
    status, reason, turn = res.status, res.reason, turns.at(duration)
    # phase-1 rotations [deg, clockwise] up to ``duration`` (the phase running then: so far)
    ones = [turns.at(min(p.end, duration)) - turns.at(p.start)
            for p in res.phases if p.phase == 1 and p.start < duration]  # fmt: skip
    if run_for > duration:
        row.update(long_columns(res, turns))
        if sim > duration + 1e-9 and turn < 359.0:  # the run outlived ``duration``
            status, reason = "ok", f"duration {duration:g} s reached"
    verdict = run_verdict(status, turn, ones, min_rotation_deg)
    ends = [p.event for p in res.phases]
    row.update(
        verdict=verdict, status=status, reason=reason, rotation_deg=round(turn, 1),
        coverage=round(res.coverage, 3), phases=len(res.phases),
        phase1=sum(1 for p in res.phases if p.phase == 1), transitions_4=res.transitions4,
        min_epsilon=round(res.min_epsilon, 3) if np.isfinite(res.min_epsilon) else "",
        end_events=_count(ends), sim_s=round(sim, 2), wall_s=round(wall, 1),
        rtf=round(sim / wall, 3) if wall > 0 else "",
        cpu_rtf=round(sim / cpu, 3) if cpu > 0 else "",
    )  # fmt: skip
    if phase_log:
        from planner.exploration.planar.phase_log import phase_rows

        row["phase_log"] = [r.line() for r in phase_rows(res)]
    return row


def gait_settings(mu: float, gravity: float | None = None):
    """The executor's ``GaitSettings`` of a batch run: friction ``mu`` [-] and ``gravity``
    [m/s^2] towards the palm (None: the settings' default)."""
    from planner.exploration.planar import GaitSettings

    return GaitSettings(mu=mu) if gravity is None else GaitSettings(mu=mu, gravity=gravity)


def run_verdict(status: str, turn: float, ones, min_rotation_deg: float) -> str:
    """A batch run's verdict (module docstring) from its ``status`` ("ok" / "failed"), its
    clockwise rotation ``turn`` [deg] when the time ran out, its phase-1 rotations ``ones``
    [deg, clockwise] and the ``--min-rotation`` threshold [deg]: "failed", "full turn",
    "turning" or "stalled"."""
    if status == "failed":
        return "failed"
    if turn >= 359.0:
        return "full turn"
    cycled = sum(1 for x in ones if x >= 5.0) >= 2 and turn >= CYCLE_NET_DEG
    return "turning" if turn >= min_rotation_deg or cycled else "stalled"


@dataclass(frozen=True)
class TurnSeries:
    """The true clockwise rotation of a run's object: ``deg`` [deg] (0 at the start) at
    the log's times ``t`` [s]."""

    t: np.ndarray
    deg: np.ndarray

    @classmethod
    def of(cls, res) -> TurnSeries:
        """The series of an ``ExplorationResult`` (its log's object pose, unwrapped)."""
        deg = -np.degrees(np.unwrap(np.asarray(res.log.poses["object"][:, 2], float)))
        return cls(np.asarray(res.log.t, float), deg - deg[0] if len(deg) else np.zeros(1))

    def at(self, when: float) -> float:
        """The rotation [deg] at simulated time ``when`` [s] (the last one after the end)."""
        k = int(np.searchsorted(self.t, when + 1e-9, side="right")) - 1
        return float(self.deg[min(max(k, 0), len(self.deg) - 1)])


def long_columns(res, turns: TurnSeries) -> dict:
    """How a run given more time (``--full-turn``) ended: ``full_turn_s`` (simulated time
    at which the object had turned 360 deg, blank if never), ``run_end`` (full turn, or the
    run's status and reason) and its ``run_turn_deg``."""
    k = np.flatnonzero(turns.deg >= 359.0)
    when = round(float(turns.t[k[0]]), 1) if len(k) else ""
    end = "full turn" if len(k) else f"{res.status}: {res.reason}"[:160]
    return {"full_turn_s": when, "run_end": end, "run_turn_deg": round(float(turns.deg[-1]), 1)}


def _count(items: list[str]) -> str:
    """``"workspace limit x3, path finished x2"`` (most frequent first)."""
    counts: dict[str, int] = {}
    for x in items:
        counts[x] = counts.get(x, 0) + 1
    return ", ".join(f"{k} x{v}" for k, v in sorted(counts.items(), key=lambda kv: -kv[1]))


def _reserve_turn(row: dict) -> float | None:
    """How far map space turns the row's object from rest with the executor's planning
    friction and stability threshold [deg] (``rest_turn_reserve_deg``), or None (not
    computed, or map space failed: "")."""
    x = row.get("rest_turn_reserve_deg")
    return float(x) if isinstance(x, int | float) else None


def explain(row: dict) -> str:
    """Agreement of the executor with plan_gait, and why they disagree."""
    ok = row["verdict"] in ("full turn", "turning")
    if row["verdict"] in ("wall cap", "not run", "error"):
        return f"not decided ({row['verdict']})"
    if ok == (row["plan_gait"] == "gait"):
        if not ok and row.get("rest_turn_deg") == 360:
            return ("agree; but map space from rest has a full turn that plan_gait's search "
                    f"misses ({row['rest_turn_reserve_deg']} deg with the executor's planning "
                    "friction and threshold)")  # fmt: skip
        return "agree"
    if ok:
        return ("disagree: plan_gait finds no cyclic rolling gait in map space "
                f"({row['plan_gait_reason'][:90]}); the executor turned the object "
                f"{row['rotation_deg']} deg by sliding, re-planning and "
                f"{row['transitions_4']} transition(s) 4")  # fmt: skip
    what = row.get("reason") or row["verdict"]
    if row["verdict"] == "does not fit":
        what = ("no start grasp: plan_gait's reachability grid admits one, the executor's "
                "start-grasp search (IK with joint margins, no penetration) does not")  # fmt: skip
    if row["verdict"] == "stalled":
        what = f"stalled at {row['rotation_deg']} deg in {row['sim_s']} s ({row['end_events']})"
    reserve = _reserve_turn(row)
    if reserve is not None and reserve < 360:
        # plan_gait has the full friction and force closure alone; the executor plans with
        # a friction reserve and a stability threshold, and map space with those is what
        # it can follow
        return (f"disagree: plan_gait finds a gait with the full friction; with the "
                f"executor's planning friction and threshold map space turns it {reserve:g} "
                f"deg from rest; the executor: {what}")[:240]  # fmt: skip
    return f"disagree: plan_gait finds a gait; the executor: {what}"[:200]


def _child(fn, args, conn) -> None:
    try:
        conn.send(fn(*args))
    except Exception as exc:  # noqa: BLE001 - reported as the object's outcome
        conn.send({"verdict": "error", "reason": f"{type(exc).__name__}: {exc}"[:200]})
    conn.close()


def run_parallel(
    tasks: list[tuple], fn, jobs: int, wall_cap: float, budget: float = math.inf
) -> list[dict]:
    """``fn(*task)`` for every task in forked worker processes, at most ``jobs`` at a time;
    a task over ``wall_cap`` [s] is killed (row verdict ``wall cap``); after ``budget`` [s]
    no new task starts (``not run``). Progress on stderr."""
    from tqdm.auto import tqdm

    ctx = mp.get_context("fork")
    out: list[dict | None] = [None] * len(tasks)
    pending = list(range(len(tasks)))
    running: dict[int, tuple] = {}
    start = time.monotonic()
    with tqdm(total=len(tasks), desc="batch", file=sys.stderr) as bar:
        while pending or running:
            if pending and time.monotonic() - start > budget:
                for i in pending:
                    out[i] = {"verdict": "not run", "reason": f"total budget {budget:g} s"}
                bar.update(len(pending))
                pending = []
            while pending and len(running) < jobs:
                i = pending.pop(0)
                recv, send = ctx.Pipe(duplex=False)
                p = ctx.Process(target=_child, args=(fn, tasks[i], send), daemon=True)
                p.start()
                send.close()
                running[i] = (p, recv, time.monotonic())
            for i, (p, recv, t0) in list(running.items()):
                if recv.poll():
                    try:
                        out[i] = recv.recv()
                    except EOFError:  # the worker died without an answer
                        p.join()
                        out[i] = {"verdict": "error", "reason": f"worker exit {p.exitcode}"}
                elif not p.is_alive():
                    out[i] = {"verdict": "error", "reason": f"worker exit {p.exitcode}"}
                elif time.monotonic() - t0 > wall_cap:
                    p.kill()
                    out[i] = {"verdict": "wall cap", "reason": f"over {wall_cap:g} s wall"}
                else:
                    continue
                p.join()
                del running[i]
                bar.update(1)
            time.sleep(0.05)
    return [r or {} for r in out]


def interleaved(objs: list[BatchObject]) -> list[BatchObject]:
    """Round-robin over the shape groups (circle, square, ellipse, polygon), so a batch cut
    short by its budget still covers every group."""
    groups: dict[str, list[BatchObject]] = {}
    for o in objs:
        groups.setdefault(o.family.split()[0], []).append(o)
    out: list[BatchObject] = []
    while any(groups.values()):
        for g in groups.values():
            if g:
                out.append(g.pop(0))
    return out


def bench_batch(args) -> list[dict]:
    from planner.exploration import explore_object
    from planner.geometry import shapes

    tip = args.left_tip or None
    explore_object(shapes.circle(0.05), hand=batch_hand(1.0, tip), duration=0.05)  # warm-up
    objs = interleaved(
        [
            o
            for o in objects(args.quick)
            if not args.only or any(k in o.name or k in o.family for k in args.only.split(","))
        ]
    )
    models = nominal_models(args.nominal)
    # map space once per object: with its first model's first seed
    tasks = [(o, args.duration, args.min_rotation, 1.0, m, args.phase_log,
              m == models[0] and seed == 0, seed, args.full_turn, tip, args.gravity)
             for seed in range(args.seeds) for o in objs for m in models]  # fmt: skip
    rows = run_parallel(tasks, run_object, args.jobs, args.wall_cap, args.budget)
    first = {t[0].name: r for t, r in zip(tasks, rows, strict=True) if t[6]}
    for t, r in zip(tasks, rows, strict=True):
        o, m = t[0], t[4]
        r.setdefault("benchmark", "batch")
        r.setdefault("object", o.name)
        r.setdefault("family", o.family)
        r.setdefault("model", m)
        r.setdefault("seed", t[7])
        for k in MAP_COLUMNS:  # computed with the object's first model
            if k in first[o.name]:
                r.setdefault(k, first[o.name][k])
        r.setdefault("plan_gait", "?")
        r.setdefault("plan_gait_reason", "")
        r["agree"] = explain(r) if "verdict" in r else ""
        r["plan_gait_reason"] = str(r["plan_gait_reason"])[:120]
    rank = {o.name: k for k, o in enumerate(objects(args.quick))}
    # the table by shape group, each object's models side by side
    return sorted(rows, key=lambda r: (rank[r["object"]], models.index(r["model"]), r["seed"]))


#: the planner's models of the batch objects (``--nominal``)
MODELS = ("circle", "true")
#: the columns of map space (``plan_gait`` and the rest reach): one object, any model
MAP_COLUMNS = ("plan_gait", "plan_gait_reason", "rest_turn_deg", "rest_turn_reserve_deg",
               "rest_blocking")  # fmt: skip


def nominal_models(spec: str) -> list[str]:
    """The models of ``--nominal`` (comma-separated, each of :data:`MODELS`, in order)."""
    models = [m.strip() for m in spec.split(",") if m.strip()]
    bad = [m for m in models if m not in MODELS]
    if bad or not models:
        raise ValueError(f"--nominal: {spec!r}: expected a comma-separated list of "
                         f"{', '.join(MODELS)}")  # fmt: skip
    return list(dict.fromkeys(models))


def summary(rows: list[dict]) -> list[str]:
    """Counts of verdicts and agreements; successes per model and family, counted per run
    and per object (an object succeeds when more than half of its seeds' runs do)."""
    batch = [r for r in rows if r.get("benchmark") == "batch"]
    seeds = sorted({r.get("seed", 0) for r in batch})
    lines = [f"runs: {len(batch)} ({len(seeds)} sensor-noise seed(s) per object and model); "
             "verdicts: " + _count([r.get("verdict", "?") for r in batch])]  # fmt: skip
    agree = sum(1 for r in batch if str(r.get("agree", "")).startswith("agree"))
    dis = sum(1 for r in batch if str(r.get("agree", "")).startswith("disagree"))
    lines.append(f"executor runs vs plan_gait: {agree} agree, {dis} disagree, "
                 f"{len(batch) - agree - dis} undecided")  # fmt: skip
    models = list(dict.fromkeys(r.get("model", "") for r in batch))

    def tally(rs: list[dict], m: str, won_if=None) -> str:
        """``"objects k/N, runs a/b"`` of model ``m`` among ``rs`` (success: ``won_if``,
        default :func:`_success`)."""
        won_if = won_if or _success
        mine = [r for r in rs if r.get("model", "") == m]
        per: dict[str, list[bool]] = {}
        for r in mine:
            per.setdefault(r["object"], []).append(won_if(r))
        won = sum(1 for v in per.values() if 2 * sum(v) > len(v))
        ok = sum(1 for r in mine if won_if(r))
        return f"objects {won}/{len(per)}, runs {ok}/{len(mine)}"

    for m in models:
        lines.append(f"executor with the {MODEL_NAMES.get(m, m)} model succeeds on "
                     f"{tally(batch, m)}")  # fmt: skip
    longer = any("run_end" in r for r in batch)
    if longer:
        for m in models:
            lines.append(f"full turn (360 deg) given more time, {MODEL_NAMES.get(m, m)} "
                         f"model: {tally(batch, m, _full_turn)}")  # fmt: skip
    fams = dict.fromkeys(r["family"] for r in batch)
    for fam in fams:
        rs = [r for r in batch if r["family"] == fam]
        # map space: once per object (its first model's first seed)
        one = [r for r in rs if r.get("model", "") == models[0] and r.get("seed", 0) == seeds[0]]
        succ = "; ".join(f"{tally(rs, m)} ({m})" for m in models)
        gait = sum(1 for r in one if r.get("plan_gait") == "gait")
        rest = sum(1 for r in one if r.get("rest_turn_deg") == 360)
        turns = [x for x in map(_reserve_turn, one) if x is not None]
        reserve = ""
        if turns:
            k = sum(1 for x in turns if x >= 360)
            short = sorted(x for x in turns if x < 360)
            reserve = (f", with the executor's planning friction and threshold "
                       f"{k}/{len(turns)}"
                       + (f" (the others {', '.join(f'{x:g}' for x in short)} deg)"
                          if short else ""))  # fmt: skip
        full = ("; full turn given more time on "
                + "; ".join(f"{tally(rs, m, _full_turn)} ({m})" for m in models)
                if longer else "")  # fmt: skip
        lines.append(f"{fam}: executor succeeds on {succ}{full}; plan_gait on "
                     f"{gait}/{len(one)}, map space from rest turns {rest}/{len(one)} a full "
                     f"turn{reserve}")  # fmt: skip
    return lines


#: how the notes name the models
MODEL_NAMES = {"circle": "nominal circle", "true": "true (posed) outline"}


def _success(row: dict) -> bool:
    return row.get("verdict") in ("full turn", "turning")


def _full_turn(row: dict) -> bool:
    """The run turned the object 360 deg (at ``--duration`` or given ``--full-turn``)."""
    return row.get("verdict") == "full turn" or row.get("full_turn_s", "") != ""


def bench_nlp() -> list[dict]:
    from planner.exploration.planar.heuristics import start_grasp_candidates
    from planner.trajectory import RollingNLP
    from robots.planar_hand import PlanarHand

    hand = PlanarHand()
    t0 = time.perf_counter()
    nlp = RollingNLP(hand, knots=6)
    build = time.perf_counter() - t0
    bl, br, q, _ = start_grasp_candidates(hand, (0, 0.05), 0.05, 0.8, None, 0.15)[0]
    args = (q, np.array([0, 0.05]), 0.05, 0.025, 0.8, np.array([bl, br]), 0.0)
    cold = [nlp.solve(*args, warm=False).solve_time_s for _ in range(5)]
    warm = [nlp.solve(*args).solve_time_s for _ in range(5)]
    pert = []
    rng = np.random.default_rng(0)
    for _ in range(8):
        nlp.solve(*args)
        d = rng.uniform(-0.01, 0.01)
        p2 = nlp.solve(q, np.array([0.001, 0.05]), 0.05 * (1 + d), 0.025, 0.8,
                       np.array([bl + d, br - d]), 0.0005)  # fmt: skip
        pert.append(p2.solve_time_s)
    med = statistics.median
    return [
        {"benchmark": "nlp build", "value_ms": 1e3 * build, "target_ms": 200},
        {"benchmark": "nlp solve cold", "value_ms": 1e3 * med(cold), "target_ms": ""},
        {"benchmark": "nlp solve warm (same start)", "value_ms": 1e3 * med(warm), "target_ms": 30},
        {"benchmark": "nlp solve warm (next-phase start)", "value_ms": 1e3 * med(pert),
         "target_ms": 30},
    ]  # fmt: skip


def bench_nlp_replay(seconds: float = 12.0) -> list[dict]:
    """The phase-1 NLPs the executor actually solves: every ``RollingNLP.solve`` of a
    ``seconds`` [s] ball_with_ridge run is recorded, then replayed on a fresh NLP (a) in
    order, warm-started as the executor does, and (b) cold. Wall and CPU time and IPOPT
    iterations per solve: the synthetic rows above re-solve nearly the same problem (2-4
    iterations), the executor's problems start from a new grasp every phase."""
    from planner.exploration.planar import circle_with_ridge, explore_object
    from planner.trajectory import RollingNLP

    calls: list[tuple] = []
    solve = RollingNLP.solve

    def recording(self, *a, **kw):
        calls.append((a, kw))
        return solve(self, *a, **kw)

    RollingNLP.solve = recording
    try:
        explore_object(circle_with_ridge(angle=math.radians(170)), hand=batch_hand(),
                       duration=seconds)  # fmt: skip
    finally:
        RollingNLP.solve = solve
    rows = []
    for mode in ("warm", "cold"):
        nlp = RollingNLP(batch_hand(), knots=6)
        wall, cpu, its, ok = [], [], [], 0
        for a, kw in calls:
            c0, w0 = time.process_time(), time.perf_counter()
            plan = nlp.solve(*a, **{**kw, "warm": mode == "warm"})
            wall.append(time.perf_counter() - w0)
            cpu.append(time.process_time() - c0)
            its.append(nlp.iterations)
            ok += plan.success
        med = statistics.median
        rows.append({
            "benchmark": f"nlp solve {mode} (executor's problems, replayed)",
            "value_ms": 1e3 * med(wall), "target_ms": 30 if mode == "warm" else "",
            "object": f"{len(calls)} solves of a {seconds:g} s ball_with_ridge run",
            "reason": f"median CPU {1e3 * med(cpu):.1f} ms, median {med(its):g} IPOPT "
                      f"iterations (max {max(its)}), {ok}/{len(calls)} converged",
        })  # fmt: skip
    return rows


def ball_run(seconds: float, seed: int) -> dict:
    """The bundled ball_with_ridge scenario (its object, hand, gains) for ``seconds``
    simulated [s] with the sensor-noise ``seed``: one row (in a worker process)."""
    import yaml

    from planner.exploration.planar import explore_object
    from planner.exploration.planar.metrics import summary_metrics
    from planner.exploration.planar.plots import fig214_measures
    from planner.kinds.gait import Config

    path = Path(__file__).parents[1] / "scenarios" / "ball_with_ridge.yaml"
    cfg = Config.model_validate({"name": "ball_with_ridge", **yaml.safe_load(path.read_text())})
    ridge = math.radians(cfg.object.ridge_angle_deg)
    c0 = time.process_time()
    res = explore_object(cfg.object.profile(), hand=cfg.hand.hand(cfg.mu), mu=cfg.mu,
                         nominal=cfg.nominal.profile(), seed=seed, duration=seconds,
                         settings=cfg.settings(),
                         max_rotation=math.radians(cfg.max_rotation_deg))  # fmt: skip
    cpu = time.process_time() - c0
    m = summary_metrics(res, ridge, cfg.explore_force, cfg.mu)
    sim = float(res.log.t[-1]) if len(res.log.t) else 0.0
    return {
        "benchmark": "ball_with_ridge", "object": f"seed {seed}, <= {seconds:g} s simulated",
        "status": res.status, "reason": res.reason, "rotation_deg": round(-m["rotation_deg"], 1),
        "coverage": round(m["coverage"], 3), "ridge_error_deg": m.get("ridge_error_deg"),
        "rtf": round(m["real_time_factor"], 3), "phases": m["phases"],
        "transitions_4": m["transitions_4"], "sim_s": round(sim, 2),
        "wall_s": round(m["wall_s"], 1),
        "value_ms": round(float(np.median(res.timings["nlp_solve_ms"])), 1),
        "cpu_rtf": round(sim / cpu, 3) if cpu > 0 else "",
        "end_events": f"NLP median wall (value_ms) / CPU "
                      f"{m['nlp_solve_cpu_median_ms']:.1f} ms, {m['nlp_iterations_median']:g} "
                      f"iterations; Fig. 2.14 sign changes "
                      f"{fig214_measures(res, None)['tangential_sign_changes_2to3']}",
    }  # fmt: skip


def bench_ball(seconds: float, seeds: int, jobs: int) -> list[dict]:
    """:func:`ball_run` for seeds 0 .. ``seeds`` - 1 (the sensor noise decides where the
    ridge meets the fingers and the palm)."""
    tasks = [(seconds, seed) for seed in range(seeds)]
    return run_parallel(tasks, ball_run, jobs, wall_cap=900.0)


def main() -> None:
    p = arg_parser(__doc__.splitlines()[0])
    p.add_argument("--duration", type=float, default=10.0, help="simulated s per object")
    p.add_argument("--wall-cap", type=float, default=240.0, help="wall s per object")
    p.add_argument("--jobs", type=int, default=2, help="worker processes")
    p.add_argument("--budget", type=float, default=math.inf, help="total wall s of the batch")
    p.add_argument("--min-rotation", type=float, default=40.0, help="'turning' threshold [deg]")
    p.add_argument(
        "--full-turn",
        type=float,
        default=120.0,
        help="run every object on up to this many simulated s (0: --duration "
        "only); columns full_turn_s / run_end: did it make the full turn",
    )
    p.add_argument("--seeds", type=int, default=3,
                   help="sensor-noise seeds per batch object and model (verdicts on non-round "
                   "objects depend on them)")  # fmt: skip
    p.add_argument("--ball", type=float, default=0.0, help="ball_with_ridge seconds (0: skip)")
    p.add_argument("--ball-seeds", type=int, default=1, help="ball_with_ridge sensor seeds")
    p.add_argument("--no-nlp", action="store_true", help="skip the NLP rows")
    p.add_argument(
        "--nominal",
        default="circle,true",
        help="the planner's models, comma-separated: circle (a nominal circle of the "
        "object's area), true (the object's outline, posed); default both",
    )
    p.add_argument("--only", default="", help="comma-separated name/family substrings")
    p.add_argument("--phase-log", action="store_true", help="print every object's phases")
    p.add_argument("--left-tip", type=float, default=0.0,
                   help="a round left tip of this radius [m] instead of the flat pad (0: the "
                   "pad); the report is then bench_gait_round_left")  # fmt: skip
    p.add_argument("--gravity", type=float, default=None,
                   help="gravity towards the palm [m/s^2] (GaitSettings.gravity, default "
                   "its 9.81; 0: the hand in a horizontal plane); other than the default "
                   "the report's name ends _gG")  # fmt: skip
    args = p.parse_args()
    from planner.errors import InvalidParameter

    try:  # the settings check it (and say its default)
        args.gravity = gait_settings(1.0, args.gravity).gravity
    except InvalidParameter as exc:
        p.error(f"--{exc}")
    if args.left_tip < 0:
        p.error(f"--left-tip: {args.left_tip:g}: expected a radius >= 0 [m]")
    try:
        nominal_models(args.nominal)  # a bad --nominal stops before any work
    except ValueError as exc:
        p.error(str(exc))
    if args.seeds < 1:
        p.error(f"--seeds: {args.seeds}: expected at least 1")
    if not args.full_turn >= 0:
        p.error(f"--full-turn: {args.full_turn:g}: expected >= 0 simulated s")
    if args.quick:
        args.duration, args.full_turn = min(args.duration, 2.0), 0.0
    t0 = time.perf_counter()
    rows = [] if args.no_nlp else bench_nlp() + bench_nlp_replay()
    rows += bench_batch(args)
    if args.ball > 0:
        rows += bench_ball(args.ball, args.ball_seeds, args.jobs)
    notes = summary(rows) + [
        f"batch: {args.duration:g} s simulated per run, sensor-noise seeds 0-{args.seeds - 1} "
        f"(wall cap {args.wall_cap:g} s), "
        f"{args.jobs} worker processes, total budget {args.budget:g} s; 'turning' = ok and "
        f">= {args.min_rotation:g} deg clockwise or two phase-1 rotations >= 5 deg and "
        f">= {CYCLE_NET_DEG:g} deg net when the time ran out; success = full turn or turning"
        + (f"; every run then went on up to {args.full_turn:g} s simulated (the same "
           "deterministic run: verdict, status, reason and rotation_deg are its state at "
           f"{args.duration:g} s; coverage, phases, events, sim_s and wall_s are the whole "
           "run's): full_turn_s = when it had turned 360 deg, run_end = how it ended"
           if args.full_turn > args.duration else ""),
        f"hand: joint ranges {list(HAND_LOWER_DEG)} .. {list(HAND_UPPER_DEG)} deg (the "
        "ball_with_ridge hand), mu = 1, "
        + (f"a round {1e3 * args.left_tip:g} mm left tip (no tactile array) instead of the "
           "flat pad" if args.left_tip else "the flat left pad")
        + f", gravity {args.gravity:g} m/s^2 towards the palm"
        + (" (a horizontal hand)" if args.gravity == 0 else "")
        + "; regular polygons with sharp corners",
        "plan_gait: map space on the TRUE object (resolution 72, pure rolling, fixed "
        "contact model); rest_turn_deg / rest_blocking: the same map space searched "
        "exhaustively from the object resting unturned (every start grasp and handoff; "
        "planar/start_reach.py): how far it can turn and the constraint that stops it "
        "(rest_turn_reserve_deg: the same with the executor's planning friction, mu less "
        "its friction_margin, and grasps above its phase-1 stability threshold, "
        "epsilon >= GaitSettings.min_epsilon); "
        "the executor's models (column model): circle = a nominal circle of the object's "
        "area, refitted to the sensed contacts; true = the object's outline, posed from "
        "the sensed contacts at every phase start"
        + (f"; objects matching {args.only!r} only" if args.only else ""),
        "rtf = simulated / wall time (inflated by the machine's load), cpu_rtf = simulated / "
        "CPU time of the worker (what load does not distort)",
        "ball_with_ridge rows: the bundled scenario (its hand and gains) per sensor-noise "
        "seed; value_ms = the run's median phase-1 NLP wall time; the NLP rows 'executor's "
        "problems, replayed' re-solve the NLPs a 12 s ball run posed (warm as the executor "
        "does, and cold): the synthetic rows re-solve nearly the same problem (2-4 IPOPT "
        "iterations), the executor's start from a new grasp every phase (10-25)",
        f"total wall {time.perf_counter() - t0:.0f} s; load average at the end "
        f"{load_average()}; 2-core machine shared with other jobs",
    ]  # fmt: skip
    cols = ["benchmark", "value_ms", "target_ms", "object", "size_cm", "model", "seed",
            "plan_gait",
            "verdict",
            "status", "reason", "rotation_deg", "coverage", "phases", "phase1",
            "transitions_4", "min_epsilon", "end_events", "sim_s", "wall_s", "rtf", "cpu_rtf",
            "full_turn_s", "run_turn_deg", "run_end",
            "ridge_error_deg", "agree", "plan_gait_reason", "rest_turn_deg",
            "rest_turn_reserve_deg", "rest_blocking"]  # fmt: skip
    name = "bench_gait_round_left" if args.left_tip else "bench_gait"
    if args.gravity != gait_settings(1.0).gravity:
        name += f"_g{args.gravity:g}"
    md = write_report(name, rows, title="hapex executed grasp gait (ch. 2, §2.3.1 batch)",
                      out=args.out, notes=notes, columns=cols)  # fmt: skip
    figure = plot(read_batch(md.with_suffix(".csv")), md.with_suffix(".png"), stamp(md))
    print(f"figure: {figure}")
    for r in rows:
        if r.get("phase_log"):
            print(f"\n{r['object']} ({r.get('model', '')} model): phases (true vs sensed "
                  "rotation [deg], centre estimate error, median/max |T|/N per "
                  "contact)")  # fmt: skip
            print("\n".join(r["phase_log"]))


if __name__ == "__main__":
    main()
