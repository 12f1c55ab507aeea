"""pdr-sim generate --plot (issue 29): only a foot's trajectory carries Zampella et al.
2011's "Fig. 1a/1b"; titles give the steps and where the route ends; a strip's top view
is stretched and labelled so, a level walk's height axis a floor high."""
from __future__ import annotations

from functools import cache

import pytest

from pdr_core.plot_layout import MIN_HEIGHT_SPAN_M
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
    assert high - low >= MIN_HEIGHT_SPAN_M - 1e-9
    [top] = [ax for ax in pocket.axes if ax.get_title().startswith("top view")]
    assert "stretched" in top.get_ylabel()
