"""benchmarks/bench_gait_friction.py: its two configurations and its summary."""

from __future__ import annotations

from conftest import benchmark_module


def test_the_configurations_differ_only_in_the_cap():
    bench = benchmark_module("bench_gait_friction")
    capped = bench._run(("capped", "circle_5cm", 2.0, 0, 0.3))
    full = bench._run(("full", "circle_5cm", 2.0, 0, 0.3))
    assert (capped["planning_mu"], full["planning_mu"]) == (0.8, 1.6)
    assert capped["mu"] == full["mu"] == 2.0
    assert capped["status"] == full["status"] == "ok"  # 0.3 s: cut by the duration
    assert not capped["full_turn"] and capped["turn_deg"] < 360


def test_the_summary_counts_full_turns_per_mu_and_configuration():
    bench = benchmark_module("bench_gait_friction")
    rows = [{"mu": 2.0, "config": "capped", "full_turn": True},
            {"mu": 2.0, "config": "capped", "full_turn": False},
            {"mu": 2.0, "config": "full", "full_turn": False},
            {"mu": 1.0, "config": "capped", "full_turn": True}]  # fmt: skip
    assert bench._summary(rows) == ["mu 1: full turns capped 1/1",
                                    "mu 2: full turns capped 1/2, full 0/1"]  # fmt: skip
