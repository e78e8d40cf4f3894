"""Where the bundled scenarios are (the source tree's ``scenarios/`` folder)."""

from __future__ import annotations

from pathlib import Path

from planner.reproduce.claim import NotImplementedClaim

__all__ = ["scenario_path"]


def scenario_path(name: str) -> Path:
    """The bundled scenario ``name`` (``scenarios/<name>.yaml``)."""
    path = Path(__file__).resolve().parents[2] / "scenarios" / f"{name}.yaml"
    if not path.is_file():
        raise NotImplementedClaim(f"bundled scenario {name!r} not found at {path}")
    return path
