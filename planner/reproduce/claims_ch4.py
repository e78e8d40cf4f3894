"""Claims of chapter 4: type identification and boundary tracing by the 3GM, feature
skeletons (DVMA and its pruning) and the global skeleton (§4.4-§4.5, Figs. 4.7-4.15)."""

from __future__ import annotations

import numpy as np
from scipy.spatial.distance import directed_hausdorff

from planner.reproduce._library_figures import save_figure, save_panels
from planner.reproduce._plots import figure, save
from planner.reproduce._require import require
from planner.reproduce.claim import ClaimContext, Evidence, Number, verdict_from
from planner.reproduce.registry import claim


def _components(n: int, edges: np.ndarray) -> int:
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    e = np.asarray(edges, dtype=int).reshape(-1, 2)
    graph = coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n))
    return int(connected_components(graph, directed=False)[0])


def _hausdorff(a: np.ndarray, b: np.ndarray) -> float:
    return max(directed_hausdorff(a, b)[0], directed_hausdorff(b, a)[0])


def _plate(kind: str):
    from planner.sim.spatial.plate import Plate, PlateFeature

    return Plate((PlateFeature(kind, 0.001, 0.003, (0.0, 0.0)),))


_REGION = ((-0.012, 0.012), (-0.008, 0.008))


def _explore(kind: str, ctx: ClaimContext):
    explore_surface = require("planner.exploration", "explore_surface")
    return explore_surface(
        _plate(kind),
        region=_REGION,
        seed=ctx.seed,
        duration=0.5 if ctx.quick else None,
    )


def _top_view(kind: str, res, ctx: ClaimContext):
    """The exploration kind's top view of the run ``res`` on the plate with one ``kind``
    feature; the true outline is drawn in full runs only (it costs ~0.5 s a plate)."""
    from planner.exploration.surface.plates import truth_features
    from planner.exploration.surface.plots import top_view

    plate = _plate(kind)
    truth = None
    if not ctx.quick:
        truth = truth_features(plate, _REGION, res.settings.tip_radius, res.settings.boundary_rise)
    found = ", ".join(f.kind for f in res.features) or "none"
    title = f"{kind} plate: {res.status}, identified: {found}"
    return top_view(res, plate, _REGION, truth, title)


def _dvma_figure(boundary: np.ndarray, sk, title: str, path) -> str | None:
    """The skeleton package's DVMA figure (the Voronoi edges, the pruned skeleton) saved at
    ``path`` (nothing without a path)."""
    if path is None:
        return None
    from planner.skeleton.plots import dvma_figure

    return save_figure(dvma_figure(boundary, sk, title), path)


_QUICK = (
    "Quick mode searches for 0.5 s only (a smoke run that may meet no feature); run "
    "`hapex reproduce --only <id>` for the full exploration. "
)


@claim(
    "fig4.7",
    "Fig. 4.7, §4.4.1",
    "Following the flow chart of Fig. 4.7, the finger identifies a cusp, a step and a ridge "
    "from the curvature features it meets while crossing them.",
    ["planner.exploration.explore_surface", "scenarios/ridge_plate.yaml"],
    "Flow chart: cross the feature, count curvature features and their signs, decide.",
)
def fig4_7(ctx: ClaimContext) -> Evidence:
    nums, views = [], []
    for kind in ("cusp", "step", "ridge"):
        res = _explore(kind, ctx)
        if ctx.figures is not None:
            views.append(_top_view(kind, res, ctx))
        kinds = [f.kind for f in res.features]
        nums.append(
            Number(
                f"{kind}: identified as",
                str(kinds),
                f"['{kind}']",
                kinds[:1] == [kind],
                f"status {res.status} {res.reason or ''}",
            )
        )
    verdict, nums = verdict_from(nums)
    return Evidence(
        verdict,
        nums,
        (_QUICK if ctx.quick else "") + "3GM with OWTS under "
        "hybrid force/velocity control in the spatial simulator.",
        save_panels(views, ["cusp", "step", "ridge"], ctx.figure_path("fig4.7")),
    )


