"""pdr_core.walking.walk_plausibility: a walk's median |f| and a thigh's swing, the warnings and
the --strict refusal both navigators share (issue 54, point 2)."""
from __future__ import annotations

import numpy as np
import pytest

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError
from pdr_core.sensors.imu_checks import check_units
from pdr_core.walking.walk_plausibility import (
    THIGH_SWING_MAX_RATIO,
    implausible_input,
    specific_force_problem,
    swing_problem,
)

RATE_HZ = 100.0


def stamps(n: int = 1001) -> np.ndarray:
    """The stamps [s] of :func:`forces` at :data:`RATE_HZ`."""
    return np.arange(n + 1) / RATE_HZ


def forces(median_mps2: float, n: int = 1001) -> np.ndarray:
    """(n, 3) specific forces with gravity whose median |f| is ``median_mps2``, a NaN row
    among them."""
    out = np.zeros((n, 3))
    out[:, 2] = median_mps2 * np.linspace(0.8, 1.2, n)
    return np.vstack([[np.nan, 0.0, 0.0], out])


def linear_acceleration(scale: float, n: int = 1001) -> np.ndarray:
    """(n, 3) gravity-removed readings of a walk (zero mean over a stride), × ``scale``."""
    t = np.arange(n) / RATE_HZ
    return scale * np.column_stack([np.sin(2 * np.pi * t), np.cos(2 * np.pi * t),
                                    2.0 * np.sin(4 * np.pi * t)])


@pytest.mark.parametrize("median_g", [0.9, 1.0, 1.3, 2.2])
def test_a_walk_or_a_run_passes(median_g):
    assert specific_force_problem(stamps(), forces(median_g * STANDARD_GRAVITY_MPS2)) is None


def test_several_g_at_walking_pace_is_named_with_its_figure():
    """Data 4 g away from a walk's: another unit."""
    problem = specific_force_problem(stamps(), forces(38.7))
    assert problem.startswith("median |f| 38.7 m/s² (3.95 g) is no walk's (0.5-2.5 g")
    assert "another unit" in problem


def test_data_in_g_read_as_mps2_are_another_unit_not_missing_gravity():
    problem = specific_force_problem(stamps(), forces(1.0))
    assert "another unit" in problem and "gravity" not in problem


@pytest.mark.parametrize("scale", [1.0, STANDARD_GRAVITY_MPS2])
def test_a_gravity_removed_accelerometer_in_any_unit_is_named(scale):
    """The user's linear acceleration read in g (2-4 g) or in m/s² (0.2 g)."""
    t = np.arange(1001) / RATE_HZ
    problem = specific_force_problem(t, linear_acceleration(scale))
    assert "gravity is missing" in problem and "gravity file" in problem


def test_a_swing_thirteen_times_a_thighs_is_named():
    assert swing_problem(None) is None and swing_problem(THIGH_SWING_MAX_RATIO) is None
    assert swing_problem(13.4).startswith("the pitch swings 13.4 times a thigh's")


def test_strict_refuses_the_first_problem_naming_the_file():
    assert implausible_input("walk", [None, "a", "b"], strict=False) == ["a", "b"]
    assert implausible_input("walk", [None], strict=True) == []
    with pytest.raises(InputError, match=r"^walk: a \(refused: --strict\)$"):
        implausible_input("walk", [None, "a", "b"], strict=True)


def test_the_unit_check_leaves_gravity_removed_data_to_the_walk_check():
    """A gravity-removed walk in m/s² has a median |f| a g-read-as-m/s² log could have
    (1.5 m/s²): without stamps it looks like g; with them it is no unit mistake, and the
    walk check names it (the navigators pass the stamps)."""
    t = np.arange(1001) / RATE_HZ
    walk = linear_acceleration(0.6)
    gyro = np.zeros_like(walk)
    with pytest.raises(InputError, match="--acc-unit"):
        check_units(walk, gyro)
    check_units(walk, gyro, t_s=t)
    assert "gravity is missing" in specific_force_problem(t, walk)
    with pytest.raises(InputError, match="--acc-unit"):
        check_units(forces(1.0)[1:], np.zeros((1001, 3)), t_s=t)
