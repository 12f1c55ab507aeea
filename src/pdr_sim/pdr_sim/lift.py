"""A lift ride: the vertical motion of the car a standing person rides in.

A passenger lift moves its car with limited jerk j, acceleration a and speed v, the
"ideal lift kinematics" of Peters 1995 ("Ideal Lift Kinematics: Complete Equations for
Plotting Optimum Motion", Elevator Technology 6, IAEE, 1995): seven phases with the jerk
+j, 0, −j (speeding up to the cruise speed), 0 (cruising), −j, 0, +j (braking), so the
acceleration is continuous and trapezoidal. A journey too short to reach the rated speed
cruises at a lower one, too short to reach a at all peaks below it (Peters 1995's short
journeys), and always ends at rest after exactly the rise.

Typical figures, the defaults of :class:`LiftMotion`: the human comfort limits the
kinematics are built on keep a passenger lift's acceleration at or below about 1 m/s² and
its jerk at or below about 2 m/s³ (Peters 1995; ISO 18738-1:2012 defines how a ride's
acceleration, jerk and speed are measured); rated speeds of lifts in buildings of a few
to twenty floors are 1–2.5 m/s. The defaults, 1.6 m/s, 0.8 m/s² and 1.2 m/s³, are a
mid-rise passenger lift within those figures (assumed: no single lift is cited), and
take a 3.5 m floor in 4.9 s, three floors in 9.2 s.

- :class:`LiftMotion`: the car's limits (speed, acceleration, jerk).
- :class:`LiftRide`: one ride, from its start time, by a signed rise; :meth:`LiftRide.at`
  gives the car's height, vertical speed and acceleration at any times.
- :func:`rides_motion`: the sum of several rides' motions at any times.

Units: time [s], height [m], + up.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

# The signs of the jerk in the seven phases: speeding up, cruising, braking
_JERK_SIGNS = np.array([1.0, 0.0, -1.0, 0.0, -1.0, 0.0, 1.0])


@dataclass(frozen=True)
class LiftMotion:
    """The limits of a lift car's motion (module docstring for the figures)."""

    speed_mps: float = 1.6              # rated speed [m/s]
    acceleration_mps2: float = 0.8      # largest acceleration and deceleration [m/s²]
    jerk_mps3: float = 1.2              # largest jerk [m/s³]


@dataclass(frozen=True)
class LiftRide:
    """One ride: the car starts moving at ``start_s`` [s] and stops ``rise_m`` [m] higher
    (negative: lower), ``floors`` floors (signed) from where it started."""

    start_s: float
    rise_m: float
    floors: int
    motion: LiftMotion = LiftMotion()

    @cached_property
    def _phases(self) -> tuple[np.ndarray, np.ndarray]:
        """(8,) phase boundaries [s from the start] and (7, 4) per phase its jerk [m/s³]
        and the height, speed and acceleration it starts with, for the magnitude of the
        rise (the sign is applied in :meth:`at`)."""
        d, m = abs(self.rise_m), self.motion
        j = m.jerk_mps3
        a = min(m.acceleration_mps2, np.sqrt(m.speed_mps * j))   # a speed too low for a
        v = m.speed_mps
        if v * (v / a + a / j) > d:             # no cruise: the rated speed is not reached
            v = (-a * a / j + np.sqrt((a * a / j) ** 2 + 4.0 * a * d)) / 2.0
            if v < a * a / j:                   # ... nor the acceleration
                v = (d * np.sqrt(j) / 2.0) ** (2.0 / 3.0)
                a = np.sqrt(v * j)
        t_jerk, t_accel = a / j, max(v / a - a / j, 0.0)
        t_cruise = max(d / v - (v / a + a / j), 0.0) if d > 0 else 0.0
        durations = np.array([t_jerk, t_accel, t_jerk, t_cruise, t_jerk, t_accel, t_jerk])
        bounds = np.concatenate(([0.0], np.cumsum(durations)))
        states = np.zeros((7, 4))
        states[:, 0] = _JERK_SIGNS * j
        for k in range(6):                      # each phase starts where the one before ends
            jerk, h, speed, accel = states[k]
            dt = durations[k]
            states[k + 1, 1:] = (h + speed * dt + accel * dt**2 / 2 + jerk * dt**3 / 6,
                                 speed + accel * dt + jerk * dt**2 / 2, accel + jerk * dt)
        return bounds, states

    @property
    def duration_s(self) -> float:
        """How long the car moves [s]."""
        return float(self._phases[0][-1])

    @property
    def end_s(self) -> float:
        return self.start_s + self.duration_s

    def at(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The car's height above where it started [m], its vertical speed [m/s] and
        acceleration [m/s²] at the times ``t`` [s] (N,): 0 before the ride, the rise
        after it."""
        bounds, states = self._phases
        tau = np.asarray(t, float) - self.start_s
        k = np.clip(np.searchsorted(bounds, tau, side="right") - 1, 0, 6)
        dt = np.clip(tau, 0.0, bounds[-1]) - bounds[k]
        jerk, h0, v0, a0 = states[k].T
        sign = np.sign(self.rise_m)
        height = h0 + v0 * dt + a0 * dt**2 / 2 + jerk * dt**3 / 6
        height = np.where(tau >= bounds[-1], abs(self.rise_m), height)
        moving = (tau > 0) & (tau < bounds[-1])
        speed = np.where(moving, v0 + a0 * dt + jerk * dt**2 / 2, 0.0)
        accel = np.where(moving, a0 + jerk * dt, 0.0)
        return sign * height, sign * speed, sign * accel


def rides_motion(rides: tuple[LiftRide, ...], t: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The summed height [m], vertical speed [m/s] and acceleration [m/s²] of ``rides`` at
    the times ``t`` [s] (N,): how far the lifts have carried a person by then."""
    t = np.asarray(t, float)
    total = np.zeros((3, len(t)))
    for ride in rides:                          # a few rides, each over all samples
        total += np.asarray(ride.at(t))
    return total[0], total[1], total[2]
