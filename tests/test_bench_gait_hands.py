"""benchmarks/bench_gait_hands.py: its hand grid (the gait's hand in it, the left finger the
right one's mirror image), one study row against map space, and its notes."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from conftest import benchmark_module


@pytest.fixture(scope="module")
def study():
    return benchmark_module("bench_gait_hands")


def test_the_grid_starts_with_the_gait_hand(study):
    from robots.planar_hand.params import gait_hand_params

    specs = study.grid(quick=False)
    assert len(specs) == len(set(specs)) == 72 * 3
    assert specs[0].is_gait_hand and not any(s.is_gait_hand for s in specs[1:])
    assert specs[0].hand(0.7).params == gait_hand_params(0.7)
    quick = study.grid(quick=True)
    assert quick == specs[:3] and all(s.is_gait_geometry for s in quick)
    assert [s.left_tip for s in quick] == ["flat pad", "round 2.5 cm", "round 1.5 cm"]
    assert sum(s.is_gait_geometry for s in specs) == 3


def test_a_round_left_tip_changes_only_the_left_tip(study):
    """The round-tipped variant of the gait's hand: the left finger's tip is a disc of the
    given radius, everything else the gait's hand."""
    from robots.planar_hand.params import gait_hand_params

    spec = study.grid(quick=True)[2]
    p, ref = spec.hand(1.0).params, gait_hand_params(1.0)
    assert (p.left.tip, p.left.tip_radius) == ("round", 0.015)
    assert replace(p.left, tip=ref.left.tip, tip_radius=ref.left.tip_radius) == ref.left
    assert p.right == ref.right and not spec.is_gait_hand


def test_a_grid_hand_is_mirrored_and_changes_only_its_three_parameters(study):
    from robots.planar_hand.params import gait_hand_params

    spec = study.HandSpec(0.06, 0.12, (-90.0, 120.0))
    p, ref = spec.hand(1.0).params, gait_hand_params(1.0)
    assert p.right.base == (0.06, 0.0) and p.left.base == (-0.06, 0.0)
    assert p.right.lengths == p.left.lengths == (0.12, *ref.right.lengths[1:])
    assert np.rad2deg([p.right.lower[0], p.right.upper[0]]) == pytest.approx([-90.0, 120.0])
    assert p.left.lower == tuple(-v for v in p.right.upper)
    assert p.left.upper == tuple(-v for v in p.right.lower)
    assert p.right.lower[1:] == ref.right.lower[1:] and p.right.upper[1:] == ref.right.upper[1:]
    assert replace(p.right, base=ref.right.base, lengths=ref.right.lengths, lower=ref.right.lower,
                   upper=ref.right.upper) == ref.right  # fmt: skip
    assert p.palm_half_width == ref.palm_half_width and p.friction == 1.0


def test_a_study_row_counts_full_turns_from_rest(study):
    """The gait's hand on the quick batch: the row's counts are start_reach's."""
    from planner.exploration.planar.start_reach import start_reach

    bench_gait = benchmark_module("bench_gait")

    spec = study.grid(quick=True)[0]
    row = study.study_hand((spec, 0.8, 0.01, True))
    hand = bench_gait.batch_hand(0.8)
    for fam in {o.family for o in bench_gait.objects(True)}:
        objs = [o for o in bench_gait.objects(True) if o.family == fam]
        full = sum(start_reach(o.profile, hand, 0.8, min_epsilon=0.01).full_turn for o in objs)
        assert row[fam] == f"{full}/{len(objs)}"
    assert row["gait_hand"] == "yes" and (row["mu"], row["min_epsilon"]) == (0.8, 0.01)
    assert row["left_tip"] == "flat pad"
    assert row["circle"] == "2/2"  # the quick batch's circles (2 and 6 cm) turn fully


def test_the_notes_name_the_best_hands_per_square_family(study):
    def row(mu, eps, gait, base, sharp):
        return {"mu": mu, "min_epsilon": eps, "gait_hand": "yes" if gait else "",
                "base_x_cm": base, "link1_cm": 8, "joint1_deg": "-90..90",
                "square sharp": sharp, "circle": "7/7"}  # fmt: skip

    rows = [row(1.0, 0.0, True, 10, "0/6"), row(1.0, 0.0, False, 6, "2/6"),
            row(0.8, 0.01, True, 10, "0/6"), row(0.8, 0.0, True, 10, "1/6")]  # fmt: skip
    notes = study.summary(rows, ["circle", "square sharp"])  # one left tip: not named
    assert notes == [
        "mu 1, the gait's hand: circle 7/7, square sharp 0/6",
        "mu 1, square sharp: at most 2/6 full turns over the 2 hands (1 hand, e.g. base 6 cm, "
        "link 1 8 cm, joint 1 -90..90 deg)",
        "mu 0.8, the gait's hand: circle 7/7, square sharp 1/6",
        "mu 0.8, square sharp: at most 1/6 full turns over the 1 hand (1 hand, e.g. base 10 "
        "cm, link 1 8 cm, joint 1 -90..90 deg)",
        "mu 0.8, epsilon >= 0.01, the gait's hand: circle 7/7, square sharp 0/6",
        "mu 0.8, epsilon >= 0.01, square sharp: at most 0/6 full turns over the 1 hand",
    ]


def test_the_notes_name_the_left_tip_when_the_study_varies_it(study):
    rows = [{"mu": 0.8, "min_epsilon": 0.01, "gait_hand": "yes", "left_tip": tip,
             "base_x_cm": 10, "link1_cm": 10, "joint1_deg": "-40..90", "square rounded": n}
            for tip, n in (("flat pad", "0/5"), ("round 2.5 cm", "4/5"))]  # fmt: skip
    assert study.summary(rows, ["square rounded"]) == [
        "mu 0.8, epsilon >= 0.01, left flat pad, the gait's hand: square rounded 0/5",
        "mu 0.8, epsilon >= 0.01, left flat pad, square rounded: at most 0/5 full turns over "
        "the 1 hand",
        "mu 0.8, epsilon >= 0.01, left round 2.5 cm, the gait's geometry: square rounded 4/5",
        "mu 0.8, epsilon >= 0.01, left round 2.5 cm, square rounded: at most 4/5 full turns "
        "over the 1 hand (1 hand, e.g. base 10 cm, link 1 10 cm, joint 1 -40..90 deg)",
    ]
