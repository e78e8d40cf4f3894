"""Joining the :class:`planner.sim.SimLog` of consecutive phases into one log."""

from __future__ import annotations

import numpy as np


def concat_logs(logs: list):
    """One ``SimLog`` holding ``logs`` back to back (the first row of every later log, a
    repeat of the previous log's last row, is dropped; contact pairs are re-indexed)."""
    from planner.sim import SimLog

    if not logs:
        raise ValueError("no logs to join")
    if len(logs) == 1:
        return logs[0]
    pairs: list[str] = []
    for lg in logs:
        for p in lg.pairs:
            if p not in pairs:
                pairs.append(p)
    parts = [lg if i == 0 else _tail(lg) for i, lg in enumerate(logs)]
    cp = []
    for lg, part in zip(logs, parts, strict=True):
        remap = np.array([pairs.index(p) for p in lg.pairs] + [-1])
        idx = _get(part, "contact_pair")
        cp.append(np.where(idx >= 0, remap[np.where(idx >= 0, idx, -1)], -1))

    def cat(key):
        return np.concatenate([p[key] if isinstance(p, dict) else getattr(p, key) for p in parts])

    out = SimLog(
        t=cat("t"),
        poses={k: np.concatenate([_get(p, "poses")[k] for p in parts]) for k in logs[0].poses},
        velocities={
            k: np.concatenate([_get(p, "velocities")[k] for p in parts]) for k in logs[0].velocities
        },
        q=cat("q"), qd=cat("qd"), tau=cat("tau"), contact_count=cat("contact_count"),
        contact_pair=np.concatenate(cp), contact_point=cat("contact_point"),
        contact_normal=cat("contact_normal"), normal_force=cat("normal_force"),
        tangential_force=cat("tangential_force"), slip_velocity=cat("slip_velocity"),
        gap=cat("gap"), pairs=pairs, events=[e for lg in logs for e in lg.events],
        status=logs[-1].status, reason=logs[-1].reason,
    )  # fmt: skip
    out.n = len(out.t)
    return out


_KEYS = ("t", "q", "qd", "tau", "contact_count", "contact_pair", "contact_point",
         "contact_normal", "normal_force", "tangential_force", "slip_velocity", "gap")  # fmt: skip


def _tail(lg) -> dict:
    d = {k: getattr(lg, k)[1:] for k in _KEYS}
    d["poses"] = {k: v[1:] for k, v in lg.poses.items()}
    d["velocities"] = {k: v[1:] for k, v in lg.velocities.items()}
    return d


def _get(part, key):
    return part[key] if isinstance(part, dict) else getattr(part, key)


__all__ = ["concat_logs"]
