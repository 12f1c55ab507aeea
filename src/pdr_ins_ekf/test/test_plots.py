"""pdr-ekf's path.png (issue 29): titled by the bag's name with the steps and the final
error of the report (or the loop gap without truth); issue 54: the height axis fits the
heights (a foot's 0-0.2 m was drawn on 0-2.7 m)."""
from __future__ import annotations

import numpy as np
import pytest

from pdr_core.evaluation.metrics import error_report
from pdr_core.evaluation.plot_layout import HEIGHT_MARGIN, MIN_LEVEL_SPAN_M
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


def height_limits(fig) -> tuple[float, float]:
    [height] = [ax for ax in fig.axes if ax.get_title() == "height"]
    return height.get_ylim()


@pytest.mark.parametrize("lift_m", [0.2, 1.5])
def test_the_height_axis_fits_the_heights(figures, tmp_path, lift_m):
    """A foot rises 0.2 m each stride: the axis MIN_LEVEL_SPAN_M about them; a walk that
    reaches 1.5 m: its span and HEIGHT_MARGIN of it above and below, no more."""
    t, _, truth = level_walk()
    truth[:, 2] = lift_m * np.abs(np.sin(t))
    path_png(t, truth, truth, tmp_path / "p.png", "foot_walk")
    low, high = height_limits(figures[0])
    if lift_m < MIN_LEVEL_SPAN_M:
        assert (low, high) == pytest.approx((lift_m / 2 - MIN_LEVEL_SPAN_M / 2,
                                             lift_m / 2 + MIN_LEVEL_SPAN_M / 2), abs=1e-3)
    else:
        assert (low, high) == pytest.approx((-HEIGHT_MARGIN * lift_m,
                                             (1 + HEIGHT_MARGIN) * lift_m), abs=1e-3)


def test_without_truth_the_title_gives_the_loop_gap(figures, tmp_path):
    t, estimate, _ = level_walk()
    path_png(t, estimate, None, tmp_path / "p.png", "walk")
    gap = error_report(t, estimate, None)["loop_gap_m"]
    assert figures[0]._suptitle.get_text() == \
        f"walk: the estimated path\nno truth, final loop gap {gap:.2f} m"
