"""The tactile-image cue of a ridge (thesis §2.3.2, Fig. 2.14) fused with the contact-trace
detection (planner/exploration/planar/sensed_features.py, macro.py): closed forms of the
image moments, synthetic images of the 8x8 array (round contact vs ridge), the candidate
runs on a synthetic trace, the fusion rules, and the regression on ``ball_with_ridge`` (the
README's main job) and on the same ball without its ridge."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from planner.errors import InvalidParameter
from planner.exploration.planar import sensed_features as sf
from robots.sensors import TactileArray


def test_image_shape_closed_forms():
    one = np.zeros((1, 8, 8))
    one[0, 3, 4] = 5.0
    pair = np.zeros((1, 8, 8))
    pair[0, 3, 4:6] = 5.0
    row = np.zeros((1, 8, 8))
    row[0, 2, :] = 1.0  # a line of 8 taxels: sqrt((1/12 + (64 - 1) / 12) / (1/12)) = 8
    el, pk = sf.image_shape(np.concatenate([one, pair, row, np.zeros((1, 8, 8))]))
    assert el[:3] == pytest.approx([1.0, 2.0, 8.0])
    assert pk[:3] == pytest.approx([1.0, 0.5, 1 / 8])
    assert np.isnan(el[3]) and np.isnan(pk[3])
    # the same line along the other axis and the diagonal 2x2 block: rotation/shape checks
    el_t, _ = sf.image_shape(row.transpose(0, 2, 1))
    assert el_t[0] == pytest.approx(8.0)
    with pytest.raises(InvalidParameter, match="images"):
        sf.image_shape(np.zeros((8, 8)))


def test_round_contact_vs_ridge_on_the_array():
    """A 10 cm ball at 0.15-0.9 N is a round patch anywhere on the pad; a 4 mm ridge across
    the pad (3-D, any direction) is a line; a ridge edge (radius 1 mm) on the planar world's
    contact line (the pad's mid-line, v = 0) loads the taxels on both sides of it."""
    arr = TactileArray()
    rng = np.random.default_rng(3)
    centres = rng.uniform(-2.5e-3, 2.5e-3, (20, 2))
    on_line = centres * [1.0, 0.0]
    for force in (0.15, 0.3, 0.9):
        for c in (centres, on_line):
            el, _ = sf.image_shape(arr.sphere_images(c, 0.05, np.full(20, force)))
            assert np.all(el < 1.25), force
        # an edge near a taxel column's centre (+-1.25 mm, +-3.75 mm, ...; farther than
        # 0.2-0.4 mm from it, it loads a 2 x 2 block: elongation 1.2, see LINE_ELONGATION)
        edge = np.array([[1.25e-3 + d, 0.0] for d in (-0.2e-3, 0.0, 0.2e-3)])
        el, pk = sf.image_shape(arr.sphere_images(edge, 1e-3, np.full(3, force)))
        assert np.all(el >= sf.LINE_ELONGATION) and np.all(pk >= 0.45), force
    for angle in (0.0, 0.5 * math.pi, 0.3):
        img = arr.ridge_image(np.array([0.4e-3, -0.7e-3]), angle, 0.002, 0.3)
        el, _ = sf.image_shape(img[None])
        assert el[0] > 2 * sf.LINE_ELONGATION, angle


def _trace(angles: np.ndarray, line: np.ndarray, force: float = 0.3) -> dict:
    """A phase-3 trace of the pad sliding over object angles ``angles`` [rad] (ball at the
    origin, no rotation), one image per row: a round Hertz patch, or an edge where ``line``."""
    arr = TactileArray()
    n = angles.size
    imgs = arr.sphere_images(np.zeros((n, 2)), 0.05, np.full(n, force))
    edge = np.tile([1.25e-3, 0.0], (int(line.sum()), 1))  # a taxel column's centre
    imgs[line] = arr.sphere_images(edge, 1e-3, np.full(len(edge), force))
    t = 0.01 * np.arange(n)
    return {
        "t": t, "kind": np.full(n, 3.0), "pad_touch": np.ones(n), "fnL": np.full(n, force),
        "pLx": 0.05 * np.cos(angles), "pLy": 0.05 * np.sin(angles), "cx": np.zeros(n),
        "cy": np.zeros(n), "image_t": t, "images": imgs, "u": np.zeros(n),
        "nLx": np.cos(angles), "nLy": np.sin(angles),
    }  # fmt: skip


BAND = (0.15, 0.9)


def test_image_ridges_finds_a_sustained_line_and_nothing_on_a_round_ball():
    a = np.linspace(0.0, 2.0, 400)
    th = np.zeros(a.size)
    assert sf.image_ridges(_trace(a, np.zeros(a.size, bool)), th, BAND) == []
    line = np.abs(a - 1.0) < 0.03  # ~60 images: the pad held on the ridge's edge
    found = sf.image_ridges(_trace(a, line), th, BAND)
    assert len(found) == 1 and found[0] == pytest.approx(1.0, abs=0.01)
    # a short blip (a pad lifting off), a light touch, or another phase is no ridge
    blip = np.zeros(a.size, bool)
    blip[100 : 100 + sf.IMAGE_MIN_RUN - 1] = True
    assert sf.image_ridges(_trace(a, blip), th, BAND) == []
    assert sf.image_ridges(_trace(a, line, force=0.05), th, BAND) == []
    tr = _trace(a, line)
    tr["kind"] = np.full(a.size, 2.0)
    assert sf.image_ridges(tr, th, BAND) == []
    # the sensed rotation maps the contact to the object frame
    found = sf.image_ridges(_trace(a, line), np.full(a.size, 0.2), BAND)
    assert found[0] == pytest.approx(0.8, abs=0.01)
    # two stretches within IMAGE_MERGE (near and far edge) are one ridge between them
    two = (np.abs(a - 0.95) < 0.03) | (np.abs(a - 1.1) < 0.03)
    found = sf.image_ridges(_trace(a, two), th, BAND)
    assert len(found) == 1 and found[0] == pytest.approx(1.025, abs=0.01)
    far = (np.abs(a - 0.5) < 0.03) | (np.abs(a - 1.5) < 0.03)  # 57 deg apart: two ridges
    assert sf.image_ridges(_trace(a, far), th, BAND) == pytest.approx([0.5, 1.5], abs=0.01)


def _walls_trace(sightings, gap: int = 20) -> dict:
    """A phase-3 trace of line-like images touching the ball (radius 50 mm, centre at the
    origin) with the pad's end: ``sightings`` ``[(object angle [rad], u [m]), ...]``, each
    a run of 15 images with the tactile centroid at ``u`` and the touched point (the pad's
    end, :func:`sf.pad_end_contact`) at that angle; runs apart by ``gap`` round images.
    The pad's +u axis is the counter-clockwise tangent."""
    angles, us, line = [], [], []
    for ang, u in sightings:
        angles += [ang] * (15 + gap)
        us += [u] * 15 + [0.0] * gap
        line += [True] * 15 + [False] * gap
    a, u, line = np.array(angles), np.array(us), np.array(line)
    tr = _trace(a, line)
    end = np.sign(u) * sf.PAD_HALF_WIDTH  # the touched point: the pad's end
    tangent = np.column_stack([-np.sin(a), np.cos(a)])
    p = (
        0.05 * np.column_stack([np.cos(a), np.sin(a)])
        - (np.where(u != 0, end, 0.0) - u)[:, None] * tangent
    )
    tr.update(u=u, pLx=p[:, 0], pLy=p[:, 1])
    return tr


def test_wall_sides_follow_the_pad_end_and_its_direction():
    tr = _walls_trace([(0.3, 8.75e-3), (0.3, -9e-3), (0.3, 3e-3)], gap=0)
    side = sf.wall_sides(tr, 8)
    assert set(side[:15]) == {1.0} and set(side[15:30]) == {-1.0} and set(side[30:]) == {0.0}
    tr["nLx"], tr["nLy"] = -tr["nLx"], -tr["nLy"]  # the pad's axis reversed: clockwise
    tr["u"] = -tr["u"]  # the same points, now at the other end of the pad
    assert np.array_equal(sf.wall_sides(tr, 8), side)
    tr["u"] = -tr["u"]
    assert np.array_equal(sf.wall_sides(tr, 8), -side)


def test_a_ridge_seen_at_both_walls_lies_between_them():
    near, far = 1.0, 1.08  # walls of a 4 mm ridge at 1.04 rad on the 50 mm ball
    # the pad's leading end stalls at the near wall in three passes, its trailing end meets
    # the far wall in one: midway, not the median of the sightings (the near wall)
    tr = _walls_trace([(near, 8.75e-3)] * 3 + [(far, -8.75e-3)])
    th = np.zeros(tr["t"].size)
    assert sf.image_ridges(tr, th, BAND) == pytest.approx([1.04], abs=2e-3)
    # only the near wall: the near wall (the ridge's width is unknown)
    tr = _walls_trace([(near, 8.75e-3)] * 3)
    assert sf.image_ridges(tr, np.zeros(tr["t"].size), BAND) == pytest.approx([near], abs=2e-3)
    # walls whose bodies point away from each other enclose nothing: the median
    tr = _walls_trace([(near, -8.75e-3)] * 3 + [(far, 8.75e-3)])
    assert sf.image_ridges(tr, np.zeros(tr["t"].size), BAND) == pytest.approx([near], abs=2e-3)


def test_fusion_rules():
    r = math.radians
    # a ridge the trace saw in two passes: the image adds nothing
    assert sf.fuse_image_ridges([r(172)], [(r(170), 1)], []) == []
    # a single-pass height region close by confirms it (placed where the images saw it);
    # an image ridge without one (the pad's own edge on the object) is dropped
    assert sf.fuse_image_ridges([r(166)], [], [r(168.5), r(40)]) == [(r(166), 1)]
    assert sf.fuse_image_ridges([r(172)], [], [r(179.8)]) == [(r(172), 1)]
    assert sf.fuse_image_ridges([r(-152)], [], [r(172.8)]) == []
    assert sf.fuse_image_ridges([r(-152)], [], []) == []
    # across +-pi
    assert sf.fuse_image_ridges([r(179)], [(r(-178), 1)], []) == []


def _run(cli, tmp_path, text: str) -> dict:
    scenario = tmp_path / "s.yaml"
    scenario.write_text(text)
    out = tmp_path / "out"
    proc = cli("run", str(scenario), "--out", str(out), timeout=600)
    assert proc.returncode == 0, proc.stderr
    return json.loads((out / "result.json").read_text())["metrics"]


def test_ball_with_ridge_finds_the_ridge(cli, tmp_path):
    """The README's main job (seed 0: the trace alone saw the ridge in one pass only)."""
    with open("scenarios/ball_with_ridge.yaml") as f:
        m = _run(cli, tmp_path, f.read())
    assert m["ridge_found"] is True
    assert m["ridge_error_deg"] <= 5.0
    assert [f["kind"] for f in m["features"]] == ["ridge"]


def test_plain_ball_finds_no_ridge(cli, tmp_path):
    with open("scenarios/ball_with_ridge.yaml") as f:
        lines = [x for x in f.read().splitlines() if not x.lstrip().startswith("ridge_")]
    text = "\n".join(lines).replace("shape: circle_with_ridge", "shape: circle")
    m = _run(cli, tmp_path, text)
    assert m["features_found"] == 0, m["features"]
