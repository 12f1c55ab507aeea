"""The figures' shared layout (issue 29, "Pictures that answer the question"): short
titles with the steps and the final error, top views to scale unless they are strips;
issue 54: height axes fitted to the heights (a floor high only with floors), titles and
warnings inside the figure."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest

from pdr_core.evaluation.plot_layout import (
    HEIGHT_MARGIN,
    MAX_EQUAL_RATIO,
    MAX_WARNINGS_SHOWN,
    MIN_FLOORS_SPAN_M,
    MIN_LEVEL_SPAN_M,
    figure_title,
    height_axis,
    lay_out,
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


def test_a_level_walk_is_drawn_about_its_heights_and_floors_a_floor_high():
    """Issue 54: a foot's 0-0.2 m was drawn on 0-2.7 m. A level walk's axis is centred on
    its heights, as high as they span with HEIGHT_MARGIN above and below, or
    MIN_LEVEL_SPAN_M for less (millimetres of noise are drawn flat)."""
    fig, ax = plt.subplots()
    foot = 0.2 * np.abs(np.sin(np.arange(300) / 7.0))
    low, high = height_axis(ax, foot, "y")
    assert ax.get_ylim() == (low, high)
    assert (low + high) / 2 == pytest.approx(0.1)
    assert high - low == pytest.approx(MIN_LEVEL_SPAN_M)
    low, high = height_axis(ax, 0.003 * np.sin(np.arange(100)), "y")
    assert (low, high) == pytest.approx((-MIN_LEVEL_SPAN_M / 2, MIN_LEVEL_SPAN_M / 2),
                                        abs=1e-3)
    drift = np.r_[np.linspace(0.0, 1.2, 50), np.nan]
    low, high = height_axis(ax, drift, "y")
    assert (low, high) == pytest.approx((-HEIGHT_MARGIN * 1.2, 1.2 + HEIGHT_MARGIN * 1.2))
    # stairs: a floor high at least, from just below the lowest, and 14.4 m in full
    low, high = height_axis(ax, np.r_[0.0, 0.8], "y", floors=True)
    assert -0.2 < low < 0 and high - low == pytest.approx(MIN_FLOORS_SPAN_M)
    low, high = height_axis(ax, np.r_[0.0, 14.4, np.nan], "y", floors=True)
    assert low < 0 and high > 14.4 and high - low < 16
    plt.close(fig)


def warning_boxes(fig) -> list:
    return [text for text in fig.texts if text.get_bbox_patch() is not None]


def inside(extent, box) -> bool:
    return box.x0 <= extent.x0 and extent.x1 <= box.x1 and box.y0 <= extent.y0 and \
        extent.y1 <= box.y1


def test_a_long_title_and_long_warnings_are_wrapped_inside_the_figure_below_the_axes():
    """Issue 54: a warning in the title was cut at the figure's edge. The title wraps; the
    warnings go whole into a box below the axes, beyond MAX_WARNINGS_SHOWN counted."""
    fig, axes = plt.subplots(1, 2, figsize=(8, 5))
    for ax in axes:
        ax.plot([0, 1], [0, 1])
        ax.set(title="a panel", xlabel="x [m]")
    long = "2 of 102 strides were longer than a person walks at their cadence " * 4
    warnings = [long, "walks 8.2 m/s", *(f"warning {k}" for k in range(4))]
    lay_out(fig, figure_title("walk", "the pocket navigator " * 6, "13 steps, no truth"),
            warnings)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    title = fig._suptitle
    assert inside(title.get_window_extent(renderer), fig.bbox)
    assert title.get_text().count("\n") >= 2 and title.get_text().endswith("13 steps, no truth")
    [box] = warning_boxes(fig)
    assert inside(box.get_bbox_patch().get_window_extent(renderer), fig.bbox)
    text = box.get_text()
    assert " ".join(text.split()) == " ".join(
        [f"warning: {w.strip()}" for w in warnings[:MAX_WARNINGS_SHOWN]]
        + [f"and {len(warnings) - MAX_WARNINGS_SHOWN} more warnings in the report"])
    assert len(text.split("\n")) > MAX_WARNINGS_SHOWN + 1, "the long warning is wrapped"
    top_of_box = box.get_bbox_patch().get_window_extent(renderer).y1
    for ax in axes:
        assert ax.get_tightbbox(renderer).y0 > top_of_box, "the axes clear the box"
        assert title.get_window_extent(renderer).y0 > ax.get_tightbbox(renderer).y1
    plt.close(fig)


def test_without_warnings_no_box():
    fig, _ = plt.subplots()
    lay_out(fig, "walk: a path")
    assert not warning_boxes(fig) and fig._suptitle.get_text() == "walk: a path"
    plt.close(fig)
