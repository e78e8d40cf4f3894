"""Feature detection from fingertip data (thesis §3.3-3.5, App. B).

- :func:`detect_features` — curvature features with one of the four algorithms of Fig. 3.8
  (settings: :class:`DetectionSettings`);
- :func:`macro_features` — group them into macro features (Table 3.1);
- :func:`noise_analysis` — the chi-squared normality test of App. B.1;
- :func:`smooth` — noise-type filters (average, median, dual-point, Gaussian, Wiener);
- :func:`b2_scheme` — the App. B.2 detection scheme used to rate filters;
- :func:`curvature_limit_smoothing` — §3.3.3 smoothing by curvature limitations;
- :func:`detect_multiscale` — re-detection for virtual fingertips r_i >= r_f (§3.2.2);
- :func:`score_features` — precision/recall/F1/localization against ground truth;
- :func:`read_trace_file` — users' CSV/NPZ logs as a :class:`FingertipTrace`;
  :func:`simulate_trace` — simulated traces over a profile, with ground truth.

The feature and trace types live in :mod:`planner.geometry` and are re-exported here.
"""

import importlib

#: where each public name lives; a submodule is imported on first use (PEP 562), so that
#: ``from planner.detection import detect_features`` does not load scipy.signal and
#: scipy.stats (1.5-2 s) for the smoothing and noise tools it does not use
_HOME = {
    "ALGORITHMS": "algorithms",
    "curvature_signal": "algorithms",
    "detect_features": "algorithms",
    "CurvatureLimited": "curvature_limit",
    "curvature_limit_smoothing": "curvature_limit",
    "read_trace_file": "datafile",
    "classify_signs": "macro",
    "macro_features": "macro",
    "detect_multiscale": "multiscale",
    "NoiseAnalysis": "noise",
    "noise_analysis": "noise",
    "SchemeResult": "scheme_b2",
    "b2_scheme": "scheme_b2",
    "Score": "scoring",
    "score_features": "scoring",
    "DetectionSettings": "settings",
    "FILTERS": "smoothing",
    "smooth": "smoothing",
    "CurvatureSignal": "types",
    "CurvatureFeature": "planner.geometry.features",
    "MacroFeature": "planner.geometry.features",
    "FingertipTrace": "planner.geometry.measurement",
    "simulate_trace": "planner.geometry.measurement",
}


def __getattr__(name: str):
    home = _HOME.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    module = importlib.import_module(home if "." in home else f"{__name__}.{home}")
    value = getattr(module, name)
    globals()[name] = value  # later lookups skip __getattr__
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


__all__ = [
    "ALGORITHMS",
    "FILTERS",
    "CurvatureFeature",
    "CurvatureLimited",
    "CurvatureSignal",
    "DetectionSettings",
    "FingertipTrace",
    "MacroFeature",
    "NoiseAnalysis",
    "SchemeResult",
    "Score",
    "b2_scheme",
    "classify_signs",
    "curvature_limit_smoothing",
    "curvature_signal",
    "detect_features",
    "detect_multiscale",
    "macro_features",
    "noise_analysis",
    "read_trace_file",
    "score_features",
    "simulate_trace",
    "smooth",
]

if sorted(_HOME) != sorted(__all__):  # pragma: no cover - a name added to one list only
    raise ImportError("planner.detection: _HOME and __all__ list different names")
