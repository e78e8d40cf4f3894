"""Interactive 3-D view of an ``explore`` run directory (optional ``[viz]`` extra: viser).

:func:`build_scene` reads a run directory written by ``hapex run`` for an ``explore`` scenario
(``scenario.yaml`` and ``trajectory.npz``) into a :class:`Scene` of plain arrays in the WCS
(the 3GM's base frame, [m]): the plate as a triangle mesh, the fingertip-centre path coloured
by phase, the traced boundaries and skeletons of the features, and the 3GM's links over time
(like Fig. 4.5). It needs only numpy. :func:`serve` shows the scene in the browser with
`viser <https://viser.studio>`_ (imported lazily; ``pip install 'hapex[viz]'``), with a time
slider that moves the finger and its fingertip along the run::

    python -m planner.exploration.surface.viz runs/ridge_plate --port 8080
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from planner import checks
from planner.errors import InvalidParameter

__all__ = ["Scene", "build_scene", "serve"]

#: RGB colours of the recorded phases (runtime.PHASES order) and of the features
PHASE_COLORS = np.array(
    [
        [150, 150, 150],  # approach
        [31, 119, 180],  # search
        [120, 120, 200],  # move
        [255, 127, 14],  # across
        [214, 39, 40],  # along
        [44, 160, 44],  # trace
        [148, 103, 189],  # reapproach
        [90, 90, 90],  # idle
    ],
    np.uint8,
)
FEATURE_COLORS = ((214, 39, 40), (44, 160, 44), (148, 103, 189), (255, 127, 14), (23, 190, 207))


@dataclass(frozen=True)
class Scene:
    """An explore run as plain arrays, all in the WCS [m].

    Attributes:
        name: the scenario's name.
        plate_vertices: (V, 3) vertices of the plate's height field over the region.
        plate_faces: (F, 3) vertex indices of its triangles.
        path: (M, 3) fingertip centres (subsampled); path_colors: (M, 3) uint8 phase colours.
        boundaries: one (K, 3) array of boundary points per traced feature (on the plate).
        skeletons: one (S, 3) array of skeleton points per feature (on the plate).
        times: (T,) times of the finger frames [s].
        fingers: (T, 8, 3) 3GM polylines base-P1-joint-endpoint, NaN, base-P2-joint.
        tips: (T, 3) fingertip centres of the frames; tip_radius: r_f [m].
    """

    name: str
    plate_vertices: np.ndarray
    plate_faces: np.ndarray
    path: np.ndarray
    path_colors: np.ndarray
    boundaries: tuple[np.ndarray, ...]
    skeletons: tuple[np.ndarray, ...]
    times: np.ndarray
    fingers: np.ndarray
    tips: np.ndarray
    tip_radius: float


def _grid_mesh(height, region: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(n², 3) vertices (plate frame) and (2 (n-1)², 3) faces of the height field."""
    u = np.linspace(region[0, 0], region[0, 1], n)
    v = np.linspace(region[1, 0], region[1, 1], n)
    U, V = np.meshgrid(u, v, indexing="ij")
    verts = np.column_stack([U.ravel(), V.ravel(), np.asarray(height(U, V), float).ravel()])
    i = np.arange(n - 1)[:, None] * n + np.arange(n - 1)[None, :]
    a, b, c, d = i.ravel(), i.ravel() + n, i.ravel() + n + 1, i.ravel() + 1
    faces = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return verts, faces.astype(np.int32)


def _on_plate(height, pts2: np.ndarray, lift: float) -> np.ndarray:
    """(K, 3) points (u, v) placed ``lift`` [m] above the plate (plate frame)."""
    if len(pts2) == 0:
        return np.zeros((0, 3))
    w = np.asarray(height(pts2[:, 0], pts2[:, 1]), float) + lift
    return np.column_stack([pts2[:, 0], pts2[:, 1], w])


def _split(rows: np.ndarray) -> list[np.ndarray]:
    """``(feature index, u, v)`` rows into one (K, 2) array per feature."""
    if len(rows) == 0:
        return []
    ids = rows[:, 0].astype(int)
    return [rows[ids == i, 1:3] for i in range(int(ids.max()) + 1)]


