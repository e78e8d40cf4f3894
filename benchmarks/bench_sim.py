"""Benchmark of the contact simulator (issue 15): hapex and MuJoCo on the same scenes.

Scenes (dt = 1 ms, the same controller law at 1 kHz for both engines; hapex runs it inside
its compiled loop and, in a second row, as a Python callable like MuJoCo's loop does):

* ``pinch hold``: a disc pinched by two round fingertips (mu = 1, 4x friction margin), 10 s:
  creep = drift of the disc centre relative to the fingertips' midpoint after the first second
  (same definition for both engines; it includes rolling and the impedance settling), and
  for hapex ``slip_m`` = the integrated slip speed at the fingertip contacts (true creep);
  a second hapex row feeds the controller exact readings, as the MuJoCo rows' loop does;
* ``palm roll``: a disc rolled one revolution on the palm by a fingertip: rolling error
  ``|dx + R dtheta| / |R dtheta|``;
* ``ridge slide (3GM)``: B2's spatial scene, the 3GM tip (r = 8 mm, 0.3 N, mu = 0.3) dragged at
  10 mm/s over a 1 mm ridge: centre path against the exact offset surface, lost-contact steps;
* ``hand hold+slide``: the flat pad holds a ball against the palm while the round fingertip
  slides on it.

MuJoCo runs the model from :func:`planner.sim.to_mjcf` at its default settings and at its
best ones (elliptic cone, impratio = 100, noslip iterations, stiff solref 0.002); its rows say
"not installed" without the ``[peers]`` extra. Timings are warm (JIT caches filled, model
built); build time is reported separately. Benchmarks measure; they never assert.

Run: ``python benchmarks/bench_sim.py [--quick] [--out DIR]``.
"""

from __future__ import annotations

import math
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # this checkout's planner
from _common import arg_parser, write_report  # noqa: E402

REPS = 3  # hapex timings: best of REPS warm runs (the machine is shared)

COLUMNS = [
    "scene",
    "engine",
    "settings",
    "sim_s",
    "build_s",
    "jit_s",
    "steps_per_s",
    "real_time_factor",
    "cpu_real_time_factor",
    "creep_m",
    "slip_m",
    "rolling_err_rel",
    "path_rms_m",
    "path_max_m",
    "lost_steps",
    "penetration_m",
    "status",
]


def _mujoco():
    try:
        import mujoco
    except ImportError:
        return None
    return mujoco


def _python(ctrl):
    """The preset as an opaque Python callable: the loop calls it from Python every step
    (what the gait's controller does), instead of running it inside the compiled loop."""
    return None if ctrl is None else (lambda t, obs: ctrl(t, obs))


def _hapex_run(build, duration, python_controller=False, reps=REPS):
    """Build, warm (first run: numba compile or cache load), then best of ``reps`` runs."""
    t0 = time.perf_counter()
    world, ctrl, info = build()
    build_s = time.perf_counter() - t0
    wrap = _python if python_controller else (lambda c: c)
    t0 = time.perf_counter()
    world.run(min(duration, 0.05), wrap(ctrl))  # fills the JIT caches
    jit_s = time.perf_counter() - t0
    wall = cpu = math.inf
    for _ in range(reps):  # the runs are deterministic: the same log every time
        world, ctrl, info = build()
        t0, c0 = time.perf_counter(), time.process_time()
        log = world.run(duration, wrap(ctrl))
        wall = min(wall, time.perf_counter() - t0)
        cpu = min(cpu, time.process_time() - c0)
    steps = len(log.t) - 1
    settings = "exact LCP (no parameters)"
    if ctrl is not None:
        settings += (
            "; Python controller, lean loop" if python_controller else "; preset in the loop"
        )
    row = {
        "engine": "hapex",
        "settings": settings,
        "sim_s": log.t[-1],
        "build_s": build_s,
        "jit_s": jit_s,
        "steps_per_s": steps / wall,
        "real_time_factor": log.t[-1] / wall,
        "cpu_real_time_factor": log.t[-1] / cpu,
        # the deepest overlap of the logged states, as MuJoCo's rows measure theirs (the log's
        # gap is measured after the next step's projection: planar/stepper.py, Limits)
        "penetration_m": float(world.logged_overlap(log).max(initial=0.0)),
        "status": log.status + (f" ({log.reason})" if log.reason else ""),
    }
    return world, info, log, row


