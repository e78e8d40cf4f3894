"""hapex planner: everything that is not a robot.

Library packages, one concept each (lower layers never import higher ones):

* ``geometry`` — curves, profiles, surfaces, offsets, curvature features;
* ``contact`` — Montana's contact kinematics, rolling, contact types, friction cones;
* ``optim`` — the one QP/LP entry point (validated problems, residuals, in-place solves);
* ``grasp`` — grasp matrix, force closure, quality, grasp/workspace maps, gait planning;
* ``control`` — controllers and the grasp-force distribution QP;
* ``sim`` — the contact simulator (worlds, per-step contact problem, sensors, logs);
* ``trajectory`` — the CasADi rolling-contact NLP (eqs. 2.3-2.4) and splines;
* ``exploration`` — ``explore_object`` (ch. 2 phase machine), ``explore_surface`` (ch. 4);
* ``detection`` — feature detection on fingertip traces (algorithms 1-4, smoothing);
* ``skeleton`` — shape skeletons (DVMA) and the global feature map.

The spine: ``kinds`` (one module per scenario kind), ``scenario`` (YAML loading and
validation), ``runner``/``runctx``/``results`` (running a kind, the run directory), ``cli``
(the ``hapex`` command), ``sweep`` (parameter studies); ``errors`` and ``checks`` are the
exception hierarchy and the argument checks every layer uses.
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("hapex")
except PackageNotFoundError:  # pragma: no cover - running from a source tree without install
    __version__ = "0.0.0+unknown"

__all__ = ["__version__"]
