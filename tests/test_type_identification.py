"""Type identification (thesis §4.4.1, Fig. 4.7 extended) on traces without the simulator."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.exploration.surface.detection_adapter import analyse_path, collapse_pattern
from planner.exploration.surface.identify import (
    KINDS,
    Crossing,
    crossing_axis,
    evidence,
    flow_chart_next,
    identify,
)
from planner.exploration.surface.kinematic import ball_trace, line_points
from planner.exploration.surface.plates import plate_height, random_plate
from planner.exploration.surface.raster_match import raster_identify
from planner.geometry import shapes
from planner.geometry.measurement import simulate_trace

R = 0.008


def _strip(profile, sigma=0.0, seed=0):
    """A 2-D cross-section trace embedded in the plate frame: (u, 0, w)."""
    rng = np.random.default_rng(seed)
    tr = simulate_trace(profile, R, spacing=1e-4, center_sigma=sigma, rng=rng)
    c = tr.centers
    centers = np.column_stack([c[:, 0], np.zeros(len(c)), c[:, 1]])
    n = tr.truth.normals
    normals = np.column_stack([n[:, 0], np.zeros(len(n)), n[:, 1]])
    return centers, normals


ACROSS = {
    "ridge": lambda h: shapes.ridge(2 * h, h, 0.2 * h, length=0.06),
    "ravine": lambda h: shapes.ravine(6 * h, h, 0.2 * h, length=0.06),
    "bump": lambda h: shapes.bump(h, 1.2 * h, "gaussian", length=0.06),
    "pit": lambda h: shapes.pit(h, 6 * h, length=0.06),
    "step": lambda h: shapes.step(h, length=0.06),
    "cusp": lambda h: shapes.cusp(np.deg2rad(140), length=0.06),
}


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("height", [2e-3, 4e-3])
@pytest.mark.parametrize("sigma", [0.0, 2e-5])
def test_cross_sections_identify_every_kind(kind, height, sigma):
    """Across the cross-section, then along the axis (the bump's and pit's profile again, the
    others' a plane), as the extended flow chart moves the finger."""
    c1, _ = _strip(ACROSS[kind](height), sigma, 1)
    along = ACROSS[kind](height) if kind in ("bump", "pit") else shapes.plane(length=0.06)
    c2, _ = _strip(along, sigma, 2)
    e1, a1, _ = evidence(c1, np.tile([0, 0, 1.0], (len(c1), 1)), R, "across")
    e2, _, _ = evidence(c2, np.tile([0, 0, 1.0], (len(c2), 1)), R, "along")
    assert a1.features, "the crossing must see curvature features"
    dec = identify([e1, e2])
    assert dec.kind == kind, dec.path
    assert dec.confidence > 0.5
    assert sum(dec.scores.values()) == pytest.approx(1.0)


def test_fig_4_7_patterns_on_one_crossing():
    """Fig. 4.7's own branches: cusp one convex, step concave-convex, ridge -+-."""
    pats = {}
    for kind in ("cusp", "step", "ridge"):
        c, _ = _strip(ACROSS[kind](3e-3))
        pats[kind] = analyse_path(c, R).pattern
    assert pats == {"cusp": "+", "step": "-+", "ridge": "-+-"}


def test_nothing_seen_is_unknown_and_flow_chart_order():
    c, _ = _strip(shapes.plane(length=0.06))
    e, a, _ = evidence(c, np.tile([0, 0, 1.0], (len(c), 1)), R)
    assert a.pattern == ""
    assert identify([e]).kind == "unknown"
    assert flow_chart_next([]) == "across"
    assert flow_chart_next([Crossing("-+-", "across")]) == "along"
    assert flow_chart_next([Crossing("-+-", "across"), Crossing("", "along")]) is None


@settings(max_examples=30, deadline=None, derandomize=True)
@given(st.lists(st.sampled_from([-1, 1]), min_size=0, max_size=8))
def test_collapse_pattern_has_no_repeated_signs(signs):
    p = collapse_pattern(signs)
    assert all(a != b for a, b in zip(p, p[1:], strict=False))
    assert set(p) <= {"+", "-"} and (len(p) > 0) == (len(signs) > 0)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(st.floats(0, np.pi), st.floats(-1.2, 1.2))
def test_axis_from_normals_of_an_oblique_ridge_crossing(psi, tilt):
    """The tilt of the normals on a ridge's flanks points across it, whatever the crossing."""
    across = np.array([np.cos(psi), np.sin(psi)])
    d = np.array([np.cos(psi + tilt), np.sin(psi + tilt)])
    s = np.linspace(-1, 1, 41)
    g = 0.3 * np.sign(-s)[:, None] * across[None] * np.abs(np.sin(3 * s))[:, None]
    normals = np.column_stack([g, np.sqrt(1 - (g**2).sum(1))])
    est = crossing_axis(normals, d)
    assert abs(abs(est @ across) - 1.0) < 1e-9


@pytest.mark.parametrize(
    ("kind", "size", "angle"),
    [("bump", 3e-3, 0.4), ("pit", 3e-3, 0.0), ("ridge", 2e-3, 1.0), ("step", 4e-3, 2.2)],
)
def test_plate_crossings_with_the_ball_identify(kind, size, angle):
    """On the simulator's plate geometry: search crossing at an angle, then across and along."""
    rng = np.random.default_rng(5)
    H = plate_height(random_plate(rng, kind, size, angle))
    d = np.array([np.cos(angle + 0.5), np.sin(angle + 0.5)])
    tr = ball_trace(H, line_points(-0.022 * d, 0.022 * d, 1e-4), R, noise=2e-5, rng=rng)
    e0, a0, across = evidence(tr.centers, tr.normals, R, "search")
    idx = [f.index for f in a0.features]
    mid = tr.centers[int(round(0.5 * (min(idx) + max(idx)))), :2]
    axis = np.array([-across[1], across[0]])
    crossings = [e0]
    for role, v in (("across", across), ("along", axis)):
        t = ball_trace(H, line_points(mid - 0.02 * v, mid + 0.02 * v, 1e-4), R, noise=2e-5, rng=rng)
        crossings.append(evidence(t.centers, t.normals, R, role)[0])
    dec = identify(crossings)
    assert dec.kind == kind, dec.path


def test_raster_pattern_matching_ridge_and_bump():
    rng = np.random.default_rng(2)
    for kind, size in (("ridge", 3e-3), ("bump", 1e-3)):
        H = plate_height(random_plate(rng, kind, size, 0.5))
        lines = [
            ball_trace(H, line_points((-0.02, y), (0.02, y), 1.5e-4), R).centers
            for y in np.arange(-0.02, 0.0201, 0.004)
        ]
        found = raster_identify(lines, R)
        assert found and found[0].decision.kind == kind


def _stadium_outline(half: float, rho: float, n: int = 600) -> np.ndarray:
    """Closed outline of the points within ``rho`` of the segment (-half, 0)-(half, 0) [m]."""
    t = np.linspace(0.0, 1.0, n, endpoint=False)
    per = 4 * half + 2 * np.pi * rho
    out = []
    for x in t * per:
        if x < 2 * half:
            out.append((-half + x, -rho))
        elif x < 2 * half + np.pi * rho:
            a = (x - 2 * half) / rho - np.pi / 2
            out.append((half + rho * np.cos(a), rho * np.sin(a)))
        elif x < 4 * half + np.pi * rho:
            out.append((half - (x - 2 * half - np.pi * rho), rho))
        else:
            a = (x - 4 * half - np.pi * rho) / rho + np.pi / 2
            out.append((-half + rho * np.cos(a), rho * np.sin(a)))
    return np.array(out)


def test_outline_elongation_uses_area_not_sample_density():
    from planner.exploration.surface.identify import outline_elongation

    t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    assert outline_elongation(np.column_stack([3e-3 * np.cos(t), 1e-3 * np.sin(t)])) == (
        pytest.approx(3.0, rel=1e-3)
    )
    dense = np.concatenate([np.linspace(0, np.pi, 600), np.linspace(np.pi, 2 * np.pi, 30)[1:]])
    circle = np.column_stack([5e-3 * np.cos(dense), 5e-3 * np.sin(dense)])
    assert np.cov(circle.T)[1, 1] / np.cov(circle.T)[0, 0] < 0.8  # lopsided sample moments
    assert outline_elongation(circle) == pytest.approx(1.0, abs=0.02)


@pytest.mark.parametrize(("kind", "elongated"), [("bump", "ridge"), ("pit", "ravine")])
def test_refine_with_outline_by_the_skeleton_of_the_traced_outline(kind, elongated):
    """A bump's medial axis is a point; a 12 mm ridge seen through the ball is a stadium only
    about twice as long as wide, but its axis is 12 mm long: ridge."""
    from planner.exploration.surface.identify import TypeDecision, refine_with_outline

    dec = TypeDecision(kind, 0.8, {kind: 0.8, elongated: 0.1}, ("flow chart",))
    rng = np.random.default_rng(2)
    stadium = _stadium_outline(6e-3, 6.5e-3) + rng.normal(0, 2e-5, (600, 2))
    out = refine_with_outline(dec, stadium, closed=True)
    assert out.kind == elongated and out.scores[elongated] == 0.8
    assert "skeleton" in out.path[-1]
    t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    circle = np.column_stack([5e-3 * np.cos(t), 5e-3 * np.sin(t)]) + rng.normal(0, 2e-5, (600, 2))
    assert refine_with_outline(dec, circle, closed=True) == dec
    assert refine_with_outline(dec, stadium, closed=False) == dec
    step = TypeDecision("step", 0.8, {"step": 0.8}, ())
    assert refine_with_outline(step, stadium, closed=True) == step


def _v_ridge_outline(width: float = 3.5e-3) -> np.ndarray:
    """The outline of scenarios/curved_ridge.yaml's V-shaped crest seen through the ball: the
    crest polyline dilated by ``width`` [m], sampled every 0.1 mm."""
    import shapely

    crest = shapely.LineString(((-0.012, -0.010), (0.006, -0.004), (-0.008, 0.010)))
    ring = shapely.segmentize(crest.buffer(width, quad_segs=32).exterior, 1e-4)
    return np.asarray(ring.coords)[:-1]


def test_outline_thinness_closed_forms():
    """Area over the largest inscribed disc's: 1 for a disc, 1 + 2 L / (pi w) for a stadium
    of half-width w and straight length L; a bent ridge stays thin where its area moments
    are nearly round."""
    from planner.exploration.surface.identify import outline_elongation, outline_thinness

    t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    disc = np.column_stack([4e-3 * np.cos(t), 4e-3 * np.sin(t)])
    assert outline_thinness(disc, 4e-3) == pytest.approx(1.0, rel=1e-5)
    half, rho = 6e-3, 2e-3
    expected = 1 + 2 * (2 * half) / (np.pi * rho)
    assert outline_thinness(_stadium_outline(half, rho, 4000), rho) == pytest.approx(
        expected, rel=1e-3
    )
    v = _v_ridge_outline()
    assert outline_elongation(v) < 1.4 < 2.0 < outline_thinness(v, 3.5e-3)
    assert np.isnan(outline_thinness(disc[:3], 4e-3)) and np.isnan(outline_thinness(disc, 0.0))


def test_a_closed_outline_rules_out_a_step():
    """A sharply bent ridge's across crossing ran over both arms and read a level change
    (step); its outline closed around it: the posterior without the step, then the outline's
    shape (thin: ridge; round: bump). An open outline keeps the step."""
    from planner.exploration.surface.identify import TypeDecision, refine_with_outline

    dec = TypeDecision("step", 0.8, {"step": 0.8, "bump": 0.12, "ridge": 0.05, "pit": 0.03}, ())
    out = refine_with_outline(dec, _v_ridge_outline(), closed=True)
    assert out.kind == "ridge" and out.scores["step"] == 0.0
    assert out.confidence == pytest.approx(0.12 / 0.2) and sum(out.scores.values()) == (
        pytest.approx(1.0)
    )
    assert "not a step" in out.path[0] and "thinness" in out.path[1]
    t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    circle = np.column_stack([5e-3 * np.cos(t), 5e-3 * np.sin(t)])
    assert refine_with_outline(dec, circle, closed=True).kind == "bump"
    assert refine_with_outline(dec, _v_ridge_outline(), closed=False) == dec


def test_lone_foot_detection_spans_the_feature():
    """Through the 8 mm ball a wide ridge's crest reads flatter than 1/r_f: the detector may
    see only its concave foot; the detection then reaches to the crest of the crossing."""
    from planner.exploration.surface.detection_adapter import PathAnalysis, PathFeature
    from planner.exploration.surface.online import _with_relief_extreme

    s = np.linspace(0.0, 0.03, 301)
    w = 0.008 + 0.003 * np.exp(-((s - 0.015) ** 2) / (2 * 0.004**2))
    uv = np.column_stack([s, np.zeros_like(s)])
    foot = PathFeature(-1, 0.006, 0.005, 0.007, uv[60], 60.0)
    a = PathAnalysis((foot,), "-", s, w, uv)
    pts = _with_relief_extreme(np.array([foot.point]), [foot], a, 0.008)
    assert len(pts) == 2 and pts[1][0] == pytest.approx(0.015, abs=2e-4)  # the crest
    top = PathFeature(1, 0.015, 0.013, 0.017, uv[150], 150.0)
    both = np.array([foot.point, top.point])
    assert _with_relief_extreme(both, [foot, top], a, 0.008) is both  # a full pattern: as is
    flat = PathAnalysis((foot,), "-", s, np.full_like(s, 0.008), uv)
    assert len(_with_relief_extreme(np.array([foot.point]), [foot], flat, 0.008)) == 1
    climbing = PathAnalysis((foot,), "-", s[:140], w[:140], uv[:140])  # still on the flank
    assert _with_relief_extreme(np.array([foot.point]), [foot], climbing, 0.008) is None


def test_a_noisy_small_round_outline_stays_a_pit():
    """The medial axis of a 2 mm circle with 0.4 mm lobes (three, as a lagging servo leaves
    them) grows branches longer than its radius; its enclosed area stays round (elongation
    ~1), so the pit is not turned into a ravine."""
    from planner.exploration.surface.identify import (
        TypeDecision,
        outline_elongation,
        refine_with_outline,
    )

    rng = np.random.default_rng(5)
    t = np.linspace(0, 2 * np.pi, 800, endpoint=False)
    r = 2e-3 + 4e-4 * np.sin(3 * t + 0.4) + rng.normal(0, 5e-5, t.size)
    ring = np.column_stack([r * np.cos(t), r * np.sin(t)])
    assert outline_elongation(ring) < 1.2
    dec = TypeDecision("pit", 0.88, {"pit": 0.88, "ravine": 0.1}, ())
    assert refine_with_outline(dec, ring, closed=True) == dec
    no_area = refine_with_outline(dec, ring, closed=True, min_area_elongation=0.0)
    assert no_area.kind == "ravine"  # the skeleton test alone is fooled
