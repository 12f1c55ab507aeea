"""pdr-ekf's path.png (issue 29): titled by the bag's name with the steps and the final
error of the report (or the loop gap without truth), the height of a level walk a floor
high."""
from __future__ import annotations

import numpy as np
import pytest

from pdr_core.metrics import error_report
from pdr_core.plot_layout import MIN_HEIGHT_SPAN_M
from pdr_ins_ekf.plots import path_png
from wstest import kept_figures


@pytest.fixture
def figures():
    with kept_figures() as kept:
        yield kept


def level_walk():
    t = np.linspace(0, 60, 601)
    truth = np.c_[t, 5 * np.sin(t / 10), 0.002 * np.sin(t)]
    return t, truth + np.c_[0.01 * t, np.zeros((len(t), 2))], truth


def test_the_title_gives_the_bag_the_steps_and_the_reports_final_error(figures, tmp_path):
    t, estimate, truth = level_walk()
    path_png(t, estimate, truth, tmp_path / "p.png", tmp_path / "foot_walk", steps=42,
             shows="the foot navigator")
    [fig] = figures
    final = error_report(t, estimate, truth)["final_error_m"]
    assert fig._suptitle.get_text() == \
        f"foot_walk: the foot navigator\n42 steps, final error {final:.2f} m"
    [height] = [ax for ax in fig.axes if ax.get_title() == "height"]
    low, high = height.get_ylim()
    assert high - low >= MIN_HEIGHT_SPAN_M - 1e-9


def test_without_truth_the_title_gives_the_loop_gap(figures, tmp_path):
    t, estimate, _ = level_walk()
    path_png(t, estimate, None, tmp_path / "p.png", "walk")
    gap = error_report(t, estimate, None)["loop_gap_m"]
    assert figures[0]._suptitle.get_text() == \
        f"walk: the estimated path\nno truth, final loop gap {gap:.2f} m"
