"""The figures' shared layout (issue 29, "Pictures that answer the question"): short
titles with the steps and the final error, top views to scale unless they are strips,
height axes a floor high."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest

from pdr_core.plot_layout import (
    MAX_EQUAL_RATIO,
    MIN_HEIGHT_SPAN_M,
    figure_title,
    height_axis,
    source_name,
    top_view,
    walk_summary,
)


def test_a_title_names_the_input_not_its_path_and_states_steps_and_error():
    assert source_name("/tmp/issue29/work/up_dw/") == "up_dw"
    assert source_name("bags/walk.mcap") == "walk.mcap"
    title = figure_title("/abs/path/to/up_dw", "the pocket navigator", walk_summary(178, 3.9))
    assert title == "up_dw: the pocket navigator\n178 steps, final error 3.90 m"
    assert walk_summary(12, loop_gap_m=0.5) == "12 steps, no truth, final loop gap 0.50 m"
    assert walk_summary() == "no truth"
    assert walk_summary(3, loop_gap_m=1.0, of_truth=True) == \
        "3 steps, the truth, ends 1.00 m from its start"


def axes_with(x, y):
    fig, ax = plt.subplots(figsize=(6, 6))
    ax.plot(x, y)
    return fig, ax


def test_a_strip_is_stretched_and_says_so():
    """80 m × 1.75 m (UP/DW from above): the north axis stretched to a 3:1 view."""
    fig, ax = axes_with([0, 80, 80, 0], [0, 0, 1.75, 1.75])
    stretch = top_view(ax)
    plt.close(fig)
    assert stretch == pytest.approx(80 / 1.75 / MAX_EQUAL_RATIO, rel=0.05)
    assert ax.get_aspect() == stretch
    assert f"stretched ×{stretch:g} (not to scale)" in ax.get_ylabel()
    assert "stretched" not in ax.get_xlabel()


def test_a_tall_strip_stretches_east_and_a_block_stays_to_scale():
    fig, ax = axes_with([0, 0.5], [0, 40])
    assert top_view(ax) > 1 and "stretched" in ax.get_xlabel()
    plt.close(fig)
    fig, ax = axes_with([0, 60, 60, 0], [0, 0, 40, 40])
    assert top_view(ax) == 1.0
    assert ax.get_aspect() == 1.0 and "stretched" not in ax.get_ylabel()
    plt.close(fig)


def test_a_straight_line_is_not_blown_up_to_its_noise():
    """A straight walk 2 cm wide: its north axis spans a metre at least."""
    fig, ax = axes_with(np.linspace(0, 20, 50), 0.01 * np.sin(np.arange(50)))
    top_view(ax)
    plt.close(fig)
    low, high = ax.get_ylim()
    assert high - low >= 1.0


def test_a_level_walk_is_drawn_a_floor_high_and_stairs_in_full():
    fig, ax = plt.subplots()
    low, high = height_axis(ax, 0.003 * np.sin(np.arange(100)), "y")
    assert high - low == pytest.approx(MIN_HEIGHT_SPAN_M)
    assert low < -0.003 and high > 0.003 and ax.get_ylim() == (low, high)
    low, high = height_axis(ax, np.r_[0.0, 14.4, np.nan], "y")
    assert low < 0 and high > 14.4 and high - low < 16
    plt.close(fig)
