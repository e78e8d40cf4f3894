"""Figures of the ``contact_sim`` kind: trajectories, contact forces, slip."""

from __future__ import annotations

import numpy as np


def figures(name: str, log) -> dict:
    """``{"trajectories", "contact_forces", "slip"}`` matplotlib figures of a :class:`SimLog`."""
    import matplotlib.pyplot as plt

    out = {}
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for body, p in log.poses.items():
        ax[0].plot(p[:, 0] * 1e3, p[:, 1] * 1e3, label=body)
        ax[1].plot(log.t, np.unwrap(p[:, 2]), label=body)
    if log.q.shape[1]:
        for k in range(log.q.shape[1]):
            ax[1].plot(log.t, log.q[:, k], "--", lw=0.8, label=f"q{k + 1}")
    ax[0].set(xlabel="x [mm]", ylabel="y [mm]", title=f"{name}: paths", aspect="equal")
    ax[1].set(xlabel="t [s]", ylabel="angle [rad]", title="angles")
    for a in ax:
        a.legend(fontsize=7)
    fig.tight_layout()
    out["trajectories"] = fig
    for key, ylabel in (("normal_force", "normal force [N]"), ("slip_velocity", "slip [m/s]")):
        fig, axes = plt.subplots(figsize=(7, 4))
        data = getattr(log, key)
        if data.ndim == 3:
            data = np.linalg.norm(data, axis=2)
        for k, pair in enumerate(log.pairs):
            m = log.contact_pair == k
            series = np.where(m, data, 0.0).sum(axis=1)
            axes.plot(log.t, series, label=pair)
        if key == "normal_force":
            tf = log.tangential_force
            tf = np.linalg.norm(tf, axis=2) if tf.ndim == 3 else np.abs(tf)
            for k, pair in enumerate(log.pairs):
                m = log.contact_pair == k
                axes.plot(log.t, np.where(m, tf, 0.0).sum(axis=1), ":", label=f"|f_t| {pair}")
        axes.set(xlabel="t [s]", ylabel=ylabel, title=f"{name}: {ylabel.split(' [')[0]}")
        axes.legend(fontsize=7)
        fig.tight_layout()
        out["contact_forces" if key == "normal_force" else "slip"] = fig
    return out
