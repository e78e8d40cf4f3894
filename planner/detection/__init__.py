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

from planner.detection.algorithms import ALGORITHMS, curvature_signal, detect_features
from planner.detection.curvature_limit import CurvatureLimited, curvature_limit_smoothing
from planner.detection.datafile import read_trace_file
from planner.detection.macro import classify_signs, macro_features
from planner.detection.multiscale import detect_multiscale
from planner.detection.noise import NoiseAnalysis, noise_analysis
from planner.detection.scheme_b2 import SchemeResult, b2_scheme
from planner.detection.scoring import Score, score_features
from planner.detection.settings import DetectionSettings
from planner.detection.smoothing import FILTERS, smooth
from planner.detection.types import CurvatureSignal
from planner.geometry.features import CurvatureFeature, MacroFeature
from planner.geometry.measurement import FingertipTrace, simulate_trace

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
