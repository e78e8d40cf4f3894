"""The explorer's servo step (runtime.py): compiled step == numpy reference, control variants."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.control.hybrid_law import HybridSettings, owts_voltages
from planner.errors import InvalidParameter
from planner.exploration import explore_surface
from planner.exploration.surface.explorer import build_world
from planner.exploration.surface.motions import approach, move_to, sweep
from planner.exploration.surface.placement import region_box
from planner.exploration.surface.result import ExplorationSettings
from planner.exploration.surface.runtime import OWTS_ON, ExplorerController, owts_mean
from planner.sim.spatial.plate import Plate, PlateFeature

REGION = ((-0.012, 0.012), (-0.006, 0.006))
PLATE = Plate((PlateFeature("ridge", 1.5e-3, 2e-3, (0.002, 0.0), np.radians(20.0)),))


class _Obs:
    def __init__(self, owts):
        self.owts = owts


@settings(max_examples=60, deadline=None)
@given(
    st.integers(0, 6),
    st.lists(st.floats(-0.2, 2.0), min_size=28, max_size=28),
    st.floats(0.0, 1.0),
)
def test_compiled_owts_mean_equals_owts_voltages(k, values, dark):
    a = np.asarray(values).reshape(7, 4)[:k].copy()
    if k:
        a[0] *= dark * 1e-3  # a row near the contact threshold
    want = owts_voltages(_Obs(a), np.zeros(4), threshold=OWTS_ON)
    got = np.full(4, np.nan)
    owts_mean(a, OWTS_ON, got)
    np.testing.assert_array_equal(got, want)


def _program(ex):
    """Approach, slide across the ridge and back: the motion primitives of the explorer."""
    yield from approach(ex)
    yield from sweep(ex, np.array([-0.008, 0.001]), np.array([0.008, 0.001]), 0.03)
    yield from move_to(ex, np.array([-0.004, -0.002]), 0.03)


@pytest.mark.parametrize("control", ["open_loop", "closed_loop", "qp"])
def test_compiled_explorer_step_equals_the_reference_path(control):
    """kernel=True (one compiled call) and kernel=False (HybridController + numpy) give the
    same recorder, path and events for the same world and program."""
    cfg = ExplorationSettings()
    runs = []
    for kernel in (True, False):
        world, gm, T = build_world(PLATE, cfg, region_box(REGION), 0.0, 1)
        s = HybridSettings(kp=cfg.kp, kv=cfg.kv, control=control)
        ex = ExplorerController(gm, s, T, 1500, kernel=kernel)
        ex.program = _program(ex)
        ex.warm_up()
        log = world.run(1.2, controller=ex, stop=ex.stop)
        runs.append((ex, log))
    (a, la), (b, lb) = runs
    assert a.rec.n == b.rec.n > 1000
    n = a.rec.n
    for name in ("t", "centre", "contact", "normal", "normal_force"):
        np.testing.assert_allclose(getattr(a.rec, name)[:n], getattr(b.rec, name)[:n], atol=1e-9)
    for name in ("in_contact", "phase", "feature", "saturated"):
        np.testing.assert_array_equal(getattr(a.rec, name)[:n], getattr(b.rec, name)[:n])
    np.testing.assert_allclose(la.q, lb.q, atol=1e-9)
    assert [e.kind for e in a.events] == [e.kind for e in b.events]
    assert a.est.k == b.est.k == n
    np.testing.assert_array_equal(a.est.centre, b.est.centre)


@pytest.mark.parametrize("control", ["closed_loop", "qp"])
def test_control_variants_explore_and_press(control):
    res = explore_surface(
        Plate(()),
        region=((-0.01, 0.01), (-0.004, 0.004)),
        duration=0.8,
        speed=0.02,
        seed=3,
        control=control,
    )
    assert res.status == "ok", res.reason
    searching = res.phase == res.phases.index("search")
    assert searching.sum() > 300
    fn = res.log.normal_force.sum(axis=1)[1 : len(res.t) + 1][searching]
    assert np.sqrt(np.mean((fn - 0.3) ** 2)) < 0.05


def test_unknown_control_is_invalid_parameter():
    with pytest.raises(InvalidParameter, match="control"):
        explore_surface(Plate(()), duration=0.1, control="pid")


@pytest.mark.parametrize("d", [-0.004, -0.002, -0.0005, 0.0, 0.001, 0.003])
def test_the_finger_starts_clear_of_the_plate(d):
    """The fingertip starts at least GAP / 2 clear of the plate, even next to a cusp crest
    (slope 1), where H + r + GAP would start it in penetration; on a flat spot at H + r."""
    from planner.exploration.surface.explorer import GAP, _start_height
    from planner.exploration.surface.plates import plate_height

    r = 0.008
    H = plate_height(Plate((PlateFeature("cusp", 3e-3, 3e-3, (d, 0.0), 0.0),)))
    z = _start_height(H, np.array([0.0, 0.0]), r) + GAP
    xs = np.linspace(-0.02, 0.02, 200001)
    clearance = np.min(np.hypot(xs, H(xs, np.zeros_like(xs)) - z)) - r
    assert 0.5 * GAP - 1e-5 < clearance < GAP + 1e-5
    flat = plate_height(Plate(()))
    assert _start_height(flat, np.array([0.003, -0.002]), r) == r


def _watched(phase: str):
    """An ExplorerController whose program holds still, in ``phase``, out of contact."""
    from planner.exploration.surface.runtime import PHASE

    cfg = ExplorationSettings()
    _, gm, T = build_world(Plate(()), cfg, region_box(REGION), 0.0, 0)
    ex = ExplorerController(gm, HybridSettings(), T, 4)
    ex.program = iter(lambda: (0.0, 0.0), None)
    ex.phase = PHASE[phase]
    ex.est.centre = np.array([0.002, -0.001, 0.01])
    return ex


def _steps(ex, k0: int, k1: int, in_contact: bool) -> None:
    for k in range(k0, k1):
        ex.est.t, ex.est.in_contact = k * 1e-3, in_contact
        ex._advance()


def test_contact_lost_longer_than_the_limit_fails_the_run():
    from planner.exploration.surface.runtime import CONTACT_LOST_TIME

    assert CONTACT_LOST_TIME == 0.5
    ex = _watched("search")
    _steps(ex, 0, 400, False)  # 0.4 s off the plate ...
    _steps(ex, 400, 401, True)  # ... back on: the clock restarts
    _steps(ex, 401, 902, False)  # off from t = 0.401 s; 0.500 s later still running
    assert ex.failed is None and ex.finished is None
    _steps(ex, 902, 903, False)  # 0.501 s
    assert ex.failed == (
        "ContactLost: no contact for more than 0.5 s while in phase search: the fingertip "
        "left the plate at t = 0.401 s, (2.0, -1.0) mm, and did not come back"
    )
    assert ex.finished == ex.failed
    assert [e.kind for e in ex.events] == ["failed"]


@pytest.mark.parametrize("phase", ["approach", "idle"])
def test_no_contact_is_expected_while_approaching_or_idle(phase):
    ex = _watched(phase)
    _steps(ex, 0, 2000, False)
    assert ex.failed is None and ex.finished is None
