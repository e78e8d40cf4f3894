"""Benchmark of the normal-force variants of the hybrid law and of the explorer's servo step.

Run: ``python benchmarks/bench_explore_control.py [--quick] [--out DIR]``. Writes
``bench_explore_control_step``, ``bench_explore_control_saturation`` and
``bench_explore_control_closed_loop`` (CSV + Markdown in ``benchmarks/results/``).

1. **Step time** (warm, per call, same inputs for every implementation): the compiled law
   (:mod:`planner.control.hybrid_kernel`) of each variant - ``open_loop`` (eq. 4.12),
   ``closed_loop`` (PI on the sensed normal force), ``qp`` (torque limits by a QP through
   :mod:`planner.optim`; unsaturated and saturated inputs) - against the plain numpy
   implementation of the same law in the same run (:mod:`planner.control.hybrid_reference`;
   the QP is the same object in both). And the explorer's whole servo step
   (:class:`~planner.exploration.surface.runtime.ExplorerController`: OWTS mean, law,
   estimates, recorder) compiled vs through ``HybridController`` and numpy, replaying the
   observations of a simulated search. Target of the control step: >= 4x numpy.
2. **Saturation** (step level): inputs where the open-loop law is torque limited (f_des beyond
   what the motors give at that pose, plus a tangential tracking error): normal force and
   tangential force delivered by the uniform scaling of the open-loop law and by the QP.
3. **Closed loop**: :func:`explore_surface` on the bundled ``ridge_plate`` and ``bug_to_goal``
   plates with each variant: normal-force RMS error (all, and below 50 Hz), boundary
   deviation, type accuracy, torque-saturated steps, real-time factor.
"""

from __future__ import annotations

import math
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _common import ROOT, arg_parser, write_report  # noqa: E402

from planner.control import hybrid_kernel as hk  # noqa: E402
from planner.control.hybrid_frames import tcs_rotation  # noqa: E402
from planner.control.hybrid_law import (  # noqa: E402
    HybridSettings,
    force_parameters,
    kernel_parameters,
)
from planner.control.hybrid_reference import (  # noqa: E402
    reference_closed_loop_step,
    reference_step,
)
from planner.control.hybrid_variants import TorqueLimitQP  # noqa: E402
from robots.sensors import OWTS  # noqa: E402
from robots.three_gm import ThreeGM  # noqa: E402

R = 0.008
GM = ThreeGM()
OW = OWTS(radius=R)


def _load() -> str:
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


def _timed(fn, count: int) -> np.ndarray:
    ts = np.empty(count)
    for i in range(count):
        t0 = time.perf_counter()
        fn(i)
        ts[i] = time.perf_counter() - t0
    return ts


def _inputs(n: int, seed: int = 0) -> dict:
    """Random servo inputs about the workspace centre, all in contact."""
    rng = np.random.default_rng(seed)
    th = GM.center_theta
    normals = np.column_stack([0.3 * rng.standard_normal((n, 2)), np.ones(n)])
    return {
        "theta": th + 0.05 * rng.standard_normal((n, 3)),
        "thd": 0.3 * rng.standard_normal((n, 3)),
        "volts": OW.voltages_from_contact(normals),
        "force": np.array([0.0, 0.0, -0.3]) + 0.05 * rng.standard_normal((n, 3)),
    }


def _state() -> np.ndarray:
    th = GM.center_theta
    s = np.zeros(12)
    s[:3] = tcs_rotation(GM.state(th).gamma1, th[2])[:, 2]
    s[3:6] = GM.forward_kinematics(th) + R * s[:3]
    return s


def _row(name: str, ts: np.ndarray, ref: float | None, saturated: float = 0.0) -> dict:
    med = float(np.median(ts))
    return {
        "implementation": name,
        "calls": len(ts),
        "median_us": med * 1e6,
        "p10_us": float(np.percentile(ts, 10)) * 1e6,
        "p90_us": float(np.percentile(ts, 90)) * 1e6,
        "saturated_share": saturated,
        "speedup_vs_numpy": (ref / med) if ref else math.nan,
    }


