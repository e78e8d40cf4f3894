"""planner.detection.plots: what the figures claim matches what they draw."""

import numpy as np
from feature_traces import feature_trace

from planner.detection import curvature_signal, detect_features, detect_multiscale
from planner.detection.algorithms import features_from_signal
from planner.detection.plots import multiscale_figure, signal_figure, trace_figure

R = 0.01


def _labels(fig) -> list[str]:
    return [t.get_text() for t in fig.axes[0].get_legend().get_texts()]


def test_trace_legend_mentions_truth_only_when_there_is_truth():
    # regression: the CSV `detect` plot's legend mentioned a truth that does not exist
    tr = feature_trace("step", 2e-3, seed=1)
    sig = curvature_signal(tr.centers, R, 3)
    feats = {3: features_from_signal(sig, sig.scale, R)}
    bare = trace_figure(tr.centers, {3: sig.surface}, feats, R)
    assert not any("truth" in s or "true" in s for s in _labels(bare))
    prof = tr.truth.profile.sample(1e-4).points
    full = trace_figure(
        tr.centers, {3: sig.surface}, feats, R, profile=prof, truth=tr.truth.observable
    )
    labels = _labels(full)
    assert "object profile (truth)" in labels and "true feature (observable)" in labels
    assert len(signal_figure({3: sig}, feats).axes) == 1


def test_multiscale_figure_has_one_row_per_radius():
    tr = feature_trace("step", 2e-3, seed=2)
    fs = detect_features(tr.centers, R)
    ms = detect_multiscale(tr.centers, R, [0.015, 0.025])
    fig = multiscale_figure({R: fs, **ms}, {R: ["step"], 0.015: ["step"], 0.025: ["step"]})
    ax = fig.axes[0]
    assert [t.get_text() for t in ax.get_yticklabels()] == [
        "r = 10 mm",
        "r = 15 mm",
        "r = 25 mm",
    ]
    # one peak marker per feature and radius (+ the two legend proxies)
    assert len(ax.lines) == sum(len(v) for v in ms.values()) + len(fs) + 2
    assert np.isfinite([f.peak for v in ms.values() for f in v]).all()
