"""drift.png shows both paths (issue 29): the uncorrected one drawn over the corrected
one, dashed, where they coincide (217 of 326 steps of the README's two laps before a
correction), the corrections marked, and the title gives the input's name, the steps
and the final error of both, or without truth their loop gaps."""
from __future__ import annotations

import numpy as np
import pytest

from pdr_drift.plots import paths_png, shared_steps
from wstest import kept_figures


@pytest.fixture
def figures():
    with kept_figures() as kept:
        yield kept


def two_paths(shared: int = 30, steps: int = 40):
    """A walk east that a correction turns north after ``shared`` steps (rows: the start,
    then one per step)."""
    uncorrected = np.c_[np.arange(steps + 1.0), np.zeros(steps + 1)]
    corrected = uncorrected.copy()
    corrected[shared + 1:, 1] = 0.5 * np.arange(1, steps - shared + 1)
    return corrected, uncorrected


def lines_by_label(ax) -> dict:
    return {line.get_label(): line for line in ax.get_lines()}


def test_the_uncorrected_path_is_drawn_over_the_shared_part(figures, tmp_path):
    corrected, uncorrected = two_paths()
    assert shared_steps(corrected, uncorrected) == 31
    paths_png(corrected, uncorrected, np.zeros((0, 3)), tmp_path / "d.png",
              tmp_path / "block_two_laps", truth=corrected + 0.1, corrected_label="corrected",
              uncorrected_label="alone", corrections=corrected[[31]])
    [fig] = figures
    [ax] = fig.axes
    lines = lines_by_label(ax)
    dashed = lines["alone (dashed; the same for the first 30 of 40 steps)"]
    order = ax.get_lines()
    assert dashed.get_linestyle() == "--"
    assert order.index(dashed) > order.index(lines["corrected"])
    assert dashed.get_linewidth() < lines["corrected"].get_linewidth()
    np.testing.assert_array_equal(lines["corrections applied"].get_xdata(), [31.0])
    title = fig._suptitle.get_text()
    assert title.startswith("block_two_laps: ") and str(tmp_path) not in title
    error = np.linalg.norm(uncorrected[-1] - (corrected[-1] + 0.1))
    assert f"40 steps, final error {error:.2f} m → 0.14 m corrected" in title


def test_without_truth_the_title_gives_both_loop_gaps(figures, tmp_path):
    corrected, uncorrected = two_paths(shared=0)
    paths_png(corrected, uncorrected, np.zeros((0, 3)), tmp_path / "d.png", "walk")
    title = figures[0]._suptitle.get_text()
    gap = np.linalg.norm(corrected[-1])
    assert f"40 steps, no truth, final loop gap 40.00 m → {gap:.2f} m corrected" in title
    # nothing shared: no note in the legend
    assert "uncorrected" in lines_by_label(figures[0].axes[0])
