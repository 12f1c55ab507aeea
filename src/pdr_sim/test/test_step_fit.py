"""Step-pattern fitting (Zampella et al. 2011, Eqs. (3)–(5)) on simulated feet, whose
true pattern is known, and the fitted pattern used back in the simulator."""
import numpy as np
import pytest
import yaml

from pdr_sim.foot_trajectory import FootTrajectory
from pdr_sim.scenario import scenario_from_dict
from pdr_sim.step_fit import cut_steps, fit_pattern, pattern_from_file, pattern_to_dict, rms_error
from pdr_sim.step_pattern import FittedPattern

WALK = {"timing": "linear", "initial": {"yaw_deg": 40},
        "segments": [{"type": "standing", "duration_s": 1.0}, {"type": "straight", "steps": 8},
                     {"type": "turn", "angle_deg": 120, "duration_s": 1.0},
                     {"type": "straight", "steps": 8}, {"type": "standing", "duration_s": 1.0}]}


def simulated_steps(rate_hz=200.0):
    traj = FootTrajectory(scenario_from_dict(WALK, "walk")).sample(rate_hz)
    return cut_steps(traj.t, traj.position)


def test_steps_are_cut_aligned_and_translated():
    steps = simulated_steps()
    assert len(steps.t) == 16 and not steps.rejected
    for t, xyz in zip(steps.t, steps.xyz, strict=True):
        np.testing.assert_allclose(xyz[0], 0.0, atol=1e-12)
        assert xyz[-1, 0] == pytest.approx(1.3, abs=0.01)
        assert np.abs(xyz[:, 1]).max() < 1e-9, "aligned with +x"
        assert 0.7 < t[-1] < 1.0


def test_fit_recovers_the_basic_pattern():
    """Eq. (1) is Eq. (4) with one cosine: the fit leaves sub-centimetre residuals."""
    steps = simulated_steps()
    pattern = fit_pattern(steps)
    along, height = rms_error(steps, pattern)
    assert along < 0.01 and height < 0.005


def test_false_steps_are_dropped():
    traj = FootTrajectory(scenario_from_dict(WALK, "walk")).sample(200.0)
    position = traj.position.copy()
    position[100, 0] += 5.0  # a marker glitch while standing: filtered out
    position[300, 0] += 5.0  # one inside the first swing: that step is dropped
    glitched = cut_steps(traj.t, position)
    assert len(glitched.t) == 15 and glitched.rejected == ["swing at 1.41 s: glitch"]
    short = cut_steps(traj.t, traj.position * 0.1)
    assert len(short.t) == 0 and all("length" in r for r in short.rejected)
    with pytest.raises(ValueError, match="only 0 valid steps"):
        fit_pattern(short)


def test_fitted_pattern_drives_the_simulator(tmp_path):
    pattern = fit_pattern(simulated_steps())
    (tmp_path / "p.yaml").write_text(yaml.safe_dump(pattern_to_dict(pattern)))
    loaded = pattern_from_file(tmp_path / "p.yaml")
    assert isinstance(loaded, FittedPattern)
    scenario = scenario_from_dict({"pattern": "fitted", "fitted_pattern": "p.yaml", "segments": [
        {"type": "straight", "steps": 3, "step": {"length_m": 1.1, "swing_s": 0.7}}]}, "f")
    traj = FootTrajectory(scenario, fitted=loaded).sample(1000.0)
    np.testing.assert_allclose(traj.position[-1], [3.3, 0.0, 0.0], atol=1e-9)
    assert np.abs(np.diff(traj.velocity, axis=0)).max() < 0.1, "continuous velocity"
