"""What a staircase can be: the building codes' figures a navigator's staircases are
checked against (pdr_pocket.stairs), SI units.

- :data:`RISER_MIN_M`, :data:`RISER_MAX_M`: the lowest and the highest riser (the height of
  one stair) the codes allow anywhere [m]. The International Building Code (IBC 2015,
  Section 1011.5.2) asks for 4 to 7 in (102–178 mm), 7¾ in (197 mm) in dwellings; DIN 18065
  (Gebäudetreppen, 2020) for 140–200 mm in houses of at most two dwellings and 140–190 mm
  elsewhere; the International Residential Code allows spiral stairs 9½ in (241 mm),
  which Muñoz Díaz 2016 (Section 4.3.1) cites as the maximum (24.1 cm) and its wooden
  test staircase spans (15–25 cm). The span of them all: a riser outside it is no stair.
- :data:`RISERS_PER_GAIT_CYCLE`: a gait cycle of one leg is two footfalls, one riser each
  (Muñoz Díaz 2016, Section 4.3.3: a step on the stairs is two treads deep).
- :data:`FLIGHT_MIN_RISERS`: DIN 18065 calls at least three risers in a row a flight.
- :data:`FLIGHT_MAX_RISERS`: DIN 18065 puts a landing after at most 18 risers (the IBC,
  Section 1011.8, after at most 12 ft, 3.66 m, of rise: 20 risers of 7 in).
- :data:`LANDING_TURN_MIN_DEG`: the least turn of a landing between two flights [°]: an
  L-shaped stair's quarter turn (a U-shaped one's half turn, a spiral's continuous one,
  DIN 18064's stair forms). A straight run of more than a flight has no landing in it.
"""
from __future__ import annotations

RISER_MIN_M = 0.102
RISER_MAX_M = 0.241
RISERS_PER_GAIT_CYCLE = 2
FLIGHT_MIN_RISERS = 3
FLIGHT_MAX_RISERS = 18
LANDING_TURN_MIN_DEG = 90.0
