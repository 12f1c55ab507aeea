"""Physical constants, in one place (SI units).

- STANDARD_GRAVITY_MPS2: standard gravity g₀ [m/s²] (the default local gravity).
- EARTH_RATE_RADPS: the Earth's rotation rate ω_e [rad/s].
- :func:`earth_rate_enu`: ω_ie^n at a latitude, Muñoz Díaz 2016, Eq. (3.24).
- EARTH_FIELD_RANGE_UT: the span of the Earth's field strength [µT] a magnetometer can
  read: 22-67 µT at the surface (the World Magnetic Model's total intensity F, from the
  South Atlantic Anomaly to the south magnetic pole: NOAA/BGS, The US/UK World Magnetic
  Model for 2020-2025, Technical Report, 2020), widened by 15 % each way for the steel of
  buildings. A reading far beyond it is a magnetometer's own hard iron, uncalibrated.
"""
from __future__ import annotations

import numpy as np

STANDARD_GRAVITY_MPS2 = 9.80665
EARTH_RATE_RADPS = 7.292115e-5
EARTH_FIELD_RANGE_UT = (22.0 * 0.85, 67.0 * 1.15)


def earth_rate_enu(latitude_deg: float) -> np.ndarray:
    """ω_ie^n = ω_e·[0, cos λ, sin λ] [rad/s] in ENU at latitude λ (Eq. (3.24))."""
    lat = np.radians(latitude_deg)
    return EARTH_RATE_RADPS * np.array([0.0, np.cos(lat), np.sin(lat)])
