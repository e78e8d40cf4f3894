"""Geometry of objects and fingertips: 2-D profiles and their parallel/traced/estimated curves
(``curves``), parametric surfaces (``surfaces``), and curvature/macro feature definitions
(``features``) of thesis §3.2."""
