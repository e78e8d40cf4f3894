"""hapex planner: everything that is not a robot.

Sub-packages hold one concept each: ``geometry`` (curves, surfaces, features), ``contact``,
``grasp``, ``control``, ``trajectory``, ``exploration``, ``detection``, ``skeleton``, ``sim``;
``scenario``, ``cli`` and ``results`` form the command-line spine.
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("hapex")
except PackageNotFoundError:  # pragma: no cover - running from a source tree without install
    __version__ = "0.0.0+unknown"

__all__ = ["__version__"]
