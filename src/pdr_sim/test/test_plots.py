"""pdr-sim generate --plot (issue 29): only a foot's trajectory carries Zampella et al.
2011's "Fig. 1a/1b"; titles give the steps and where the route ends; a strip's top view
is stretched and labelled so; issue 54: a level walk's height axis fits its heights, the
speed panel is a line per window, not a solid block of every sample."""
from __future__ import annotations

from functools import cache

import numpy as np
import pytest

from pdr_core.evaluation.plot_layout import MIN_LEVEL_SPAN_M
from pdr_sim import plots
from pdr_sim.foot_trajectory import FootTrajectory
from pdr_sim.pocket_scenario import pocket_scenario_from_dict
from pdr_sim.scenario import load_scenario
from pdr_sim.simulation import SimulationConfig, simulate
from wstest import kept_figures


@pytest.fixture
def figures():
    with kept_figures() as kept:
        yield kept


@cache
def pocket_walk():
    """12 m along a corridor with a phone in the pocket, ideal sensors."""
    data = {"segments": [{"type": "standing", "duration_s": 2},
                         {"type": "walk", "distance_m": 12}]}
    return simulate(SimulationConfig(pocket_scenario_from_dict(data, "corridor"), data,
                                     "ideal", {}, 50.0, 0, placement="pocket"))


def titles(fig) -> list[str]:
    return [ax.get_title() for ax in fig.axes]


def test_a_foot_trajectory_carries_the_papers_figure_labels(figures, tmp_path):
    scenario, _ = load_scenario("straight")
    model = FootTrajectory(scenario)
    steps = plots.step_count(model)
    assert steps == sum(s.steps for s in scenario.segments if s.type in ("straight", "curve"))
    plots.trajectory_png(model.sample(100.0), tmp_path / "t.png", "straight, ideal, 100 Hz",
                         steps=steps)
    [fig] = figures
    assert {"position (Fig. 1a)", "attitude (Fig. 1b)"} <= set(titles(fig))
    title = fig._suptitle.get_text()
    assert title.startswith("straight, ideal, 100 Hz: the simulated foot's trajectory")
    assert f"{steps} steps, the truth, ends " in title
    top = fig.axes[0]
    assert top.get_title() == "top view" and "stretched" in top.get_ylabel()


def test_the_speed_panel_is_the_mean_and_peak_per_window(figures, tmp_path):
    """A foot at 100 Hz swings from 0 to 5 m/s every stride: drawn whole, the panel was a
    block of thousands of vertical strokes. Now two lines of a point per SPEED_WINDOW_S,
    a point per few pixels at most; the mean is the samples' mean in each window and the
    peak their maximum."""
    scenario, _ = load_scenario("long_mixed_walk")
    traj = FootTrajectory(scenario).sample(100.0)
    plots.trajectory_png(traj, tmp_path / "t.png", "long_mixed_walk")
    [fig] = figures
    [speed] = [ax for ax in fig.axes if ax.get_title().startswith("speed")]
    assert speed.get_title() == f"speed, per {plots.SPEED_WINDOW_S:g} s window"
    peak, mean = speed.get_lines()
    width_px = speed.get_window_extent().width
    duration = traj.t[-1] - traj.t[0]
    assert len(mean.get_xdata()) == np.ceil(duration / plots.SPEED_WINDOW_S) < width_px / 4
    samples = np.linalg.norm(traj.velocity, axis=1)
    first = traj.t < traj.t[0] + plots.SPEED_WINDOW_S
    assert mean.get_ydata()[0] == pytest.approx(samples[first].mean())
    assert peak.get_ydata().max() == pytest.approx(samples.max())
    walking = mean.get_ydata()[len(mean.get_ydata()) // 2]
    assert 0.7 < walking < 1.8 < peak.get_ydata()[len(mean.get_ydata()) // 2]


def test_a_long_walk_gets_longer_windows():
    t = np.arange(0.0, 3600.0, 0.01)
    centres, mean, peak, window = plots.windowed_speed(t, np.abs(np.sin(t)))
    assert window == pytest.approx(3600.0 / plots.MAX_SPEED_WINDOWS, rel=1e-3)
    assert len(centres) == len(mean) == len(peak) <= plots.MAX_SPEED_WINDOWS + 1
    np.testing.assert_allclose(mean[:-1], 2 / np.pi, atol=0.03)   # 12 s of a π s period


def test_a_pocket_trajectory_has_no_foot_paper_labels(figures, tmp_path):
    sim = pocket_walk()
    steps = plots.step_count(sim.model)
    assert steps == len(sim.model.true_steps.length) > 5
    plots.trajectory_png(sim.trajectory, tmp_path / "t.png", "corridor", steps=steps,
                         foot=False)
    plots.pocket_png(sim.model, sim.trajectory, tmp_path / "p.png", "corridor")
    trajectory, pocket = figures
    assert not [t for t in titles(trajectory) if "Fig." in t]
    assert {"position", "attitude"} <= set(titles(trajectory))
    for fig in figures:
        assert f"{steps} steps, the truth" in fig._suptitle.get_text()
    [route] = [ax for ax in pocket.axes if ax.get_title() == "route (3D)"]
    low, high = route.get_zlim()
    heights = np.r_[sim.trajectory.position[:, 2], sim.model.route["step"][:, 2]]
    assert high - low == pytest.approx(max(MIN_LEVEL_SPAN_M, 1.1 * np.ptp(heights)))
    assert low < heights.min() and heights.max() < high
    [top] = [ax for ax in pocket.axes if ax.get_title().startswith("top view")]
    assert "stretched" in top.get_ylabel()
