"""The standard atmosphere's barometric formula (pdr_core.sensors.atmosphere): its published
values (ICAO Doc 7488: 89,874.6 Pa at 1,000 m), the inverse, and the slope."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from pdr_core.sensors.atmosphere import (
    SEA_LEVEL_PRESSURE_PA,
    height_m,
    metres_per_pascal,
    pressure_pa,
)


def test_the_standard_atmosphere_at_1000_m():
    assert pressure_pa(0.0) == SEA_LEVEL_PRESSURE_PA
    assert pressure_pa(1000.0) == pytest.approx(89_874.6, abs=0.5)


@given(st.floats(-400.0, 5000.0), st.floats(80_000.0, 105_000.0))
def test_height_inverts_pressure(h, reference_pa):
    assert height_m(pressure_pa(h, reference_pa), reference_pa) == pytest.approx(h, abs=1e-6)


def test_one_hectopascal_is_about_eight_metres_near_the_ground():
    p = np.array([100_000.0, 101_325.0])
    numeric = (height_m(p + 1.0) - height_m(p - 1.0)) / 2.0
    assert metres_per_pascal(p) == pytest.approx(numeric, rel=1e-6)
    assert -100 * metres_per_pascal(SEA_LEVEL_PRESSURE_PA) == pytest.approx(8.32, abs=0.01)
