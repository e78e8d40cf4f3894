"""Benchmark of one planar grasp control step (kinematics + Jacobians + QP), fast vs naive.

* fast: :class:`planner.control.grasp_step.GraspStep` — CasADi-generated C (FK, contact
  Jacobians, mass matrix, gravity, the control laws, the QP data) and DAQP's C workspace
  API, one ctypes call on preallocated arrays;
* naive: :func:`planner.control.grasp_reference.reference_step` — the same step with numpy,
  Pinocchio and ``qpsolvers.solve_qp`` (DAQP backend), in the same run.

Also: agreement of the two (max |tau| difference) and finite-difference checks of the
contact Jacobians (max error). Targets (issue 11): fast <= 15 us median, >= 4x the naive.

The last row is the WHOLE gait controller call (``GaitController(t, obs)``: sensing from the
encoders, strain gauges and 8x8 tactile image, phase references, internal-force PI, rolling
PD, the compiled step with its QP, the trace and the event checks) replayed on the
observations recorded from ``scenarios/ball_with_ridge.yaml`` (tests/data, all three phase
kinds), against :class:`naive_gait.NaiveGaitController` (the same call in numpy, Pinocchio
and qpsolvers) on the same recording in the same run. Target: <= 30 us median (the budget
of the >= 20x real-time gait), >= 4x the naive. The segment references are replayed from
the recording (dictionary look-ups): the planner's own reference callables are not timed.

Run: ``python benchmarks/bench_control.py [--quick] [--out DIR]``.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).parent.parent / "tests"))
sys.path.insert(0, str(Path(__file__).parent.parent))
from _common import arg_parser, time_call, write_report  # noqa: E402


def fd_error(hand) -> float:
    import casadi as cs

    from planner.control.grasp_kinematics import finger_terms_sx

    q, qd, off = cs.SX.sym("q", 6), cs.SX.sym("qd", 6), cs.SX.sym("o", 4)
    T = finger_terms_sx(hand.model, q, qd, off, cs.DM([0, -9.81]))
    F = cs.Function(
        "f", [q, off], [T["left"]["p"], T["left"]["J"], T["right"]["p"], T["right"]["J"]]
    )
    rng = np.random.default_rng(0)
    worst = 0.0
    for _ in range(20):
        qq, oo = rng.uniform(-1, 1, 6), rng.uniform(-0.02, 0.02, 4)
        out = [np.asarray(v) for v in F(qq, oo)]
        for k in (0, 2):
            for j in range(6):
                e = np.zeros(6)
                e[j] = 1e-6
                d = (np.asarray(F(qq + e, oo)[k]) - np.asarray(F(qq - e, oo)[k])).ravel() / 2e-6
                worst = max(worst, float(np.max(np.abs(d - out[k + 1][:, j]))))
    return worst


def gait_call_row(repeat: int) -> dict:
    """Per-call median of the fast and naive gait controllers on the recorded run."""
    import gait_replay
    from naive_gait import NaiveGaitController

    data = gait_replay.load()
    for w in data["windows"]:  # build the observations once, outside the timed calls
        w["sense"] = w["sense"] and (gait_replay.observation(w["sense"][0]), w["sense"][1])
        for c in w["calls"]:
            c["obs_object"] = gait_replay.observation(c["obs"])
    fast = gait_replay.make_controller(data)
    naive = gait_replay.make_controller(data, NaiveGaitController)
    diff = 0.0
    for ctrl in (fast, naive):
        for _ in range(repeat):
            ctrl.step_times.clear()
            taus = list(_replay(ctrl, data))
        if ctrl is fast:
            ref = taus
        else:
            diff = max(float(np.max(np.abs(a - b))) for a, b in zip(ref, taus, strict=True))
    t_fast, t_naive = np.median(fast.step_times), np.median(naive.step_times)
    return {
        "step": f"gait controller call ({len(fast.step_times)} recorded calls)",
        "fast_median_us": 1e6 * t_fast, "naive_median_us": 1e6 * t_naive,
        "speedup": t_naive / t_fast, "target_us": 30.0, "max_tau_diff_Nm": diff,
        "backend": fast.step.backend,
    }  # fmt: skip


def _replay(ctrl, data):
    """``gait_replay.replay`` on pre-built observations; yields the torques."""
    import gait_replay

    for w in data["windows"]:
        ctrl.sensing.est.u = w["pre"]["u"]
        ctrl._last_tau = w["pre"]["last_tau"].copy()
        if w["sense"]:
            ctrl.sensing.update(*w["sense"])
        ctrl.start(gait_replay.replay_segment(w), w["t0"])
        for c in w["calls"]:
            yield np.array(ctrl(c["t"], c["obs_object"]))


def main() -> None:
    args = arg_parser(__doc__.splitlines()[0]).parse_args()
    from test_control_grasp import HAND, _grasp_inputs

    from planner.control.grasp_reference import reference_step
    from planner.control.grasp_step import GraspStep

    step = GraspStep(HAND)
    data = HAND.model.createData()
    rows = []
    for mode, name in (((1, 0, 0), "phase 1 (grasp)"), ((0, 0, 1), "phase 2 (hold + explore)")):
        q, qd, geo, ref, par = _grasp_inputs(mode)
        step.q[:], step.qd[:], step.geo[:], step.ref[:], step.par[:] = q, qd, geo, ref, par
        step()
        diff = float(np.max(np.abs(step.tau - reference_step(HAND.model, data, q, qd, geo, ref,
                                                               par)["tau"])))  # fmt: skip
        t_fast = time_call(step, repeat=9 if not args.quick else 3)
        inputs = (HAND.model, data, q, qd, geo, ref, par)
        t_naive = time_call(lambda a=inputs: reference_step(*a), repeat=9 if not args.quick else 3)
        rows.append({
            "step": name, "fast_median_us": 1e6 * t_fast["median_s"],
            "naive_median_us": 1e6 * t_naive["median_s"],
            "speedup": t_naive["median_s"] / t_fast["median_s"], "target_us": 15.0,
            "max_tau_diff_Nm": diff, "backend": step.backend,
        })  # fmt: skip
    rows.append(gait_call_row(repeat=5 if not args.quick else 1))
    notes = [
        f"finite-difference check of the contact Jacobians: max error {fd_error(HAND):.2e} m/rad",
        f"load average at the end: {os.getloadavg()}; the machine (2 cores) was shared with "
        "other engineers' jobs, so absolute times are pessimistic",
        "fast = generated C + DAQP workspace updated in place (warm active set); naive = numpy "
        "+ Pinocchio + qpsolvers(daqp), same inputs, same run",
    ]
    write_report("bench_control", rows, title="hapex planar grasp control step", out=args.out,
                 notes=notes)  # fmt: skip


if __name__ == "__main__":
    main()