@claim(
    "fig4.8",
    "Fig. 4.8, §4.4.2",
    "Tracing a feature along the intersection of the plane parallel to the surface and the "
    "plane orthogonal to the contact normal follows its boundary and closes the loop.",
    ["planner.exploration.explore_surface", "scenarios/ridge_plate.yaml"],
    "The direction of travel during tracing from the two planes.",
)
def fig4_8(ctx: ClaimContext) -> Evidence:
    res = _explore("bump", ctx)
    figure_name = None
    if ctx.figures is not None:
        figure_name = save_figure(_top_view("bump", res, ctx), ctx.figure_path("fig4.8"))
    closed = bool(res.features and res.features[0].closed)
    nums = [
        Number("boundary closed", closed, True, closed, f"status {res.status}"),
        Number("run status", res.status, "ok", res.status == "ok", res.reason or ""),
    ]
    verdict, nums = verdict_from(nums)
    return Evidence(
        verdict,
        nums,
        (_QUICK if ctx.quick else "") + "Boundary of a 2 mm bump traced in the spatial simulator.",
        figure_name,
    )


@claim(
    "fig4.11",
    "Fig. 4.11, §4.4.3",
    "As the number of boundary samples grows, the discrete Voronoi medial axis approaches "
    "the continuous medial axis.",
    ["planner.skeleton.feature_skeleton"],
    "DVMA of a feature with few and many boundary samples beside the continuous axis.",
)
def fig4_11(ctx: ClaimContext) -> Evidence:
    from planner.skeleton import feature_skeleton
    from planner.skeleton.shapes import ellipse_medial_axis, ellipse_outline

    a, b = 0.02, 0.008
    truth = ellipse_medial_axis(a, b)
    spacings = (0.002, 0.001, 0.0005) if ctx.quick else (0.002, 0.001, 0.0005, 0.00025)
    errs = []
    fig, ax = figure()
    for sp in spacings:
        sk = feature_skeleton(ellipse_outline(a, b, sp), spacing=sp)
        errs.append(_hausdorff(sk.points, truth))
        ax.plot(
            sk.points[:, 0] * 1e3,
            sk.points[:, 1] * 1e3,
            ".",
            ms=2,
            label=f"spacing {sp * 1e3:g} mm",
        )
    ax.plot(truth[:, 0] * 1e3, truth[:, 1] * 1e3, "k-", lw=0.8, label="medial axis")
    ax.set_aspect("equal")
    ax.legend(fontsize=7)
    decreasing = all(e2 <= e1 * 1.05 for e1, e2 in zip(errs, errs[1:], strict=False))
    verdict, nums = verdict_from(
        [
            Number(
                "Hausdorff to the true axis, finest [m]",
                errs[-1],
                None,
                errs[-1] < 0.15 * b,
                "< 0.15 b",
            ),
            Number("error shrinks with denser samples", decreasing, True, decreasing),
        ]
    )
    return Evidence(
        verdict,
        nums,
        "Ellipse 40 x 16 mm; exact medial axis as reference.",
        save(fig, ctx.figure_path("fig4.11")),
    )


@claim(
    "fig4.12",
    "Fig. 4.12, §4.4.3",
    "For non-branching features the unwanted skeleton arcs are pruned, leaving one path.",
    ["planner.skeleton.feature_skeleton"],
    "Examples of branching and non-branching features with their skeletons; when only "
    "non-branching features are considered, the unwanted skeleton arcs are pruned away.",
)
def fig4_12(ctx: ClaimContext) -> Evidence:
    from planner.skeleton import feature_skeleton
    from planner.skeleton.shapes import rectangle_outline

    w, h, sp = 0.05, 0.008, 0.0005
    boundary = rectangle_outline(w, h, sp)
    sk = feature_skeleton(boundary, spacing=sp, branching=False)
    figure_name = _dvma_figure(
        boundary, sk, "50 x 8 mm ridge, non-branching: one path", ctx.figure_path("fig4.12")
    )
    ends, branches = len(sk.end_points), len(sk.branch_points)
    ratio = sk.length / (w - h + h * np.sqrt(2))
    verdict, nums = verdict_from(
        [
            Number("end points", ends, 2, ends == 2, "== 2"),
            Number("branch points", branches, 0, branches == 0, "== 0"),
            Number(
                "skeleton length / (w - h + h sqrt 2)",
                ratio,
                1.0,
                abs(ratio - 1) < 0.05,
                "|d| < 0.05",
            ),
        ]
    )
    return Evidence(
        verdict,
        nums,
        "50 x 8 mm ridge, non-branching: the side branches are pruned and one path remains, "
        "the longest path of the rectangle's medial axis (corner, central segment w - h, "
        "opposite corner: w - h + h sqrt 2).",
        figure_name,
    )


