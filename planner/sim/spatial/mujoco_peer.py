"""The ridge-slide scene in MuJoCo, through :func:`planner.sim.to_mjcf` (the benchmark's peer).

:func:`mujoco_ridge_rollout` loads the MJCF of a :func:`~.scenes.ridge_slide_scene` world
(the 3GM as bodies, hinges and a ``connect`` equality closing the five-bar, the plate as a
201x201 ``hfield``), runs the scene's own :class:`~.tip_controller.TipForceVelocityController`
at 1 kHz on MuJoCo's state, and measures the same quantities as hapex's run: the tip-centre
path against the exact offset surface (:func:`~.scenes.path_error`), steps without contact
force after the first contact, penetration, steps per second.

What the controller observes in MuJoCo: the motor angles and rates (exact: no encoder model)
and an ideal OWTS: the true contact normal of the tip (MuJoCo's contact frame) expressed in
the TCS, one sample per step, no noise. So the peer gets cleaner sensing than hapex' own
run (quantized encoders, noisy 12-bit OWTS).

Settings: ``"default"`` is the model as exported (MuJoCo's default solver parameters, the
elliptic cone ``to_mjcf`` writes); ``"best"`` adds ``impratio = 100``, 20 ``noslip``
iterations and stiff contacts (``solref`` time constant ``2 dt``), the settings of the
planar scenes' "best" rows.
"""

from __future__ import annotations

import time

import numpy as np

from planner.sim.mjcf import MUJOCO_SETTINGS
from planner.sim.observation import Observation
from planner.sim.spatial.finger import tcs_rotation
from planner.sim.spatial.scenes import RidgeScene, path_error
from planner.sim.spatial.sensing import OWTSReading

__all__ = ["SETTINGS", "mujoco_ridge_rollout"]

#: the two settings measured, with their labels
SETTINGS = MUJOCO_SETTINGS


def _model(scene: RidgeScene, settings: str):
    from planner.sim.mjcf import mujoco_model

    mujoco, m, d = mujoco_model(scene.world, settings)  # checks the settings
    mujoco.mj_forward(m, d)
    return mujoco, m, d


def _tip_contact(mujoco, m, d, tip: int, plate: int, force: np.ndarray):
    """``(surface normal (3,) WCS, normal force [N], penetration [m])`` of the tip's contact
    with the plate (the one with the largest force), or ``(None, 0, 0)``."""
    best, fn_best, pen = None, 0.0, 0.0
    for i in range(d.ncon):
        c = d.contact[i]
        pair = (int(c.geom1), int(c.geom2))
        if pair not in ((tip, plate), (plate, tip)):
            continue
        pen = max(pen, -float(c.dist))
        mujoco.mj_contactForce(m, d, i, force)
        if force[0] > fn_best:
            n = np.array(c.frame[:3])  # from geom1 to geom2
            best, fn_best = (n if pair[0] == plate else -n), float(force[0])
    return best, fn_best, pen


def mujoco_ridge_rollout(scene: RidgeScene, settings: str = "default") -> dict:
    """Run ``scene`` (fresh, not yet stepped) in MuJoCo; the measured quantities.

    Returns:
        dict with ``steps_per_s``, ``rms``, ``max`` [m] (centre path vs the exact offset),
        ``lost_steps``, ``penetration_max`` [m], ``build_s`` [s], ``status``, ``settings``
        (label).
    """
    t0 = time.perf_counter()
    mujoco, m, d = _model(scene, settings)
    build_s = time.perf_counter() - t0
    w, ctrl = scene.world, scene.controller
    tip, plate = m.geom(f"{w.finger.name}_tip").id, m.geom(scene.surface).id
    site = d.site(f"{w.finger.name}_tip")
    qa = [m.joint(n).qposadr[0] for n in ("theta1", "theta2", "theta3", "gamma1")]
    va = [m.joint(n).dofadr[0] for n in ("theta1", "theta2", "theta3")]
    act = [m.actuator(n).id for n in ("theta1", "theta2", "theta3")]
    n = int(round(scene.duration / w.dt))
    centres, active = np.zeros((n + 1, 3)), np.zeros(n + 1, bool)
    centres[0] = site.xpos
    force, pen = np.zeros(6), 0.0
    lo, hi = m.actuator_ctrlrange[act, 0], m.actuator_ctrlrange[act, 1]
    normal, _, pen = _tip_contact(mujoco, m, d, tip, plate, force)
    t0 = time.perf_counter()
    for k in range(n):
        q, qd = d.qpos[qa[:3]].copy(), d.qvel[va].copy()
        if normal is None:
            z = np.zeros((1, 3))
            reading = OWTSReading(np.array([d.time]), np.zeros((1, 4)), z, z, np.zeros(1, bool))
        else:
            R = tcs_rotation(float(d.qpos[qa[3]] + q[0]), float(q[2]))
            nt = R.T @ -normal
            reading = OWTSReading(
                np.array([d.time]), np.zeros((1, 4)), (w.finger.radius * nt)[None], nt[None],
                np.ones(1, bool),
            )  # fmt: skip
        tau = ctrl(d.time, Observation(d.time, q, qd, (w.finger.name,), owts=reading))
        d.ctrl[act] = np.clip(tau, lo, hi)
        mujoco.mj_step(m, d)
        normal, fn, p = _tip_contact(mujoco, m, d, tip, plate, force)  # also the next reading
        centres[k + 1], active[k + 1], pen = site.xpos, fn > 0.0, max(pen, p)
    wall = time.perf_counter() - t0
    pe = path_error(scene, centres, active)
    ok = bool(np.all(np.isfinite(d.qpos)))
    crossed = centres[-1, 0] - scene.ridge.position[0] > 2 * scene.ridge.width
    status = "ok" if crossed else "did not cross the ridge"
    return {
        "steps_per_s": n / wall,
        "rms": pe.rms,
        "max": pe.max,
        "lost_steps": pe.lost_steps,
        "penetration_max": pen,
        "build_s": build_s,
        "status": (status if active.any() else "no contact") if ok else "diverged",
        "settings": SETTINGS[settings],
    }
