"""hapex reproduce: every figure claim draws its hapex figure and describes the thesis figure."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.image as mpimg
import pytest

from planner.reproduce import ClaimContext, Verdict, all_claims, run_claim, select

#: Claims that once gave no figure (their checks never asked for a figure path).
FIGURE_IDS = (
    "fig2.10",
    "fig2.12",
    "fig2.14",
    "fig3.9",
    "sec3.4.2",
    "fig4.7",
    "fig4.8",
    "fig4.12",
    "fig4.13",
)

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def quick_results(tmp_path_factory):
    """The quick checks of :data:`FIGURE_IDS`, run once, figures in a temporary report."""
    out = tmp_path_factory.mktemp("reproduce")
    ctx = ClaimContext(quick=True, figures=out / "figures")
    return out, {c.id: run_claim(c, ctx) for c in select(list(FIGURE_IDS))}


@pytest.mark.parametrize("claim_id", FIGURE_IDS)
def test_claim_draws_its_figure(quick_results, claim_id):
    out, results = quick_results
    r = results[claim_id]
    assert r.evidence.verdict not in (Verdict.ERROR, Verdict.NOT_IMPLEMENTED), r.error
    assert r.evidence.figure == f"figures/{claim_id}.png"
    path = out / r.evidence.figure
    data = path.read_bytes()
    assert data.startswith(PNG_SIGNATURE) and len(data) > 1000
    image = mpimg.imread(path)
    assert image.ndim == 3 and image.shape[0] > 50 and image.shape[1] > 50
    assert image.std() > 0  # something is drawn


def test_no_figures_without_a_folder():
    (r,) = [run_claim(c, ClaimContext(quick=True)) for c in select(["fig4.12"])]
    assert r.evidence.figure is None and r.evidence.verdict is Verdict.REPRODUCED


def test_every_figure_claim_describes_the_thesis_figure(quick_results):
    _, results = quick_results
    for c in all_claims():
        if c.id.startswith("fig") or c.id in results:
            assert c.thesis_figure.strip(), f"{c.id}: no description of the thesis figure"
