"""pdr_core.walk_plausibility: a walk's median |f| and a thigh's swing, the warnings and
the --strict refusal both navigators share (issue 54, point 2)."""
from __future__ import annotations

import numpy as np
import pytest

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError
from pdr_core.walk_plausibility import (
    THIGH_SWING_MAX_RATIO,
    implausible_input,
    specific_force_problem,
    swing_problem,
)


def forces(median_mps2: float, n: int = 101) -> np.ndarray:
    """(n, 3) specific forces whose median |f| is ``median_mps2``, a NaN row among them."""
    out = np.zeros((n, 3))
    out[:, 2] = median_mps2 * np.linspace(0.8, 1.2, n)
    return np.vstack([[np.nan, 0.0, 0.0], out])


@pytest.mark.parametrize("median_g", [0.9, 1.0, 1.3, 2.2])
def test_a_walk_or_a_run_passes(median_g):
    assert specific_force_problem(forces(median_g * STANDARD_GRAVITY_MPS2)) is None


def test_several_g_at_walking_pace_is_named_with_its_figure():
    """The user's gravity-removed accelerometer read in g: median 38.7 m/s²."""
    problem = specific_force_problem(forces(38.7))
    assert problem.startswith("median |f| 38.7 m/s² (3.95 g) is no walk's (0.5-2.5 g")
    assert "--acc-unit g" in problem


def test_gravity_missing_is_named_with_the_remedy():
    problem = specific_force_problem(forces(1.2))
    assert "gravity is missing" in problem and "gravity file" in problem


def test_a_swing_thirteen_times_a_thighs_is_named():
    assert swing_problem(None) is None and swing_problem(THIGH_SWING_MAX_RATIO) is None
    assert swing_problem(13.4).startswith("the pitch swings 13.4 times a thigh's")


def test_strict_refuses_the_first_problem_naming_the_file():
    assert implausible_input("walk", [None, "a", "b"], strict=False) == ["a", "b"]
    assert implausible_input("walk", [None], strict=True) == []
    with pytest.raises(InputError, match=r"^walk: a \(refused: --strict\)$"):
        implausible_input("walk", [None, "a", "b"], strict=True)
