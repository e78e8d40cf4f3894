"""Claims whose capability is not in hapex yet say so instead of failing."""

from __future__ import annotations

from importlib import import_module

from planner.reproduce.claim import NotImplementedClaim

__all__ = ["require"]


def require(module: str, name: str):
    """Return ``module.name`` or raise :class:`NotImplementedClaim` when it does not exist."""
    try:
        return getattr(import_module(module), name)
    except (ImportError, AttributeError) as exc:
        raise NotImplementedClaim(f"{module}.{name} is not implemented yet ({exc})") from None