def _mj_rollout(world, ctrl, duration, settings, bodies):
    """Run the world's MJCF in MuJoCo; returns (row, {body: (T, 3) poses}, (T, 6) q)."""
    from planner.sim import Observation
    from planner.sim.mjcf import mujoco_model

    t0 = time.perf_counter()
    mujoco, m, d = mujoco_model(world, settings)
    build_s = time.perf_counter() - t0
    nh = 6 if world.hand is not None else 0
    n = int(round(duration / world.dt))
    poses = {b: np.zeros((n + 1, 3)) for b in bodies}
    qs = np.zeros((n + 1, nh))
    start = {b: world._x[world._names[b].index].copy() for b in bodies}
    adr = {b: m.jnt_qposadr[m.joint(f"{b}_x").id] for b in bodies}

    def record(k):
        for b in bodies:
            a = adr[b]
            poses[b][k] = start[b] + d.qpos[a : a + 3]
        qs[k] = d.qpos[:nh]

    record(0)
    pen = 0.0
    t0 = time.perf_counter()
    for k in range(n):
        if ctrl is not None:
            obs = Observation(d.time, d.qpos[:nh].copy(), d.qvel[:nh].copy())
            d.ctrl[:] = np.clip(ctrl(d.time, obs), -2.0, 2.0)
        mujoco.mj_step(m, d)
        for i in range(d.ncon):
            pen = max(pen, -d.contact[i].dist)
        record(k + 1)
    wall = time.perf_counter() - t0
    row = {
        "engine": "MuJoCo " + mujoco.__version__,
        "settings": "default" if settings == "default" else "elliptic, impratio=100, noslip",
        "sim_s": n * world.dt,
        "build_s": build_s,
        "steps_per_s": n / wall,
        "real_time_factor": n * world.dt / wall,
        "penetration_m": pen,
        "status": "ok" if np.all(np.isfinite(d.qpos)) else "diverged",
    }
    return row, poses, qs


def _tips(world, q):
    hand = world.hand.hand
    out = np.zeros((len(q), 2, 2))
    for k in range(len(q)):
        tp = hand.fingertip_positions(q[k])
        out[k, 0], out[k, 1] = tp["left"], tp["right"]
    return out


def _slip(world, log, body):
    """Integrated |slip velocity| over the fingertip-``body`` contacts [m] (true creep)."""
    m = log.pair_mask("hand.left", body) | log.pair_mask("hand.right", body)
    return float(np.abs(np.where(m, log.slip_velocity, 0.0)).sum() * world.dt)


def _creep(world, disc, q, t_settle):
    k0 = int(round(t_settle / world.dt))
    tips = _tips(world, q[[k0, -1]])
    rel0 = disc[k0, :2] - tips[0].mean(axis=0)
    rel1 = disc[-1, :2] - tips[1].mean(axis=0)
    return float(np.linalg.norm(rel1 - rel0))


def bench_pinch(quick: bool) -> list[dict]:
    from planner.sim.observation import SensorSettings
    from planner.sim.planar.scenes import pinch_scene

    T = 1.5 if quick else 10.0
    world, info, log, row = _hapex_run(lambda: pinch_scene(squeeze=1.96, friction=1.0), T)
    row["creep_m"] = _creep(world, log.poses["disc"], log.q, 1.0)
    row["slip_m"] = _slip(world, log, "disc")
    rows = [row]
    # the same scene with exact readings (no encoder quantization, no gauge noise): what the
    # MuJoCo rows' loop feeds the same controller (qpos, qvel), so creep is comparable
    world, info, log, row = _hapex_run(
        lambda: pinch_scene(squeeze=1.96, friction=1.0, sensors=SensorSettings.ideal()), T
    )
    row["settings"] += "; ideal sensors (exact readings, as MuJoCo's loop)"
    row["creep_m"] = _creep(world, log.poses["disc"], log.q, 1.0)
    row["slip_m"] = _slip(world, log, "disc")
    rows.append(row)
    world, info, log, row = _hapex_run(
        lambda: pinch_scene(squeeze=1.96, friction=1.0), T, python_controller=True
    )
    row["creep_m"] = _creep(world, log.poses["disc"], log.q, 1.0)
    row["slip_m"] = _slip(world, log, "disc")
    rows.append(row)
    rows += _mj_rows(pinch_scene, dict(squeeze=1.96, friction=1.0), T, ["disc"], "pinch")
    for r in rows:
        r["scene"] = f"pinch hold {T:g} s"
    return rows


