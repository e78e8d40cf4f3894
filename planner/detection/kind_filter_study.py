"""The runner of the ``filter_study`` scenario kind (:mod:`planner.kinds.filter_study`)."""

from __future__ import annotations

import numpy as np

from planner.detection.filter_study import StudyTrace, grid, rate_filters
from planner.detection.synthetic import Shape, simulate
from planner.results import RunResult

#: the best settings App. B.4 reports
THESIS_GAUSSIAN = {"windows": (25, 40), "sigmas": (5, 10)}
THESIS_WIENER = {"windows": (35, 40)}


def _table(scores) -> str:
    rows = ["filter,window,sigma,fp,fn,errors"]
    for s in scores:
        sg = "" if s.setting.sigma is None else f"{s.setting.sigma:g}"
        rows.append(
            f"{s.setting.method},{s.setting.window},{sg},{s.fp:.3f},{s.fn:.3f},{s.errors:.3f}"
        )
    return "\n".join(rows) + "\n"


def run_filter_study(config, ctx) -> RunResult:
    """Simulate the traces, rate every filter setting, report the best ones."""
    r = float(config.tip_radius)
    windows, sigmas, repeats = config.windows, config.sigmas, config.repeats
    if ctx.quick:
        windows = tuple(w for w in windows if w in (10, 25, 40)) or windows[:2]
        sigmas = tuple(s for s in sigmas if s in (3, 8)) or sigmas[:1]
        repeats = 1
    shape = Shape(
        kind=config.shape,
        size=config.size_mm * 1e-3,
        width=config.width_mm * 1e-3,
        angle=np.deg2rad(config.angle_deg),
        length=config.length,
    )
    traces = []
    with ctx.timer("simulate"):
        for _ in range(repeats):
            tr = simulate(
                shape,
                r,
                spacing=config.spacing,
                speed=config.speed,
                center_sigma=config.noise_sigma,
                rng=ctx.rng,
            )
            traces.append(
                StudyTrace(
                    tr.t,
                    tr.centers,
                    tuple(f.sign for f in tr.observable),
                    tuple(float(x) for x in tr.t[tr.observable_index]),
                )
            )
    settings = grid(config.filters, windows, sigmas, config.dual_point_iterations)
    tol_t = (config.tolerance or r / 2) / config.speed
    with ctx.timer("rate"):
        scores = rate_filters(
            traces,
            settings,
            r,
            tol_t,
            decimate=config.decimate,
            curvature_sigma=config.curvature_sigma,
        )
    best = min(scores, key=lambda s: s.errors)
    metrics: dict = {
        "n_settings": len(scores),
        "repeats": repeats,
        "n_samples": int(traces[0].t.size),
        "n_true_features": len(traces[0].truth_signs),
        "best_filter": best.setting.method,
        "best_window": best.setting.window,
        "best_sigma": best.setting.sigma,
        "best_errors": best.errors,
    }
    per: dict[str, object] = {}
    for m in config.filters:
        ms = [s for s in scores if s.setting.method == m]
        b = min(ms, key=lambda s: s.errors)
        per[m] = b
        metrics[f"{m}_best_window"] = b.setting.window
        metrics[f"{m}_best_sigma"] = b.setting.sigma
        metrics[f"{m}_best_errors"] = b.errors
    g = [s for s in scores if s.setting.method == "gaussian"]
    if g:
        (w0, w1), (s0, s1) = THESIS_GAUSSIAN["windows"], THESIS_GAUSSIAN["sigmas"]
        inside = [s for s in g if w0 <= s.setting.window <= w1 and s0 <= s.setting.sigma <= s1]
        if inside:
            m_in = min(s.errors for s in inside)
            metrics["gaussian_thesis_region_errors"] = m_in
            metrics["gaussian_agrees_with_thesis"] = bool(m_in <= per["gaussian"].errors + 0.5)
    wi = [s for s in scores if s.setting.method == "wiener"]
    if wi:
        w0, w1 = THESIS_WIENER["windows"]
        inside = [s for s in wi if w0 <= s.setting.window <= w1]
        if inside:
            m_in = min(s.errors for s in inside)
            metrics["wiener_thesis_region_errors"] = m_in
            metrics["wiener_agrees_with_thesis"] = bool(m_in <= per["wiener"].errors + 0.5)
    arrays = {
        "errors": np.array([s.errors for s in scores]),
        "fp": np.array([s.fp for s in scores]),
        "fn": np.array([s.fn for s in scores]),
        "window": np.array([s.setting.window for s in scores]),
        "sigma": np.array([np.nan if s.setting.sigma is None else s.setting.sigma for s in scores]),
    }
    figures = {}
    if ctx.plots:
        with ctx.timer("plots"):
            figures["filter_errors"] = _figure(config, scores, windows, sigmas)
    return RunResult(
        status="ok",
        metrics=metrics,
        arrays=arrays,
        figures=figures,
        files={"filter_study.csv": _table(scores)},
    )


def _figure(config, scores, windows, sigmas):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 4.5))
    ax1 = fig.add_subplot(1, 2, 1)
    for m in config.filters:
        if m in ("gaussian", "none", "dual_point"):
            continue
        ms = [s for s in scores if s.setting.method == m]
        ax1.plot([s.setting.window for s in ms], [s.errors for s in ms], "o-", label=m)
    g = [s for s in scores if s.setting.method == "gaussian"]
    if g:
        best_sig = min(g, key=lambda s: s.errors).setting.sigma
        gs = [s for s in g if s.setting.sigma == best_sig]
        ax1.plot(
            [s.setting.window for s in gs],
            [s.errors for s in gs],
            "s-",
            label=f"gaussian, sigma={best_sig:g}",
        )
    for m in ("none",):
        ms = [s for s in scores if s.setting.method == m]
        if ms:
            ax1.axhline(ms[0].errors, color="0.5", ls=":", label="no filter")
    ax1.set_xlabel("window [samples]")
    ax1.set_ylabel("false positives + false negatives per trace")
    ax1.set_title("App. B.2 scheme errors by filter window")
    ax1.legend(fontsize=8)
    ax1.grid(True, lw=0.3)
    ax2 = fig.add_subplot(1, 2, 2)
    if g:
        mat = np.full((len(sigmas), len(windows)), np.nan)
        for s in g:
            mat[sigmas.index(s.setting.sigma), windows.index(s.setting.window)] = s.errors
        im = ax2.imshow(mat, origin="lower", aspect="auto", cmap="viridis_r")
        ax2.set_xticks(range(len(windows)), [str(w) for w in windows])
        ax2.set_yticks(range(len(sigmas)), [f"{s:g}" for s in sigmas])
        for i in range(len(sigmas)):
            for j in range(len(windows)):
                ax2.text(
                    j,
                    i,
                    f"{mat[i, j]:.1f}",
                    ha="center",
                    va="center",
                    fontsize=7,
                    color="w" if mat[i, j] > np.nanmax(mat) / 2 else "k",
                )
        fig.colorbar(im, ax=ax2, label="FP + FN per trace")
        ax2.set_xlabel("Gaussian window [samples]")
        ax2.set_ylabel("Gaussian sigma [samples]")
        ax2.set_title("Gaussian filter (thesis best: window 25-40, sigma 5-10)", fontsize=9)
    fig.subplots_adjust(left=0.07, right=0.97, bottom=0.12, top=0.92, wspace=0.25)
    return fig
