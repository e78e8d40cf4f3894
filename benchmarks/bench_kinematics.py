"""Kinematics and sensor-model speed: FK + Jacobian of both robots, OWTS, 8x8 array image.

Run: ``python benchmarks/bench_kinematics.py [--quick] [--out DIR]``.

Cases (issue #4 targets in the table):

* 3GM FK + Jacobian per call: closed form (numpy, eqs. C.4-C.9), Pinocchio (tree kinematics
  at the closed configuration + elimination of the passive joints through the loop-closure
  Jacobian), CasADi Function (SX virtual machine) and code-generated CasADi, both called
  through ``Function.buffer()``.
* Planar hand FK + Jacobian of both fingertips per call: closed form, Pinocchio, CasADi walked
  from the ``pin.Model`` (virtual machine and code-generated, through ``buffer()``).
* OWTS voltages -> contact point and normal, vectorized over N samples: samples per second
  (target >= 1 M/s).
* 8x8 tactile array image of a sphere contact: a single call (the issue's target, <= 20 µs
  per call) and batched (amortized per contact; no target of its own).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _common import arg_parser, time_call, write_report  # noqa: E402

_KEEP: list = []  # the buffers and arrays must outlive their trigger (else: use after free)


def _buffer_call(f, arg: np.ndarray):
    """A zero-allocation caller of CasADi Function ``f`` via ``Function.buffer()``.

    Returns the trigger and the output arrays (flat, column-major); the buffer object and the
    argument array are kept alive in ``_KEEP``.
    """
    buf, trigger = f.buffer()
    a = np.ascontiguousarray(arg, dtype=float)
    buf.set_arg(0, memoryview(a))
    outs = [np.zeros(f.nnz_out(i)) for i in range(f.n_out())]
    for i, o in enumerate(outs):
        buf.set_res(i, memoryview(o))
    _KEEP.append((f, buf, a, outs))
    return trigger, outs


def _row(case, method, t, target="", per=1, unit="µs/call"):
    us = t["median_s"] * 1e6 / per
    return {
        "case": case,
        "method": method,
        "median": us,
        "best": t["best_s"] * 1e6 / per,
        "unit": unit,
        "target": target,
    }


def bench_three_gm(rows, compile_ok: bool) -> None:
    import pinocchio as pin

    from robots import casadi_kinematics as ck
    from robots.three_gm import ThreeGM
    from robots.three_gm.casadi_fk import casadi_kinematics
    from robots.three_gm.model import ACTUATED, PASSIVE, configuration

    gm = ThreeGM()
    th = gm.center_theta
    # numpy closed form (with the boundary checks of the public API)
    rows.append(
        _row(
            "3GM FK+J",
            "closed form (ThreeGM.forward_kinematics_and_jacobian)",
            time_call(lambda: gm.forward_kinematics_and_jacobian(th)),
        )
    )
    m = gm.model
    d = m.createData()
    q = configuration(th, *gm.passive_angles(th))
    ids = [m.getFrameId(n) for n in ("endpoint", "closure_a", "closure_b")]
    act, pas = list(ACTUATED), list(PASSIVE)

    def pin_call():
        pin.computeJointJacobians(m, d, q)
        pin.updateFramePlacements(m, d)
        Je = pin.getFrameJacobian(m, d, ids[0], pin.LOCAL_WORLD_ALIGNED)[:3]
        Jc = (
            pin.getFrameJacobian(m, d, ids[1], pin.LOCAL_WORLD_ALIGNED)[:3]
            - pin.getFrameJacobian(m, d, ids[2], pin.LOCAL_WORLD_ALIGNED)[:3]
        )
        dqp = -np.linalg.lstsq(Jc[:, pas], Jc[:, act], rcond=None)[0]
        return d.oMf[ids[0]].translation, Je[:, act] + Je[:, pas] @ dqp

    rows.append(_row("3GM FK+J", "Pinocchio (tree + closure elimination)", time_call(pin_call)))
    f = casadi_kinematics(gm.params)
    trig, _ = _buffer_call(f, th)
    rows.append(_row("3GM FK+J", "CasADi SX Function via buffer()", time_call(trig)))
    if compile_ok:
        trig, outs = _buffer_call(ck.compile(f), th)
        trig()
        assert np.allclose(outs[0], gm.forward_kinematics(th), atol=1e-14)
        rows.append(
            _row(
                "3GM FK+J",
                "CasADi code-generated (gcc -O2) via buffer()",
                time_call(trig),
                target="~0.12 µs (issue)",
            )
        )


def bench_hand(rows, compile_ok: bool) -> None:
    import pinocchio as pin

    from robots import casadi_kinematics as ck
    from robots.planar_hand import PlanarHand

    hand = PlanarHand()
    q = hand.neutral() + 0.05
    rows.append(
        _row(
            "hand FK+J (2 tips)",
            "closed form (fingertip_positions + 2 jacobian)",
            time_call(
                lambda: (
                    hand.fingertip_positions(q),
                    hand.jacobian(q, "left"),
                    hand.jacobian(q, "right"),
                )
            ),
        )
    )
    m = hand.model
    d = m.createData()
    ids = [m.getFrameId("left_tip"), m.getFrameId("right_tip")]

    def pin_call():
        pin.computeJointJacobians(m, d, q)
        pin.updateFramePlacements(m, d)
        return [
            (d.oMf[i].translation, pin.getFrameJacobian(m, d, i, pin.LOCAL_WORLD_ALIGNED))
            for i in ids
        ]

    rows.append(
        _row(
            "hand FK+J (2 tips)",
            "Pinocchio",
            time_call(pin_call),
            target="~2.7 µs per 3-DOF (issue)",
        )
    )
    f = ck.frame_kinematics(m, ["left_tip", "right_tip"], "hand_fk")
    trig, _ = _buffer_call(f, q)
    rows.append(
        _row("hand FK+J (2 tips)", "CasADi walked pin.Model, SX via buffer()", time_call(trig))
    )
    if compile_ok:
        trig, outs = _buffer_call(ck.compile(f), q)
        trig()
        assert np.allclose(outs[0], [*hand.fingertip_positions(q)["left"], 0.0], atol=1e-14)
        rows.append(
            _row(
                "hand FK+J (2 tips)",
                "CasADi walked, code-generated via buffer()",
                time_call(trig),
                target="~0.12 µs per 3-DOF (issue)",
            )
        )


def bench_sensors(rows, quick: bool) -> None:
    from robots.sensors import OWTS, TactileArray

    rng = np.random.default_rng(0)
    s = OWTS()
    n = 100_000 if quick else 1_000_000
    th = np.arccos(rng.uniform(np.cos(np.deg2rad(75)), 1.0, n))
    ph = rng.uniform(-np.pi, np.pi, n)
    normals = np.column_stack([np.cos(ph) * np.sin(th), np.sin(ph) * np.sin(th), np.cos(th)])
    v = s.voltages_from_contact(normals)
    t = time_call(lambda: s.contact_from_voltages(v), repeat=5)
    r = _row("OWTS voltages->contact", f"vectorized, N = {n}", t, per=n, unit="µs/sample")
    r["rate"] = f"{n / t['median_s'] / 1e6:.1f} M samples/s"
    r["target"] = ">= 1 M samples/s"
    rows.append(r)
    t = time_call(lambda: s.contact_from_voltages(v[0]))
    rows.append(_row("OWTS voltages->contact", "single sample", t))
    arr = TactileArray()
    rows.append(
        _row(
            "8x8 array image (sphere)",
            "single contact",
            time_call(lambda: arr.sphere_images([0.001, -0.002], 0.05, 0.3)),
            target="<= 20 µs/contact",
            unit="µs/contact",
        )
    )
    k = 256
    centers = rng.uniform(-0.006, 0.006, (k, 2))
    t = time_call(lambda: arr.sphere_images(centers, 0.05, 0.3), repeat=5)
    rows.append(
        _row(
            "8x8 array image (sphere)",
            f"batched, {k} contacts (amortized per contact)",
            t,
            per=k,
            target="none: the <= 20 µs target is the single call's (row above)",
            unit="µs/contact",
        )
    )


def main() -> None:
    args = arg_parser(__doc__.splitlines()[0]).parse_args()
    from robots import casadi_kinematics as ck

    compile_ok = True
    try:
        import casadi as cs

        x = cs.SX.sym("x")
        ck.compile(cs.Function("bench_probe", [x], [x]))
    except Exception as exc:  # noqa: BLE001 - report, then skip the compiled rows
        print(f"code generation unavailable, skipping compiled rows: {exc}")
        compile_ok = False
    rows: list[dict] = []
    bench_three_gm(rows, compile_ok)
    bench_hand(rows, compile_ok)
    bench_sensors(rows, args.quick)
    write_report(
        "kinematics",
        rows,
        title="Kinematics and sensor models",
        out=args.out,
        columns=["case", "method", "median", "best", "unit", "rate", "target"],
        notes=[
            "median/best of 7 batches (5 for large vectorized calls); per-call "
            "times include the Python call overhead",
            "Pinocchio 3GM row: kinematics at a closed configuration plus the "
            "passive-joint elimination (numpy lstsq), not the Newton closure",
        ],
    )


if __name__ == "__main__":
    main()