def _variant_rows(control: str, fd: float, n: int, m: int) -> list[dict]:
    """Compiled vs numpy step of one variant (``fd``: desired normal force [N])."""
    s = HybridSettings(control=control, normal_force=fd, max_error=0.003)
    par, fpar = kernel_parameters(GM, s, OW), force_parameters(s)
    x = _inputs(n)
    target = np.array([0.03, 0.0, 0.0])
    st_k, st_r = _state(), _state()
    fs_k, fs_r = np.zeros(hk.NFSTATE), np.zeros(hk.NFSTATE)
    out = np.zeros(hk.NOUT)
    qp = TorqueLimitQP(GM.torque_limits, s.qp_weights) if control == "qp" else None
    th, thd, v, f = x["theta"], x["thd"], x["volts"], x["force"]
    sat = np.zeros(n, bool)

    def compiled(i):
        if control == "closed_loop":
            hk.hybrid_step_closed_loop(
                th[i], thd[i], v[i], f[i], st_k, fs_k, target, par, fpar, out
            )
        else:
            hk.hybrid_step(th[i], thd[i], v[i], st_k, target, par, out)
            if qp is not None:
                qp.apply(out, st_k[:3])
        sat[i] = out[13] != 0.0

    outs = []  # the kernel's outputs of the first m inputs: the numpy path's QP reads them

    def numpy_law(i):
        if control == "closed_loop":
            reference_closed_loop_step(
                GM, OW, th[i], thd[i], v[i], f[i], st_r, fs_r, target, par, fpar, False
            )
        else:
            reference_step(GM, OW, th[i], thd[i], v[i], st_r, target, par)
            if qp is not None and outs[i][13]:
                qp.solve(outs[i], st_r[:3])

    compiled(0)  # JIT / cache load
    t_k = _timed(compiled, n)
    if qp is not None:
        st_k[:] = _state()
        for i in range(m):
            hk.hybrid_step(th[i], thd[i], v[i], st_k, target, par, out)
            outs.append(out.copy())
    t_n = _timed(numpy_law, m)
    ref = float(np.median(t_n))
    label = f"{control} (f_des {fd:g} N)"
    return [
        _row(f"{label}: compiled", t_k, ref, float(sat.mean())),
        _row(f"{label}: numpy", t_n, None, float(sat[:m].mean())),
    ]


def _explorer_rows(steps: int) -> list[dict]:
    """The explorer's servo step, compiled vs reference, replaying a simulated search."""
    from planner.exploration.surface.explorer import build_world
    from planner.exploration.surface.placement import region_box
    from planner.exploration.surface.result import ExplorationSettings
    from planner.exploration.surface.runtime import ExplorerController
    from planner.sim.spatial.plate import Plate

    cfg = ExplorationSettings()
    world, gm, T = build_world(Plate(()), cfg, region_box(((-0.02, 0.02), (-0.02, 0.02))), 0, 0)
    hs = HybridSettings(kp=cfg.kp, kv=cfg.kv)

    def slide():
        while True:
            yield 0.02, 0.005

    rec_ex = ExplorerController(gm, hs, T, steps + 2)
    rec_ex.program = slide()
    rec_ex.warm_up()
    observations = []

    def recording(t, obs):
        observations.append(obs)
        return rec_ex(t, obs)

    world.run(steps * 1e-3, controller=recording)
    rows, ref = [], None
    for kernel in (False, True):
        ex = ExplorerController(gm, hs, T, len(observations) + 2, kernel=kernel)
        ex.program = slide()
        ex.warm_up()
        ts = _timed(lambda i, ex=ex: ex(i * 1e-3, observations[i]), len(observations))
        name = "explorer step: " + ("compiled" if kernel else "HybridController + numpy")
        rows.append(_row(name, ts, ref))
        ref = float(np.median(ts))
    return rows[::-1]


def step_rows(quick: bool) -> list[dict]:
    n, m = (2000, 300) if quick else (20000, 2000)
    rows = []
    for control, fd in (("open_loop", 0.3), ("closed_loop", 0.3), ("qp", 0.3), ("qp", 16.0)):
        rows += _variant_rows(control, fd, n, m)
    rows += _explorer_rows(1000 if quick else 5000)
    return rows


def saturation_rows(quick: bool) -> list[dict]:
    """Open-loop scaling vs QP on torque-limited steps."""
    n = 200 if quick else 2000
    rows = []
    for fd in (12.0, 16.0, 24.0):
        s = HybridSettings(normal_force=fd, max_error=0.003)
        par = kernel_parameters(GM, s, OW)
        qp = TorqueLimitQP(GM.torque_limits, s.qp_weights)
        x = _inputs(n, seed=1)
        rng = np.random.default_rng(2)
        fn_open, fn_qp, ft_open, ft_qp, ft_law, viol = [], [], [], [], [], 0.0
        out = np.zeros(hk.NOUT)
        for i in range(n):
            st = _state()
            hk.hybrid_step(x["theta"][i], x["thd"][i], x["volts"][i], st, np.zeros(3), par, out)
            st[3:6] += 0.003 * (rng.uniform(-1, 1) * out[hk.O_XS : hk.O_XS + 3])
            hk.hybrid_step(x["theta"][i], x["thd"][i], x["volts"][i], st, np.zeros(3), par, out)
            if not out[13]:
                continue
            ft, fn = qp.split(out, st[:3])
            scale = out[18] / fn
            tau = qp.solve(out, st[:3])
            if tau is None:
                continue
            viol = max(viol, float(np.max(np.abs(tau) - GM.torque_limits)))
            fn_open.append(out[18])
            fn_qp.append(qp.last[1])
            ft_law.append(float(np.linalg.norm(ft)))
            ft_open.append(scale * ft_law[-1])
            ft_qp.append(qp.last[0] * ft_law[-1])
        k = len(fn_qp)
        rows.append(
            {
                "f_des_N": fd,
                "saturated_steps": k,
                "open_loop_fn_mean_N": float(np.mean(fn_open)) if k else math.nan,
                "qp_fn_mean_N": float(np.mean(fn_qp)) if k else math.nan,
                "law_ft_mean_N": float(np.mean(ft_law)) if k else math.nan,
                "open_loop_ft_mean_N": float(np.mean(ft_open)) if k else math.nan,
                "qp_ft_mean_N": float(np.mean(ft_qp)) if k else math.nan,
                "qp_max_limit_violation_Nm": viol,
            }
        )
    return rows


