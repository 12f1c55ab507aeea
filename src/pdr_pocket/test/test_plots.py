"""pdr-pocket's figures answer their question (issue 29): a short title with the steps
and the final error, a strip's top view stretched and labelled so, and a zoom on a few
gait cycles of a long pitch trace with the detected steps. Issue 54: the 1σ ellipses the
top view's title promises are drawn on a short walk too, a level walk's height axis fits
its heights, the warnings are whole in a box below the axes. Checked on the figure
itself, not on pixels."""
from __future__ import annotations

import numpy as np
import pytest
from matplotlib.inset import InsetIndicator

from pdr_core.evaluation.plot_layout import MIN_FLOORS_SPAN_M, MIN_LEVEL_SPAN_M
from pdr_core.vocabulary import Activity
from pdr_pocket import plots
from pdr_pocket.orientation import AttitudeEstimate
from wstest import kept_figures

CYCLE_S = 1.1


@pytest.fixture
def figures():
    with kept_figures() as kept:
        yield kept


def strip_walk(minutes: float, with_truth: bool = True):
    """A level walk out and back along a strip 80 m × 1.75 m, one step per gait cycle,
    and its thigh pitch at 100 Hz."""
    t = np.arange(0, 60 * minutes, 0.01)
    steps_t = np.arange(5.0, t[-1] - 1.0, CYCLE_S)
    n = len(steps_t)
    east = 80 * (1 - np.abs(np.linspace(-1, 1, n + 1)))
    north = np.where(np.arange(n + 1) > n // 2, 1.75, 0.0)
    positions = np.c_[east, north, 0.002 * np.sin(np.arange(n + 1))]
    covariances = np.tile(np.eye(3) * 0.01, (n + 1, 1, 1))
    pitch = 15 * np.sin(2 * np.pi * t / CYCLE_S) + 10
    truth = positions + [0.1, 0.0, 0.0] if with_truth else None
    return dict(positions=positions, covariances=covariances,
                activity=np.ones(n + 1, int), truth=truth, t_s=t, pitch_deg=pitch,
                step_t=steps_t, true_step_t=steps_t + 0.05)


def draw(figures, tmp_path, walk, **kwargs):
    plots.navigation_png(**walk, path=tmp_path / "path.png",
                         source=tmp_path / "work" / "up_dw", **kwargs)
    assert (tmp_path / "path.png").stat().st_size > 10_000
    [fig] = figures
    return fig, {ax.get_title(): ax for ax in fig.axes}


def top_view(axes: dict):
    [top] = [ax for title, ax in axes.items() if title.startswith("top view")]
    return top


def test_the_title_is_the_walks_name_its_steps_and_final_error(figures, tmp_path):
    walk = strip_walk(2)
    fig, _ = draw(figures, tmp_path, walk, final_error_m=1.234)
    title = fig._suptitle.get_text()
    assert str(tmp_path) not in title
    assert title.startswith("up_dw: the pocket navigator")
    assert f"{len(walk['step_t'])} steps, final error 1.23 m" in title


def test_without_truth_the_title_gives_the_loop_gap(figures, tmp_path):
    fig, _ = draw(figures, tmp_path, strip_walk(2, with_truth=False), loop_gap_m=1.75)
    assert "no truth, final loop gap 1.75 m" in fig._suptitle.get_text()


def test_a_strip_is_stretched_and_a_level_walks_height_fits_it(figures, tmp_path):
    """Its heights are ±2 mm: the height axis MIN_LEVEL_SPAN_M about them; with a stairs
    step, a floor."""
    walk = strip_walk(2)
    _, axes = draw(figures, tmp_path, walk)
    top = top_view(axes)
    assert top.get_aspect() > 5 and "stretched" in top.get_ylabel()
    low, high = axes["3D path"].get_zlim()
    assert (low, high) == pytest.approx((-MIN_LEVEL_SPAN_M / 2, MIN_LEVEL_SPAN_M / 2),
                                        abs=0.003)
    walk["activity"][5] = Activity.UPSTAIRS
    figures.clear()
    _, axes = draw(figures, tmp_path, walk)
    low, high = axes["3D path"].get_zlim()
    assert high - low == pytest.approx(MIN_FLOORS_SPAN_M)


def test_the_ellipses_are_spaced_for_the_walks_length_and_the_last_step_has_one():
    np.testing.assert_array_equal(plots.ellipse_steps(13), [2, 4, 6, 8, 10, 12, 13])
    np.testing.assert_array_equal(plots.ellipse_steps(5), [1, 2, 3, 4, 5])
    np.testing.assert_array_equal(plots.ellipse_steps(200), np.arange(20, 201, 20))
    assert len(plots.ellipse_steps(0)) == 0
    for steps in (1, 9, 13, 104, 999, 5000):
        marked = plots.ellipse_steps(steps)
        assert marked[-1] == steps and 1 <= len(marked) <= plots.ELLIPSES_PER_WALK + 1


def test_a_thirteen_step_walk_shows_the_ellipses_its_title_promises(figures, tmp_path):
    """Issue 54: "1σ ellipses every 20 steps" and none drawn on a 13-step walk."""
    walk = strip_walk(20 / 60)
    steps = len(walk["positions"]) - 1
    assert steps == 13
    walk["covariances"] *= np.arange(steps + 1)[:, None, None]   # σ grows with the steps
    _, axes = draw(figures, tmp_path, walk)
    top = top_view(axes)
    assert top.get_title() == "top view, 1σ ellipses every 2 steps and at the last (13)"
    [rings] = top.collections
    rings = rings.get_segments()
    assert len(rings) == 7
    for ring, k in zip(rings, [2, 4, 6, 8, 10, 12, 13], strict=True):
        np.testing.assert_allclose(ring[:-1].mean(axis=0), walk["positions"][k, :2],
                                   atol=1e-9)   # a closed ring: its last point its first
        radius = np.linalg.norm(ring - walk["positions"][k, :2], axis=1)
        np.testing.assert_allclose(radius, np.sqrt(0.01 * k))


def test_a_seven_minute_pitch_trace_has_a_zoom_on_a_few_gait_cycles(figures, tmp_path):
    walk = strip_walk(7)
    _, axes = draw(figures, tmp_path, walk)
    [title] = [t for t in axes if t.startswith("zoom")]
    zoom = axes[title]
    low, high = zoom.get_xlim()
    assert plots.ZOOM_CYCLES * CYCLE_S <= high - low <= (plots.ZOOM_CYCLES + 1.5) * CYCLE_S
    shown = walk["step_t"][(walk["step_t"] >= low) & (walk["step_t"] <= high)]
    [marks] = [line for line in zoom.get_lines() if line.get_marker() == "v"]
    np.testing.assert_array_equal(marks.get_xdata(), shown)
    assert len(shown) == plots.ZOOM_CYCLES + 1
    # the whole trace shows where the zoom is
    [box] = [a for a in axes["thigh pitch and steps"].artists if isinstance(a, InsetIndicator)]
    assert box.rectangle.get_x() == pytest.approx(low)
    assert box.rectangle.get_width() == pytest.approx(high - low)


def test_a_short_pitch_trace_has_no_zoom(figures, tmp_path):
    _, axes = draw(figures, tmp_path, strip_walk(0.5))
    assert not [t for t in axes if t.startswith("zoom")]


def test_the_attitude_figure_is_titled_by_name_and_final_error(figures, tmp_path):
    t = np.linspace(0, 60, 601)
    n = len(t)
    errors = np.tile([0.1, -0.2, 1.5], (n, 1))
    estimate = AttitudeEstimate(t, np.tile(np.eye(3), (n, 1, 1)), np.zeros((n, 3)),
                                np.tile(np.eye(6) * 1e-4, (n, 1, 1)),
                                np.zeros((n, 1), dtype=bool), np.zeros((n, 0), dtype=bool),
                                detector_names=("field_disturbed",))
    plots.attitude_png(estimate, errors, np.full(n, -2.25), None, tmp_path / "a.png",
                       tmp_path / "walk")
    title = figures[0]._suptitle.get_text()
    assert title.startswith("walk: ") and str(tmp_path) not in title
    assert "final error roll +0.10°, pitch -0.20°, yaw +1.50°, heading -2.25°" in title


def test_wide_ellipses_leave_the_path_its_extent(figures, tmp_path):
    """Issue 40: a heading σ that grows makes ellipses far wider than the walk; the top
    view keeps the path's (and the truth's) extent and cuts them at the frame."""
    walk = strip_walk(2)
    walk["covariances"] = np.tile(np.diag([400.0, 400.0, 0.01]), (len(walk["positions"]), 1, 1))
    _, axes = draw(figures, tmp_path, walk)
    top = top_view(axes)
    left, right = top.get_xlim()
    assert right - left < 1.5 * 80.2            # the strip's length, not the 40 m ellipses
    [rings] = top.collections
    assert len(rings.get_segments()) == len(plots.ellipse_steps(len(walk["positions"]) - 1))


def test_the_warnings_are_whole_in_a_box_below_the_axes(figures, tmp_path):
    """Issue 54: a warning shortened into the title was cut; now it is whole, wrapped in
    a box inside the figure, below the axes, and the title is the walk's."""
    long = "2 of 102 strides were longer than a person walks at their cadence " * 4
    fig, _ = draw(figures, tmp_path, strip_walk(2), warnings=[long, "walks 8.2 m/s"])
    assert fig._suptitle.get_text().count("\n") == 1, "no warning in the title"
    fig.canvas.draw()       # at the figure's dpi (the file's was 110)
    renderer = fig.canvas.get_renderer()
    [box] = [text for text in fig.texts if text.get_bbox_patch() is not None]
    assert " ".join(box.get_text().split()) == \
        f"warning: {long.strip()} warning: walks 8.2 m/s"
    extent = box.get_bbox_patch().get_window_extent(renderer)
    title = fig._suptitle.get_window_extent(renderer)
    assert fig.bbox.x0 <= extent.x0 and extent.x1 <= fig.bbox.x1 and extent.y0 >= 0
    assert fig.bbox.x0 <= title.x0 and title.x1 <= fig.bbox.x1 and title.y1 <= fig.bbox.y1
    for ax in fig.axes:
        assert ax.get_tightbbox(renderer).y0 > extent.y1
