"""Air pressure and height: the barometric formula of the ICAO Standard Atmosphere's
troposphere (ISO 2533:1975, ICAO Doc 7488), SI units.

p(h) = p_ref·(1 − L·(h − h_ref)/T_ref)^(g₀·M/(R·L)), with T_ref the temperature at h_ref,
is what a phone's pressure altitude uses; near the ground one hectopascal is about 8.3 m.
A barometer measures height changes, not height: the weather moves p_ref by up to about
1 hPa/h, so only differences over a short time are heights (Parviainen et al. 2008; Ye
et al. 2014, "B-Loc", on phones).

- :data:`SEA_LEVEL_PRESSURE_PA`, :data:`SEA_LEVEL_TEMPERATURE_K`, :data:`LAPSE_RATE_K_PER_M`,
  :data:`GAS_CONSTANT_J_PER_MOL_K`, :data:`MOLAR_MASS_AIR_KG_PER_MOL`: the standard
  atmosphere's constants;
- :func:`pressure_pa`: p [Pa] at heights h [m] above a reference;
- :func:`height_m`: h [m] above a reference from p [Pa], the inverse;
- :func:`metres_per_pascal`: dh/dp [m/Pa] (negative) at a pressure.
"""
from __future__ import annotations

import numpy as np

from pdr_core.constants import STANDARD_GRAVITY_MPS2

SEA_LEVEL_PRESSURE_PA = 101_325.0
SEA_LEVEL_TEMPERATURE_K = 288.15
LAPSE_RATE_K_PER_M = 0.0065
GAS_CONSTANT_J_PER_MOL_K = 8.314_462_618
MOLAR_MASS_AIR_KG_PER_MOL = 0.028_964_4
# g₀·M/(R·L), the exponent of the troposphere's formula (5.2559)
_EXPONENT = STANDARD_GRAVITY_MPS2 * MOLAR_MASS_AIR_KG_PER_MOL / (
    GAS_CONSTANT_J_PER_MOL_K * LAPSE_RATE_K_PER_M)


def pressure_pa(height_m, reference_pa: float = SEA_LEVEL_PRESSURE_PA,
                reference_temperature_k: float = SEA_LEVEL_TEMPERATURE_K):
    """p [Pa] at ``height_m`` [m] above the reference where the pressure is
    ``reference_pa`` and the temperature ``reference_temperature_k``."""
    ratio = 1.0 - LAPSE_RATE_K_PER_M * np.asarray(height_m, float) / reference_temperature_k
    return reference_pa * ratio ** _EXPONENT


def height_m(pressure, reference_pa: float = SEA_LEVEL_PRESSURE_PA,
             reference_temperature_k: float = SEA_LEVEL_TEMPERATURE_K):
    """h [m] above the reference (pressure ``reference_pa``, temperature
    ``reference_temperature_k``) at pressure ``pressure`` [Pa]: :func:`pressure_pa`
    inverted."""
    ratio = (np.asarray(pressure, float) / reference_pa) ** (1.0 / _EXPONENT)
    return reference_temperature_k * (1.0 - ratio) / LAPSE_RATE_K_PER_M


def metres_per_pascal(pressure, reference_pa: float = SEA_LEVEL_PRESSURE_PA,
                      reference_temperature_k: float = SEA_LEVEL_TEMPERATURE_K):
    """dh/dp [m/Pa] at pressure ``pressure`` [Pa] (−0.083 m/Pa at sea level)."""
    p = np.asarray(pressure, float)
    ratio = (p / reference_pa) ** (1.0 / _EXPONENT)
    return -reference_temperature_k * ratio / (LAPSE_RATE_K_PER_M * _EXPONENT * p)