def _mj_rows(builder, kwargs, T, bodies, kind, info=None):
    if _mujoco() is None:
        return [{"engine": "MuJoCo", "settings": "-", "status": "not installed"}]
    rows = []
    for settings in ("default", "best"):
        world, ctrl, info = builder(**kwargs)
        row, poses, qs = _mj_rollout(world, ctrl, T, settings, bodies)
        if kind == "pinch":
            row["creep_m"] = _creep(world, poses["disc"], qs, 1.0)
            if poses["disc"][-1, 1] < poses["disc"][0, 1] - 0.01:
                row["status"] = "dropped"
        elif kind == "roll":
            p = poses["disc"]
            R = info["radius"]
            dx, dth = p[-1, 0] - p[0, 0], p[-1, 2] - p[0, 2]
            row["rolling_err_rel"] = abs(dx + R * dth) / abs(R * dth)
        elif kind == "slide":
            row["creep_m"] = float(np.linalg.norm(poses["ball"][-1, :2] - poses["ball"][0, :2]))
        rows.append(row)
    return rows


def bench_roll(quick: bool) -> list[dict]:
    from planner.sim.planar.scenes import palm_roll_scene

    _, _, info = palm_roll_scene()
    T = 0.5 if quick else info["revolution_time"]
    world, info, log, row = _hapex_run(palm_roll_scene, T)
    p = log.poses["disc"]
    R = info["radius"]
    dx, dth = p[-1, 0] - p[0, 0], p[-1, 2] - p[0, 2]
    row["rolling_err_rel"] = abs(dx + R * dth) / abs(R * dth)
    rows = [row]
    _, _, log2, row2 = _hapex_run(palm_roll_scene, T, python_controller=True)
    p2 = log2.poses["disc"]
    dx2, dth2 = p2[-1, 0] - p2[0, 0], p2[-1, 2] - p2[0, 2]
    row2["rolling_err_rel"] = abs(dx2 + R * dth2) / abs(R * dth2)
    rows += [row2, *_mj_rows(palm_roll_scene, {}, T, ["disc"], "roll")]
    for r in rows:
        r["scene"] = f"palm roll {dth / (2 * math.pi):.2f} rev"
    return rows


def bench_hold_slide(quick: bool) -> list[dict]:
    from planner.sim.planar.scenes import palm_hold_slide_scene

    T = 0.3 if quick else 1.5  # the straight set-point path leaves the ball after ~1.6 s
    world, info, log, row = _hapex_run(palm_hold_slide_scene, T)
    row["creep_m"] = float(np.linalg.norm(log.poses["ball"][-1, :2] - log.poses["ball"][0, :2]))
    row["slip_m"] = _slip(world, log, "ball")  # includes the intended slide of the right tip
    rows = [row]
    world, _, log, row = _hapex_run(palm_hold_slide_scene, T, python_controller=True)
    row["creep_m"] = float(np.linalg.norm(log.poses["ball"][-1, :2] - log.poses["ball"][0, :2]))
    row["slip_m"] = _slip(world, log, "ball")
    rows += [row, *_mj_rows(palm_hold_slide_scene, {}, T, ["ball"], "slide")]
    for r in rows:
        r["scene"] = f"hand hold+slide {T:g} s"
    return rows


