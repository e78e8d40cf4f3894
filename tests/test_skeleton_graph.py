"""Skeleton graph helpers and segment helpers: arcs, pruning, paths, merging, clipping."""

import numpy as np
import pytest

from planner.skeleton import graph as g
from planner.skeleton.segments import clip_segments, merge_segments, point_segment_distance


def star(arm_lengths):
    """A star: centre node 0 and one straight arm of several unit-step nodes per length."""
    pts, edges = [np.zeros(2)], []
    for k, L in enumerate(arm_lengths):
        d = np.array([np.cos(k), np.sin(k)])
        prev = 0
        for step in range(1, L + 1):
            pts.append(step * d)
            edges.append((prev, len(pts) - 1))
            prev = len(pts) - 1
    return np.array(pts), np.array(edges)


def test_arcs_of_a_star():
    pts, edges = star([3, 5, 1])
    n, labels = g.arc_labels(len(pts), edges)
    assert n == 3
    lab, arc_len, term = g.terminal_arcs(len(pts), edges, g.edge_lengths(pts, edges))
    assert sorted(arc_len.round(9)) == [1, 3, 5] and term.all()


def test_prune_terminal_arcs_removes_short_spurs_only():
    pts, edges = star([6, 7, 2])
    keep = g.prune_terminal_arcs(pts, edges, min_length=3.0)
    assert keep.sum() == 13  # the 2-long arm is gone, the others merge into one arc
    keep_all = g.prune_terminal_arcs(pts, edges, min_length=100.0)
    assert keep_all.sum() == 7  # all arms short: only the longest survives


def test_longest_path_and_path_edges():
    pts, edges = star([4, 6, 2])
    path = g.longest_path(pts, edges)
    assert len(path) == 11 and {path[0], path[-1]} == {4, 10}
    assert g.path_edges(path).shape == (10, 2)


def test_largest_component_and_cycles():
    edges = np.array([[0, 1], [1, 2], [3, 4], [4, 5], [5, 6], [6, 3]])
    pts = np.random.default_rng(0).random((7, 2))
    mask = g.largest_component_mask(7, edges)
    assert mask.tolist() == [False, False, True, True, True, True]
    assert g.has_cycle(7, edges) and not g.has_cycle(7, edges[:2])
    assert g.component_labels(7, edges)[0] == 2
    assert pts.shape == (7, 2)


def test_merge_close_points_and_compact():
    pts = np.array([[0, 0], [1, 0], [1 + 1e-13, 0], [2, 0], [5, 5]])
    edges = np.array([[0, 1], [2, 3], [1, 2]])
    p, e, src = g.merge_close_points(pts, edges, 1e-9)
    assert len(p) == 3 and len(e) == 2 and src.tolist() == [0, 1]
    assert g.degrees(len(p), e).tolist() == [1, 2, 1]


def test_clip_segments_against_box():
    seg = np.array(
        [[[-1, 0.5], [2, 0.5]], [[0.2, 0.2], [0.4, 0.6]], [[2, 2], [3, 3]], [[0.5, -1], [0.5, 0.5]]]
    )
    out, inside = clip_segments(seg, (0, 0, 1, 1))
    assert inside.tolist() == [True, True, False, True]
    assert np.allclose(out[0], [[0, 0.5], [1, 0.5]])
    assert np.allclose(out[1], seg[1])
    assert out[3, 0, 1] == 0.0  # exactly on the border


def test_merge_segments_and_point_segment_distance():
    seg = np.array([[[0, 0], [1, 0]], [[1, 0], [1, 1]]], dtype=float)
    p, e = merge_segments(seg)
    assert len(p) == 3 and e.shape == (2, 2)
    d = point_segment_distance(np.array([[0.5, 1.0], [3.0, 1.0]]), seg)
    assert d == pytest.approx([1.0, 2.0])
