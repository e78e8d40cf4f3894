"""The optional interactive view of explore runs (viz.py): the scene, without a server."""

from __future__ import annotations

import sys

import numpy as np
import pytest
from conftest import ROOT, run_cli

from planner.errors import InvalidParameter
from planner.exploration.surface import viz
from planner.exploration.surface.placement import to_world
from robots.three_gm import ThreeGM


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("viz") / "ridge"
    scenario = str(ROOT / "scenarios" / "ridge_plate.yaml")
    proc = run_cli("run", scenario, "--quick", "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    # two traced features' boundaries and skeletons (a quick run traces none)
    arr = dict(np.load(out / "trajectory.npz"))
    ang = np.linspace(0, 2 * np.pi, 50)
    ring = np.column_stack([0.004 * np.cos(ang), 0.004 * np.sin(ang)])
    arr["boundaries"] = np.vstack(
        [np.column_stack([np.zeros(50), ring]), np.column_stack([np.ones(50), ring + 0.01])]
    )
    arr["skeleton_points"] = np.array([[0, 0.0, 0.0], [1, 0.01, 0.01], [1, 0.011, 0.01]])
    np.savez(out / "trajectory.npz", **arr)
    return out


def test_scene_holds_the_run_in_the_wcs(run_dir):
    arr = np.load(run_dir / "trajectory.npz")
    sc = viz.build_scene(run_dir, grid=20, max_path=100, frames=7)
    assert sc.name == "ridge_plate"
    assert sc.plate_vertices.shape == (400, 3) and sc.plate_faces.shape == (2 * 19 * 19, 3)
    assert sc.plate_faces.min() == 0 and sc.plate_faces.max() == 399
    # the plate mesh is the plate frame's height field moved by the pose
    T = arr["pose"]
    local = (sc.plate_vertices - T[:3, 3]) @ T[:3, :3]
    assert np.ptp(local[:, 0]) == pytest.approx(0.04) and np.ptp(local[:, 1]) == pytest.approx(0.04)
    assert local[:, 2].max() == pytest.approx(0.002, rel=0.05)  # the 2 mm ridge
    assert len(sc.path) == 100
    np.testing.assert_allclose(sc.path[0], to_world(T, arr["path"][0]))
    np.testing.assert_allclose(sc.path[-1], to_world(T, arr["path"][-1]))
    assert sc.path_colors.shape == (100, 3) and sc.path_colors.dtype == np.uint8
    assert [len(b) for b in sc.boundaries] == [50, 50]
    assert [len(k) for k in sc.skeletons] == [1, 2]
    # a boundary point sits on the plate (+ lift), moved by the pose
    b_local = (sc.boundaries[1] - T[:3, 3]) @ T[:3, :3]
    np.testing.assert_allclose(b_local[:, :2], np.asarray(arr["boundaries"])[50:, 1:], atol=1e-12)
    assert sc.fingers.shape == (7, 8, 3) and sc.times.shape == (7,)
    gm = ThreeGM()
    np.testing.assert_allclose(sc.tips[-1], gm.forward_kinematics(arr["q"][-1]), atol=1e-12)
    np.testing.assert_allclose(sc.fingers[-1][3], sc.tips[-1], atol=1e-9)  # endpoint = tip


class _Recorder:
    """A stand-in for a viser server: records what add_scene adds."""

    def __init__(self):
        self.calls, self.scene, self.gui = [], self, self
        self.callbacks = []

    def __getattr__(self, name):
        def add(*args, **kwargs):
            self.calls.append((name, args, kwargs))
            handle = type("Handle", (), {})()
            handle.value = args[-1] if name == "add_slider" else None
            handle.on_update = lambda fn: self.callbacks.append(fn) or fn
            return handle

        return add


def test_add_scene_adds_plate_path_features_finger_and_slider(run_dir):
    sc = viz.build_scene(run_dir, grid=10, frames=5)
    server = _Recorder()
    viz.add_scene(server, sc)
    names = [args[0] for kind, args, _ in server.calls if kind != "add_slider"]
    assert names[:2] == ["/plate", "/path"]
    assert "/feature1/boundary" in names and "/finger" in names and "/tip" in names
    seg = next(a[1] for k, a, _ in server.calls if a and a[0] == "/path")
    assert seg.shape[1:] == (2, 3) and not np.isnan(seg).any()
    assert len(server.callbacks) == 1


def test_serve_without_viser_says_how_to_install(run_dir, monkeypatch):
    monkeypatch.setitem(sys.modules, "viser", None)
    with pytest.raises(ImportError, match=r"hapex\[viz\]"):
        viz.serve(run_dir, block=False)


def test_not_a_run_directory_is_invalid_parameter(tmp_path):
    with pytest.raises(InvalidParameter, match="run_dir"):
        viz.build_scene(tmp_path)