def build_scene(
    run_dir, *, grid: int = 60, max_path: int = 5000, frames: int = 200, lift: float = 2e-4
) -> Scene:
    """Read an ``explore`` run directory into a :class:`Scene` (no viser needed).

    Args:
        run_dir: directory with ``scenario.yaml`` and ``trajectory.npz`` (``hapex run``).
        grid: plate mesh resolution per side [-].
        max_path: most path points kept (evenly subsampled) [-].
        frames: number of finger frames over the run [-].
        lift: boundaries and skeletons are drawn this far above the plate [m].

    Raises:
        InvalidParameter: not an explore run directory.
    """
    from planner.exploration.surface.placement import to_world
    from planner.exploration.surface.plates import plate_height
    from planner.exploration.surface.plots import _finger_points
    from planner.scenario import load_scenario
    from robots.three_gm import ThreeGM

    d = Path(run_dir)
    grid = checks.integer("grid", grid, 2)
    max_path = checks.integer("max_path", max_path, 2)
    frames = checks.integer("frames", frames, 1)
    if not (d / "scenario.yaml").is_file() or not (d / "trajectory.npz").is_file():
        raise InvalidParameter(
            f"run_dir: expected an explore run directory with scenario.yaml and "
            f"trajectory.npz, got {str(d)!r}"
        )
    config = load_scenario(d / "scenario.yaml")
    if getattr(config, "kind", None) != "explore":
        raise InvalidParameter(f"run_dir: expected an explore run, got kind {config.kind!r}")
    arr = np.load(d / "trajectory.npz")
    plate = config.plate.build(config.name)
    H = plate_height(plate)
    T = arr["pose"]
    region = np.asarray(config.region, float)
    verts, faces = _grid_mesh(H, region, grid)
    path, phase = arr["path"], arr["phase"].astype(int)
    keep = np.unique(np.linspace(0, len(path) - 1, min(len(path), max_path)).astype(int))
    colors = PHASE_COLORS[np.clip(phase[keep], 0, len(PHASE_COLORS) - 1)]
    bounds = tuple(to_world(T, _on_plate(H, b, lift)) for b in _split(arr["boundaries"]))
    skels = tuple(to_world(T, _on_plate(H, s, lift)) for s in _split(arr["skeleton_points"]))
    gm = ThreeGM()
    q, t = arr["q"], arr["sim_t"]
    idx = np.unique(np.linspace(0, len(q) - 1, min(len(q), frames)).astype(int))
    fingers = np.array([_finger_points(gm, q[k]) for k in idx]).reshape(len(idx), 8, 3)
    tips = np.array([gm.forward_kinematics(q[k]) for k in idx]).reshape(len(idx), 3)
    return Scene(
        name=config.name,
        plate_vertices=to_world(T, verts),
        plate_faces=faces,
        path=to_world(T, path[keep]) if len(keep) else np.zeros((0, 3)),
        path_colors=colors,
        boundaries=bounds,
        skeletons=skels,
        times=t[idx],
        fingers=fingers,
        tips=tips,
        tip_radius=float(config.tip_radius),
    )


def _segments(polyline: np.ndarray) -> np.ndarray:
    """(N-1, 2, 3) segments of a polyline, skipping those with a NaN end."""
    seg = np.stack([polyline[:-1], polyline[1:]], axis=1)
    return seg[~np.isnan(seg).any(axis=(1, 2))]


def _load_viser():
    try:
        import viser
    except ImportError as exc:
        raise ImportError(
            "the interactive view needs viser, an optional dependency: "
            "pip install 'hapex[viz]' (or pip install viser)"
        ) from exc
    return viser


def serve(run_dir, *, host: str = "127.0.0.1", port: int = 8080, block: bool = True):
    """Show an ``explore`` run directory in the browser (viser); returns the server.

    Args:
        run_dir: the run directory (see :func:`build_scene`).
        host, port: where the viser server listens.
        block: serve until interrupted (False: return the running server at once).

    Raises:
        ImportError: viser is not installed (the ``[viz]`` extra).
        InvalidParameter: not an explore run directory.
    """
    viser = _load_viser()
    scene = build_scene(run_dir)
    server = viser.ViserServer(host=host, port=int(port), label=f"hapex: {scene.name}")
    add_scene(server, scene)
    if block:
        server.sleep_forever()
    return server


def add_scene(server, scene: Scene) -> None:
    """Add a :class:`Scene` to a viser server: plate, path, features, finger and a time
    slider moving the finger."""
    s = server.scene
    s.add_mesh_simple(
        "/plate", scene.plate_vertices, scene.plate_faces, color=(200, 200, 200), side="double"
    )
    if len(scene.path) > 1:
        seg = _segments(scene.path)
        s.add_line_segments(
            "/path", seg, np.repeat(scene.path_colors[1:, None], 2, axis=1), thickness=2e-4
        )
    for i, (b, k) in enumerate(zip(scene.boundaries, scene.skeletons, strict=False)):
        color = FEATURE_COLORS[i % len(FEATURE_COLORS)]
        s.add_point_cloud(f"/feature{i}/boundary", b, color, point_size=3e-4)
        s.add_point_cloud(f"/feature{i}/skeleton", k, (0, 0, 0), point_size=5e-4)
    finger = s.add_line_segments(
        "/finger", _segments(scene.fingers[-1]), (255, 140, 0), thickness=1.5e-3
    )
    tip = s.add_icosphere(
        "/tip", scene.tip_radius, (255, 140, 0), opacity=0.5, position=scene.tips[-1]
    )
    slider = server.gui.add_slider(
        "time [s]",
        float(scene.times[0]),
        float(scene.times[-1]),
        float(max(scene.times[-1] - scene.times[0], 1e-3) / max(len(scene.times) - 1, 1)),
        float(scene.times[-1]),
    )

    @slider.on_update
    def _(_event) -> None:
        k = int(np.argmin(np.abs(scene.times - slider.value)))
        finger.points = _segments(scene.fingers[k])
        tip.position = scene.tips[k]


def main(argv=None) -> None:
    """``python -m planner.exploration.surface.viz RUN_DIR [--host H] [--port P]``."""
    p = argparse.ArgumentParser(description="Interactive 3-D view of an explore run (viser)")
    p.add_argument("run_dir")
    p.add_argument("--host", default="127.0.0.1")
    p.add_argument("--port", type=int, default=8080)
    a = p.parse_args(argv)
    serve(a.run_dir, host=a.host, port=a.port)


if __name__ == "__main__":
    main()
