"""The record of a run: preallocated arrays, events, status (issue 15, item 4).

Arrays are allocated once for the whole run (``n_rows`` = steps + 1) and trimmed to the rows
actually written when the run ends (early stops included), as MuJoCo users do with
``MjData`` rollouts: nothing grows inside the loop.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from planner.sim.events import SimEvent

__all__ = ["SimLog"]


@dataclass
class SimLog:
    """Time series of a run.

    Attributes:
        t: (T,) time [s].
        poses: ``{body: (T, 3) (x, y, angle) planar [m, rad] | (T, 7) (xyz, quat wxyz)}``.
        velocities: ``{body: (T, 3) (vx, vy, omega) | (T, 6) (v, omega) in the world frame}``.
        q, qd: (T, n) joint angles [rad] and velocities [rad/s] of the hand/finger (true).
        tau: (T, n) joint torques (after saturation) held over the step that starts at
            ``t`` [N m] (the last row repeats the last command).
        contact_count: (T,) number of contact candidates at ``t`` (may exceed K).
        contact_pair: (T, K) index into ``pairs`` (-1: empty slot).
        contact_point, contact_normal: (T, K, d) [m], unit (see :class:`Contact`).
        normal_force: (T, K) [N]; tangential_force, slip_velocity: (T, K) planar or
            (T, K, 3) spatial [N], [m/s]; gap: (T, K) [m].
        pairs: ``"body_a|body_b"`` names of the contact pairs seen.
        events: the :class:`SimEvent` list.
        status: ``"ok"`` or ``"failed"``; reason: why the run stopped early ("" if not).
    """

    t: np.ndarray
    poses: dict[str, np.ndarray]
    velocities: dict[str, np.ndarray]
    q: np.ndarray
    qd: np.ndarray
    tau: np.ndarray
    contact_count: np.ndarray
    contact_pair: np.ndarray
    contact_point: np.ndarray
    contact_normal: np.ndarray
    normal_force: np.ndarray
    tangential_force: np.ndarray
    slip_velocity: np.ndarray
    gap: np.ndarray
    pairs: list[str] = field(default_factory=list)
    events: list[SimEvent] = field(default_factory=list)
    status: str = "ok"
    reason: str = ""
    n: int = 0

    @classmethod
    def allocate(
        cls,
        n_rows: int,
        bodies: tuple[str, ...],
        pose_size: int,
        velocity_size: int,
        n_joints: int,
        max_contacts: int = 8,
        dim: int = 2,
    ) -> SimLog:
        """Zero-filled arrays for ``n_rows`` rows (NaN for contact geometry)."""
        T, K = int(n_rows), int(max_contacts)
        tshape = (T, K) if dim == 2 else (T, K, 3)
        return cls(
            t=np.zeros(T),
            poses={b: np.zeros((T, pose_size)) for b in bodies},
            velocities={b: np.zeros((T, velocity_size)) for b in bodies},
            q=np.zeros((T, n_joints)),
            qd=np.zeros((T, n_joints)),
            tau=np.zeros((T, n_joints)),
            contact_count=np.zeros(T, np.int32),
            contact_pair=np.full((T, K), -1, np.int32),
            contact_point=np.full((T, K, dim), np.nan),
            contact_normal=np.full((T, K, dim), np.nan),
            normal_force=np.zeros((T, K)),
            tangential_force=np.zeros(tshape),
            slip_velocity=np.zeros(tshape),
            gap=np.full((T, K), np.nan),
        )

    @property
    def max_contacts(self) -> int:
        """K, the contact slots per row."""
        return self.contact_pair.shape[1]

    def pair_index(self, a: str, b: str) -> int:
        """Index of the pair ``a|b`` in :attr:`pairs` (added when new)."""
        key = f"{a}|{b}"
        try:
            return self.pairs.index(key)
        except ValueError:
            self.pairs.append(key)
            return len(self.pairs) - 1

    def write_contacts(self, k: int, contacts) -> None:
        """Row ``k``'s contact slots from contact records (``.bodies``, ``.point`` [m],
        ``.normal``, ``.normal_force`` [N], ``.tangential_force`` [N], ``.slip_velocity``
        [m/s], ``.gap`` [m]); records beyond :attr:`max_contacts` are counted, not stored."""
        self.contact_count[k] = len(contacts)
        for i, c in enumerate(contacts[: self.max_contacts]):
            self.contact_pair[k, i] = self.pair_index(*c.bodies)
            self.contact_point[k, i] = c.point
            self.contact_normal[k, i] = c.normal
            self.normal_force[k, i] = c.normal_force
            self.tangential_force[k, i] = c.tangential_force
            self.slip_velocity[k, i] = c.slip_velocity
            self.gap[k, i] = c.gap

    def pair_mask(self, a: str, b: str) -> np.ndarray:
        """(T, K) True where the slot holds a contact between ``a`` and ``b`` (either order)."""
        idx = [i for i, p in enumerate(self.pairs) if p in (f"{a}|{b}", f"{b}|{a}")]
        return np.isin(self.contact_pair, idx)

    def trim(self, n: int) -> None:
        """Keep the first ``n`` rows (called by the run loop when it ends)."""
        self.n = int(n)
        for name in (
            "t",
            "q",
            "qd",
            "tau",
            "contact_count",
            "contact_pair",
            "contact_point",
            "contact_normal",
            "normal_force",
            "tangential_force",
            "slip_velocity",
            "gap",
        ):
            setattr(self, name, getattr(self, name)[:n])
        self.poses = {k: v[:n] for k, v in self.poses.items()}
        self.velocities = {k: v[:n] for k, v in self.velocities.items()}

    def arrays(self) -> dict[str, np.ndarray]:
        """Every array under a flat name (``pose/<body>``, ``velocity/<body>``, ...)."""
        out = {
            "t": self.t,
            "q": self.q,
            "qd": self.qd,
            "tau": self.tau,
            "contact_count": self.contact_count,
            "contact_pair": self.contact_pair,
            "contact_point": self.contact_point,
            "contact_normal": self.contact_normal,
            "normal_force": self.normal_force,
            "tangential_force": self.tangential_force,
            "slip_velocity": self.slip_velocity,
            "gap": self.gap,
            "pairs": np.array(self.pairs, dtype=str),
        }
        out.update({f"pose/{k}": v for k, v in self.poses.items()})
        out.update({f"velocity/{k}": v for k, v in self.velocities.items()})
        return out

    def save_npz(self, path: str | Path) -> Path:
        """Write every array, the events (JSON) and the status to ``path`` (.npz)."""
        path = Path(path)
        events = json.dumps([e.as_dict() for e in self.events])
        np.savez_compressed(
            path,
            **self.arrays(),
            events=np.array(events),
            status=np.array(self.status),
            reason=np.array(self.reason),
        )
        return path
