"""Feature detection from fingertip data (thesis §3.3-3.5, App. B).

Public API:

- :func:`detect_features` — curvature features with one of the four algorithms of Fig. 3.8;
- :func:`macro_features` — group them into macro features (Table 3.1);
- :func:`noise_analysis` — the chi-squared normality test of App. B.1;
- :func:`smooth` — noise-type filters (average, median, dual-point, Gaussian, Wiener);
- :func:`b2_scheme` — the App. B.2 detection scheme used to rate filters;
- :func:`curvature_limit_smoothing` — §3.3.3 smoothing by curvature limitations;
- :func:`detect_multiscale` — re-detection for virtual fingertips r_i >= r_f (§3.2.2);
- :func:`score_features` — precision/recall/F1/localization against ground truth;
- :func:`read_trace_file` — users' CSV/NPZ logs.
"""

from importlib import import_module
from typing import TYPE_CHECKING

_LAZY = {
    "ALGORITHMS": "algorithms",
    "curvature_signal": "algorithms",
    "detect_features": "algorithms",
    "CurvatureLimited": "curvature_limit",
    "curvature_limit_smoothing": "curvature_limit",
    "FingertipData": "datafile",
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
    "FILTERS": "smoothing",
    "smooth": "smoothing",
    "CurvatureFeature": "types",
    "CurvatureSignal": "types",
    "MacroFeature": "types",
}


def __getattr__(name: str):
    """Import submodules on first use (keeps ``import planner.detection`` light: scipy.stats
    is only loaded by ``noise_analysis``)."""
    if name in _LAZY:
        value = getattr(import_module(f"planner.detection.{_LAZY[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'planner.detection' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)


if TYPE_CHECKING:  # pragma: no cover
    from planner.detection.algorithms import ALGORITHMS, curvature_signal, detect_features
    from planner.detection.curvature_limit import CurvatureLimited, curvature_limit_smoothing
    from planner.detection.datafile import FingertipData, read_trace_file
    from planner.detection.macro import classify_signs, macro_features
    from planner.detection.multiscale import detect_multiscale
    from planner.detection.noise import NoiseAnalysis, noise_analysis
    from planner.detection.scheme_b2 import SchemeResult, b2_scheme
    from planner.detection.scoring import Score, score_features
    from planner.detection.smoothing import FILTERS, smooth
    from planner.detection.types import CurvatureFeature, CurvatureSignal, MacroFeature

__all__ = [
    "ALGORITHMS",
    "FILTERS",
    "CurvatureFeature",
    "CurvatureLimited",
    "CurvatureSignal",
    "FingertipData",
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
    "smooth",
]
