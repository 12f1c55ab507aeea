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