def _hapex_slide(build, kw: dict, label: str):
    """Build and run a 3GM slide scene (warm); the scene and its hapex row."""
    from planner.sim.spatial.scenes import centre_path_error

    t0 = time.perf_counter()
    sc = build(**kw)
    build_s = time.perf_counter() - t0
    t0, c0 = time.perf_counter(), time.process_time()
    log = sc.world.run(sc.duration, sc.controller)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    pe = centre_path_error(sc, log)
    gaps = log.gap[np.isfinite(log.gap)]
    row = {
        "engine": "hapex",
        # the wall clock of a shared machine understates the speed: the process' CPU time too
        "settings": f"{label}; {log.t[-1] / cpu:.1f}x RT in CPU time",
        "sim_s": log.t[-1],
        "build_s": build_s,
        "steps_per_s": (len(log.t) - 1) / wall,
        "real_time_factor": log.t[-1] / wall,
        "path_rms_m": pe.rms,
        "path_max_m": pe.max,
        "lost_steps": pe.lost_steps,
        # the deepest of the logged gaps and of the centre below its exact offset surface (a
        # second contact the one-foot model misses shows only in the latter)
        "penetration_m": max(
            0.0,
            -float(gaps.min()) if gaps.size else 0.0,
            -float(np.min(pe.errors, initial=0.0)),
        ),
        "status": log.status,
    }
    return sc, row


def bench_ravine(quick: bool) -> list[dict]:
    """The 8 mm 3GM tip sliding across a 2 x 2 mm ravine it cannot enter (feature_plate's):
    one contact per sphere (the default) against every contact (``all_contacts``)."""
    from planner.sim.spatial.scenes import ridge_slide_scene

    kw = {"kind": "ravine", "ridge_height": 2e-3, "ridge_width": 2e-3}
    kw["travel"] = 0.012 if quick else 0.03
    rows = []
    for every, label in ((False, "one contact per sphere"), (True, "all_contacts")):
        rows.append(_hapex_slide(ridge_slide_scene, {**kw, "all_contacts": every}, label)[1])
    for r in rows:
        r["scene"] = "ravine slide (3GM, tip wider than the ravine)"
    return rows


def bench_ridge(quick: bool) -> list[dict]:
    """The 3GM ridge slide: hapex (warm: the JIT caches are filled by a short first run) and
    MuJoCo on the same scene via ``to_mjcf`` (:mod:`planner.sim.spatial.mujoco_peer`)."""
    try:
        from planner.sim.spatial.scenes import ridge_slide_scene
    except ImportError as exc:
        return [{"scene": "ridge slide (3GM)", "engine": "hapex", "status": f"n/a: {exc}"}]
    kw = {"travel": 0.006} if quick else {}
    warm = ridge_slide_scene(travel=0.004)
    warm.world.run(0.02, warm.controller)  # numba/ctypes caches
    sc, row = _hapex_slide(ridge_slide_scene, kw, "exact (no parameters)")
    rows = [row]
    if _mujoco() is None:
        rows.append({"engine": "MuJoCo", "settings": "-", "status": "not installed"})
    else:
        from planner.sim.spatial.mujoco_peer import mujoco_ridge_rollout

        for settings in ("default", "best"):
            r = mujoco_ridge_rollout(ridge_slide_scene(**kw), settings)
            rows.append(
                {
                    "engine": "MuJoCo " + _mujoco().__version__,
                    "settings": r["settings"],
                    "sim_s": sc.duration,
                    "build_s": r["build_s"],
                    "steps_per_s": r["steps_per_s"],
                    "real_time_factor": r["steps_per_s"] * sc.world.dt,
                    "path_rms_m": r["rms"],
                    "path_max_m": r["max"],
                    "lost_steps": r["lost_steps"],
                    "penetration_m": r["penetration_max"],
                    "status": r["status"],
                }
            )
    for r in rows:
        r["scene"] = "ridge slide (3GM)"
    return rows


def _cpu_us(f, n: int = 300) -> float:
    """Best-of-3 process (CPU) time of one call of ``f`` [us] (CPU time: the machine is shared)."""
    best = math.inf
    for _ in range(3):
        c0 = time.process_time()
        for _ in range(n):
            f()
        best = min(best, (time.process_time() - c0) / n)
    return best * 1e6


def _loop_us(build, T: float, wrap, loop: str) -> float:
    """Best-of-3 CPU time per step of ``world.run`` [us]."""
    best = math.inf
    for _ in range(3):
        world, ctrl, _ = build()
        c0 = time.process_time()
        log = world.run(T, wrap(ctrl), loop=loop)
        best = min(best, (time.process_time() - c0) / (len(log.t) - 1))
    return best * 1e6