@claim(
    "fig4.13",
    "Fig. 4.13, §4.4.3",
    "When a feature turns sharply, extra disconnected skeletons appear and the largest "
    "connected skeleton is the feature's skeleton.",
    ["planner.skeleton.feature_skeleton", "scenarios/curved_ridge_skeleton.yaml"],
    "A sharply turning feature in three steps: the Voronoi diagram of its boundary "
    "samples, the skeletons extracted with an edge length threshold (extra ones outside "
    "the turn), and the final skeleton, the one with the most edges.",
)
def fig4_13(ctx: ClaimContext) -> Evidence:
    from planner.skeleton import feature_skeleton
    from planner.skeleton.shapes import ridge_polygon, sample_outline

    turn = np.deg2rad(155.0)
    arm = 0.03
    center = np.array(
        [[-arm, 0.0], [0.0, 0.0], [arm * np.cos(np.pi - turn), arm * np.sin(np.pi - turn)]]
    )
    sp = 0.0004
    pts = sample_outline(ridge_polygon(center, 0.006), sp, noise=3e-5, rng=ctx.rng())
    sk = feature_skeleton(pts, spacing=sp)
    figure_name = _dvma_figure(
        pts, sk, "ridge turning by 155 deg: the largest skeleton kept", ctx.figure_path("fig4.13")
    )
    from shapely import LineString, Point

    line = LineString(center)
    dev = max(line.distance(Point(p)) for p in sk.points)
    parts = _components(sk.points.shape[0], sk.edges)
    verdict, nums = verdict_from(
        [
            Number("connected skeletons kept", parts, 1, parts == 1, "== 1 (keep the largest)"),
            Number(
                "max distance from the centre line [m]",
                dev,
                None,
                dev < 0.0015,
                "< 1.5 mm (a quarter of the width)",
            ),
            Number("end points", len(sk.end_points), 2, len(sk.end_points) == 2, "== 2"),
        ]
    )
    return Evidence(
        verdict, nums, "Two 30 mm arms meeting at a 155 deg turn, 6 mm wide.", figure_name
    )


@claim(
    "fig4.14-4.15",
    "Figs. 4.14-4.15, §4.5.3",
    "The global skeleton, from the Voronoi diagram of the features, runs midway between "
    "features and divides the surface into one region per feature.",
    ["planner.skeleton.global_skeleton"],
    "Regions around features bounded by the global skeleton.",
)
def fig4_14(ctx: ClaimContext) -> Evidence:
    from planner.skeleton import global_skeleton
    from planner.skeleton.shapes import rectangle_outline

    a = rectangle_outline(0.05, 0.008, 0.0005)
    b = a + [0.0, 0.018]
    gs = global_skeleton([a, b])
    mid = float(np.max(np.abs(gs.points[:, 1] - 0.009)))
    fig, ax = figure()
    for poly in gs.regions:
        x, y = poly.exterior.xy
        ax.fill(np.asarray(x) * 1e3, np.asarray(y) * 1e3, alpha=0.3)
    for bd in (a, b):
        ax.plot(bd[:, 0] * 1e3, bd[:, 1] * 1e3, "k.", ms=1)
    ax.plot(gs.points[:, 0] * 1e3, gs.points[:, 1] * 1e3, "r.", ms=2)
    ax.set_aspect("equal")
    verdict, nums = verdict_from(
        [
            Number(
                "clearance [m]",
                float(gs.clearance),
                0.005,
                abs(gs.clearance - 0.005) < 1e-6,
                "|d| < 1 um",
            ),
            Number("max distance from the mid-line [m]", mid, 0.0, mid < 1e-6, "< 1 um"),
            Number("regions", len(gs.regions), 2, len(gs.regions) == 2, "== 2"),
        ]
    )
    return Evidence(
        verdict,
        nums,
        "Two parallel 50 x 8 mm ridges, 10 mm apart.",
        save(fig, ctx.figure_path("fig4.14-4.15")),
    )
