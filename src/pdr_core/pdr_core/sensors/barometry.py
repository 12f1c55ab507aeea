"""The barometer's words and limits, defined once (SI units inside; issue 41).

- :data:`PA_PER_HPA`: pascals in a hectopascal (a millibar), the unit phones and weather
  reports give pressure in;
- :data:`PRESSURE_MIN_PA`, :data:`PRESSURE_MAX_PA`: the air pressure a person can meet
  (above Everest's summit, 33.7 kPa, to below the Dead Sea's shore, 106.7 kPa): a reading
  outside is no air pressure near the ground;
- :data:`MISGIVEN_UNITS_PA`: the units a pressure is given in by mistake, with their
  factor to Pa (hPa read as Pa is 100 times too small), so a message can name the fix;
- :func:`misgiven_unit`: the unit of :data:`MISGIVEN_UNITS_PA` that makes readings
  plausible (None: none does);
- :data:`PRESSURE_NOISE_RATE_HZ`, :data:`READING_SPAN_MAX_S`: the rate a barometer's noise
  per reading is given at, and the longest a reading can average (a reading at a lower
  rate averages longer and is that much less noisy);
- :data:`OFFSET_JUMPS_MAX_PER_MIN`: offset jumps in a minute beyond which a barometer is
  not trusted;
- :class:`HeightChangeKind`: what a change of the barometric height was (a lift, an
  escalator, stairs, an offset of the barometer), the vocabulary of
  pdr_pocket.height_filter's events.
"""
from __future__ import annotations

from enum import IntEnum

import numpy as np

PA_PER_HPA = 100.0
PRESSURE_MIN_PA = 30_000.0
PRESSURE_MAX_PA = 110_000.0
MISGIVEN_UNITS_PA = {"hPa": PA_PER_HPA, "kPa": 1000.0}
# pdr_pocket's pressure_noise_hpa is a reading's noise at the 25 Hz of a phone's barometer
# for navigation (pdr_core.sensors.imu_profiles, PHONE_BAROMETER); a barometer read at f Hz
# averages 25/f of those (oversampling, IIR filter: the BMP280's and LPS22HB's datasheets),
# so its reading's variance is 25/f times smaller: the LPS22HB's 0.0075 hPa RMS at 1 Hz
# with its low-pass, an iPhone's 1 Hz readings within 0.004 hPa of each other, an Android's
# 10 Hz ones 0.009 hPa RMS (../shared/data/phone/sensor_logger), against 0.03 hPa at 25 Hz
PRESSURE_NOISE_RATE_HZ = 25.0
# the slowest phone barometers report once a second (the iPhone's, the LPS22HB's slowest
# rate): a longer interval between readings is readings missing, not a longer average
READING_SPAN_MAX_S = 1.0
# a real offset of the barometer (a ventilated stairwell's or lift lobby's 0.2-0.4 hPa)
# comes at a door and goes at the next: two jumps for about a minute's stay, and a person
# passes few such doors a minute. More than 4 in 60 s (two such stays) is a barometer
# whose readings do not follow the filter's model (invented between its readings, a wrong
# noise, a sensor in trouble): the user's iPhone gave 15 in 24 s on a level walk
OFFSET_JUMPS_MAX_PER_MIN = 4


def plausible_pressure(pressure_pa) -> np.ndarray:
    """Whether each pressure [Pa] is air pressure a person can meet (bool array)."""
    p = np.asarray(pressure_pa, float)
    return (p >= PRESSURE_MIN_PA) & (p <= PRESSURE_MAX_PA)


def misgiven_unit(pressure_pa) -> str | None:
    """The unit of :data:`MISGIVEN_UNITS_PA` in which the implausible readings
    ``pressure_pa`` (as if Pa) are plausible, by their median: "hPa" for 1013; None when
    no unit explains them (a glitch, not a unit)."""
    p = np.asarray(pressure_pa, float)
    if not p.size:
        return None
    median = float(np.median(p))
    for unit, factor in MISGIVEN_UNITS_PA.items():
        if plausible_pressure(median * factor):
            return unit
    return None


class HeightChangeKind(IntEnum):
    """What a change of the barometric height without a step to explain it was."""

    OFFSET = 0          # the barometer's: a door, ventilation, a pressurised stairwell
    STAIRS = 1          # walked: the steps carry it, the barometer fuses with them
    LIFT = 2            # a ride: the vertical specific force's pulses confirm it
    ESCALATOR = 3       # a ride: slow and smooth over many seconds, no pulses
    UNRESOLVED = 4      # no level before it or after it to measure it by

    @property
    def label(self) -> str:
        """The lower-case name reports and logs use ("lift")."""
        return self.name.lower()


RIDE_KINDS = (HeightChangeKind.LIFT, HeightChangeKind.ESCALATOR)