def bench_breakdown(quick: bool) -> list[dict]:
    """Per-step CPU time of each part of a hand-scene step and of whole runs, warm [us]."""
    from planner.sim.planar import scenes
    from planner.sim.planar.stepper import step

    builders = {
        "pinch hold": lambda: scenes.pinch_scene(squeeze=1.96, friction=1.0),
        "palm roll": scenes.palm_roll_scene,
        "hand hold+slide": scenes.palm_hold_slide_scene,
    }
    rows = []
    for name, build in builders.items():
        world, ctrl, _ = build()
        for _ in range(50):
            world.step(ctrl(world.time, world.observe()))
        tau = ctrl(world.time, world.observe())
        saved = [a.copy() for a in (world._x, world._v, world.q, world.qd)]

        def reset(w=world, s=saved):
            w._x[:], w._v[:], w.q[:], w.qd[:] = s

        def compiled(w=world, r=reset, u=tau):
            r()
            w.step(u)

        def python(w=world, r=reset, u=tau):
            r()
            step(w, u)

        base = _cpu_us(reset)
        obs = world.observe()
        T = 0.3 if quick else 1.0
        world.run(0.02, _python(ctrl))  # JIT caches of the loops
        parts = {
            "world.step (compiled step, one Python call)": _cpu_us(compiled) - base,
            "world.step (Python reference step)": _cpu_us(python, 50) - base,
            "world.observe": _cpu_us(world.observe),
            "preset controller, called from Python": _cpu_us(lambda c=ctrl, o=obs: c(0.1, o)),
            "run: preset in the compiled loop": _loop_us(build, T, lambda c: c, "auto"),
            "run: Python controller, lean loop": _loop_us(build, T, _python, "auto"),
            "run: Python controller, reference loop": _loop_us(build, T, _python, "python"),
        }
        rows += [{"scene": name, "part": k, "cpu_us_per_step": v} for k, v in parts.items()]
    return rows


def main() -> None:
    args = arg_parser(__doc__.splitlines()[0]).parse_args()
    rows = []
    for bench in (bench_pinch, bench_roll, bench_ridge, bench_ravine, bench_hold_slide):
        rows += bench(args.quick)
    write_report(
        "sim_breakdown",
        bench_breakdown(args.quick),
        title="Planar hand scenes: CPU time per step by part (warm, in contact) [us]",
        out=args.out,
        notes=[
            "CPU (process) time, best of 3 (the machine is shared); 'run:' rows are world.run "
            "per step with the controller at 1 kHz: the preset inside the compiled loop, the "
            "same law as an opaque Python callable (the gait's case) in the lean loop and in "
            "the reference loop (loop='python'); 20x real time at dt = 1 ms is 50 us/step",
        ],
    )
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    write_report(
        "sim",
        rows,
        title="Contact simulator: hapex vs MuJoCo on the same scenes (dt = 1 ms)",
        out=args.out,
        columns=COLUMNS,
        notes=[
            "targets: >= 20x real time (planar hand), >= 10x (3GM), creep <= 1 nm / 10 s, "
            "penetration <= 1 um, path error <= 0.1 um RMS / 1 um max, 0 lost steps, "
            "rolling error <= 1e-6",
            "hapex: best of 3 warm runs (build_s: scene construction; jit_s: the first short "
            "run, numba compile or cache load); 'preset in the loop': the scene's controller "
            "runs inside the compiled loop; 'Python controller, lean loop': the same law "
            "called from Python at 1 kHz (as MuJoCo's rows, whose loop calls it from Python); "
            "cpu_real_time_factor uses process time (less sensitive to the shared machine)",
            "pinch creep_m (disc centre relative to the fingertips' midpoint, after 1 s): with "
            "the default sensors the controller acts on quantized encoders and the disc rolls "
            "(does not slip: slip_m) by a few um back and forth; with ideal sensors, as MuJoCo's "
            "rows are fed, the drift dies out to round-off",
            f"load average at the end: {load:.2f} (shared machine)",
        ],
    )


if __name__ == "__main__":
    main()