def _scenario(name: str):
    import yaml

    from planner.kinds.explore import Config

    return Config(**yaml.safe_load((ROOT / "scenarios" / f"{name}.yaml").read_text()))


def closed_rows(quick: bool) -> list[dict]:
    from planner.exploration.surface import explore_surface
    from planner.exploration.surface.metrics import exploration_metrics

    rows = []
    for name in ("ridge_plate",) if quick else ("ridge_plate", "bug_to_goal"):
        c = _scenario(name)
        plate = c.plate.build()
        for control in ("open_loop", "closed_loop", "qp"):
            res = explore_surface(
                plate,
                strategy=c.strategy,
                region=c.region,
                tip_radius=c.tip_radius,
                normal_force=c.normal_force,
                speed=c.speed,
                seed=c.seed,
                duration=4.0 if quick else c.duration,
                tilt=math.radians(c.plate.tilt_deg),
                goal=c.goal,
                trace_speed=c.trace_speed,
                friction=c.friction,
                control=control,
            )
            m = exploration_metrics(res, plate, np.asarray(c.region), c.tip_radius, c.normal_force)
            fn = res.log.normal_force.sum(axis=1)[1 : len(res.phase) + 1]
            on = (fn > 0) & (res.phase != 0)
            e = fn[on] - c.normal_force
            low = np.convolve(e, np.ones(20) / 20, mode="same")  # 20 ms mean: below ~50 Hz
            rows.append(
                {
                    "scenario": name,
                    "control": control,
                    "status": res.status,
                    "fn_rms_error_N": m["normal_force_rms_error_N"],
                    "fn_rms_error_below_50Hz_N": float(np.sqrt(np.mean(low**2))),
                    "fn_mean_error_N": float(np.mean(e)),
                    "boundary_dev_mean_mm": m["boundary_deviation_mean_mm"],
                    "type_accuracy": m["type_accuracy"],
                    "closure": m["closure"],
                    "saturation_events": sum(e.kind == "torque_saturated" for e in res.events),
                    "sim_s": res.sim_time,
                    "real_time_factor": res.real_time_factor,
                }
            )
            print(rows[-1], flush=True)
    return rows


def main() -> None:
    p = arg_parser(__doc__.splitlines()[0])
    args = p.parse_args()
    notes = [f"load average at start: {_load()} (2 cores shared with other engineers)"]
    rows = step_rows(args.quick)
    write_report(
        "bench_explore_control_step",
        rows,
        title="Normal-force variants and explorer servo step (warm, per call)",
        out=args.out,
        notes=[
            *notes,
            "same inputs for compiled and numpy; numpy = planner.control.hybrid_reference",
            "qp rows: the same TorqueLimitQP (DAQP via planner.optim) after either law; "
            "it solves only on saturated steps",
            "explorer step: ExplorerController with a constant program, replaying recorded "
            "observations; numpy = kernel=False (HybridController + numpy estimates)",
            "target (issue 12): control step >= 4x faster than numpy",
        ],
    )
    write_report(
        "bench_explore_control_saturation",
        saturation_rows(args.quick),
        title="Torque-limited steps: uniform scaling (open loop) vs QP",
        out=args.out,
        notes=[*notes, "fn: normal force commanded [N]; ft: tangential force [N]"],
    )
    write_report(
        "bench_explore_control_closed_loop",
        closed_rows(args.quick),
        title="explore_surface with each normal-force variant",
        out=args.out,
        notes=[
            *notes,
            f"load average at the end: {_load()}",
            "fn error: true contact normal force (simulator) minus f_des, in contact, "
            "after the approach; below 50 Hz: 20 ms moving mean",
            "saturation_events: torque_saturated onsets",
        ],
    )


if __name__ == "__main__":
    main()
