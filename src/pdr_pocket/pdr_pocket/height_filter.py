"""The height of a pocket walk from its steps and the barometer, and the lift and
escalator rides between floors (issue 41). Plain NumPy, causal and chunk-invariant: fed
in pieces, as a live node feeds it, it gives exactly what it gives fed at once.

**The model.** A Kalman filter on x = [h, b, ḃ]: h [m] the person's height above the
start, b [m] the barometer's offset (the barometric height less h) and ḃ [m/s] its weather
drift. Each sensor comes in through its own entry point, as VQF's updateGyr/updateAcc:

- :meth:`HeightFilter.step`: a step's vertical displacement v [m] (Muñoz Díaz 2016,
  Eqs. (4.4)-(4.5); 0 on level steps) with its variance, climbed over the step's gait
  cycle (t − duration, t] (t the pitch maximum): each epoch takes the share of v and of
  its variance that falls into it, h ← h + v·δt/duration, so the height the barometer
  sees climbing through a step is the filter's too; a step's variance is
  max(σ_v², (f·v)²) with f = ``step_vertical_sigma_fraction`` (a step's v is no better
  than that fraction of itself however small the navigator's σ);
- :meth:`HeightFilter.pressure`: readings p [Pa] become barometric heights
  z = pdr_core.sensors.atmosphere.height_m(p) and are averaged over epochs of ``epoch_s``
  (a fixed grid of absolute time, so any chunking cuts them alike); each epoch's mean is
  one measurement z = h + b + n of the height at the epoch's middle, R = σ_z²/N + σ_c² with
  σ_z² = (σ_p² + q²/12)·(dh/dp)² (σ_p a reading's noise at 25 Hz, q its step, dh/dp at the
  first reading), σ_c the slow noise the mean keeps (``correlated_noise_hpa``) and N the
  epoch's readings counted by the time they span: N = 25 Hz·Σ s_i
  (pdr_core.sensors.barometry.PRESSURE_NOISE_RATE_HZ), s_i the time since the last new reading
  (at most 1 s, READING_SPAN_MAX_S), 0 for a reading that repeats the one before. A
  barometer read at 1 Hz averages a second (its noise is 5 times smaller than at 25 Hz),
  so an epoch of it weighs what the same time at 25 Hz weighs; a held value repeated
  (an app that samples faster than its sensor, readings filled in between real ones)
  adds nothing. Counted as readings, 1 Hz readings weighed a 25th of what they are worth,
  and a wrong climb (a lone step the flight check held back as stairs and then refused,
  whose climb the filter has) stayed in h four times longer than at 25 Hz;
- :meth:`HeightFilter.vertical_force`: f_up [m/s²], the specific force along the
  navigation frame's up axis (≈ g at rest), averaged per epoch for the lift test below.

Between epochs (Δt = ``epoch_s``) h holds, b drifts with ḃ and walks slowly, and ḃ is a
first-order Gauss-Markov process (σ_w = ``weather_drift_hpa_per_h``, correlation time
τ_w = ``weather_drift_time_s``)::

    h ← h
    b ← b + Δt·ḃ + w_b,        var(w_b) = q_b·Δt   (q_b: offset_walk_hpa_per_sqrt_h)
    ḃ ← φ·ḃ + w_ḃ,             φ = exp(−Δt/τ_w),   var(w_ḃ) = σ_w²·(1 − φ²)

The weather moves the pressure by up to about 1 hPa/h, 8 m/h of barometric height
(Parviainen et al. 2008); over a staircase's half minute that is 7 cm, so the barometer
measures a climb's height while level walking pins h and leaves every slow change to b.
A sudden offset (a door to a pressurised stairwell, a lift lobby's ventilation: 0.2-0.4 hPa,
2-3 m, for a minute) is a jump of b: an innovation ν = z − h − b beyond the χ² gate
(``offset_jump_gate_probability``, 1 dof) adds a jump's variance σ_j² to P_bb before the
update, so b takes the jump and h keeps its value. More than
pdr_core.sensors.barometry.OFFSET_JUMPS_MAX_PER_MIN (4) jumps within 60 s while the barometric
height is still (no change in progress below: a lift ride jumps at every epoch until it is
judged) is no barometer to trust: from then on the filter stops fusing it (no update, no
change judged; h goes on from the steps alone, as without a barometer) and says so once
(an InputWarning, and :meth:`HeightFilter.status`).

(Muralidharan et al. 2014 found a phone's absolute pressure a poor guide to its floor, as
it differs between phones and drifts with time and place, while its changes over a short
time are good ones; B-Loc, Ye et al. 2014, counts floors from such changes.)

**Changes of the barometric height and the rides.** The filter alone would give b every
change no step explains, a lift ride included. A detector watches the epochs' barometric
heights: a change starts when the height moves faster than ``motion_speed_mps`` over
``motion_window_s`` (a backward difference) and ends when it has held still for
``settle_s``; its height D is the mean of the level after less the mean of the level
before (each ``settle_s`` long, the weather's ḃ·Δt taken off), and its start and end are
when the height passes 10 % and 90 % of D. Then it is judged, in this order:

1. **stairs** when a stairs step falls within it: the steps and the filter have it;
2. **a lift** when the person stood still through it (f_up's σ within an epoch below
   ``still_force_sigma_mps2`` for ``lift_min_still_fraction`` of the epochs, still ones
   at both ends) and the vertical force shows the ride: its double integral
   D_acc = ∫∫ (f_up − mean f_up), with zero velocity at both ends of the still span
   (the velocity's linear trend removed, which also takes out any bias of the force), has
   the sign of D and |D| within a factor ``lift_height_ratio_max``, and its speed peaks
   beyond ``lift_min_speed_mps`` in D's direction. A lift gives an acceleration pulse and
   a deceleration pulse of 0.3-1 m/s² and 1-2 s each; an offset of the barometer gives
   none (FTrack, Ye et al. 2012, reads lift rides from the accelerometer's pulses alone);
3. **an escalator** (``escalators``) when the change took at least ``escalator_min_s``
   (10-90 %) and its 1 s speed never exceeded ``escalator_max_speed_mps``: an escalator
   climbs at 0.2-0.4 m/s, without pulses, while the person stands or walks on level
   steps; an offset is a step of the pressure within a second or two. (A staircase the
   step detector took for level walking is also a slow, smooth change without stairs
   steps: it counts as an escalator, and the filter gets its height right.)
4. otherwise **an offset** of the barometer, which b keeps.

A ride of at least ``ride_min_height_m`` moves its height from b to h (h + b, which the
barometer measures, unchanged): h ← h_before + D, b ← b − δ with δ the part moved, and
P ← P + σ_D²·g·gᵀ, g = [1, −1, 0]. A ride shows in h when it has ended and held for
``settle_s`` (about 4 s after the car stops); :meth:`HeightFilter.step` reports it at the
next step. Floors are round(h / floor height), as pdr_pocket.stairs counts them.

**Time and chunks.** Epochs are processed when a step or :meth:`HeightFilter.advance`
reaches past their end, so every reading stamped before a step's time must have been given
before :meth:`HeightFilter.step` is called (later ones may come earlier: they wait).
Steps come in time order, and :meth:`HeightFilter.advance` goes no further than the
earliest time a step yet to come may climb from (the last step's time while walking; the
end of the walk); a step climbing from a time already processed climbs in the next epoch
instead (counted, :attr:`HeightFilter.late_steps`), and only then does the chunking
matter. A reading stamped before the time already processed is late:
dropped and counted, as are NaN readings and stamps that do not increase
(:attr:`HeightFilter.dropped`). A pressure no person meets (beyond 30-110 kPa) is a glitch,
dropped and counted, unless the readings are plausible in hPa or kPa: then a ValueError
names the unit, since every reading of that sensor will be wrong alike.

Without a pressure reading (none yet, or ``enabled: false``) :meth:`HeightFilter.step` is
h ← h + v and σ² ← σ² + σ_v² exactly, the navigator's own height.

- :class:`HeightFilter`: the filter (the Kalman filter and the change detector);
  pdr_pocket.ride_judge: what a change was; pdr_pocket.height_records: what a step gets
  back (:class:`~pdr_pocket.height_records.StepHeight`), a change judged
  (:class:`~pdr_pocket.height_records.HeightChange`), whether the barometer is fused
  (:class:`~pdr_pocket.height_records.BarometerStatus`) and the configuration in SI units
  per epoch (:class:`~pdr_pocket.height_records.HeightCoefficients`).
"""
from __future__ import annotations

import warnings

import numpy as np

from pdr_core.errors import InputWarning
from pdr_core.sensors.atmosphere import height_m, metres_per_pascal
from pdr_core.sensors.barometry import (
    MISGIVEN_UNITS_PA,
    OFFSET_JUMPS_MAX_PER_MIN,
    PRESSURE_NOISE_RATE_HZ,
    READING_SPAN_MAX_S,
    RIDE_KINDS,
    HeightChangeKind,
    misgiven_unit,
    plausible_pressure,
)
from pdr_core.topics import IMU_PRESSURE
from pdr_core.vocabulary import FLOOR_HEIGHT_M
from pdr_pocket.config import BarometerConfig
from pdr_pocket.height_records import (
    BarometerStatus,
    ChangeInProgress,
    Climb,
    Epochs,
    HeightChange,
    HeightCoefficients,
    PendingReadings,
    StepHeight,
    epoch_means,
)
from pdr_pocket.ride_judge import change_height_variance, change_kind, force_height, passages

H, B, BDOT = range(3)           # the state's indices
SECONDS_PER_MINUTE = 60.0


class HeightFilter:
    """Steps and the barometer to a height, floors and rides (the module docstring).

    ``config`` (default BarometerConfig()); ``floor_height_m`` the floors' height [m], the
    navigator's StairsConfig.floor_height_m. Attributes: :attr:`changes` every judged
    change, :attr:`rides` the lifts and escalators among them, :attr:`jumps` the offset
    jumps the gate let in, :attr:`dropped` the readings dropped by reason,
    :attr:`distrusted_s` when it stopped fusing a barometer that jumped too often (None
    while it fuses); :meth:`status` says which."""

    def __init__(self, config: BarometerConfig | None = None,
                 floor_height_m: float = FLOOR_HEIGHT_M) -> None:
        self.config = config or BarometerConfig()
        self.floor_height_m = float(floor_height_m)
        self.coefficients: HeightCoefficients | None = None
        self._h, self._var = 0.0, 0.0           # the height while there is no barometer
        self.x: np.ndarray | None = None        # [h, b, ḃ] once the barometer is on
        self.P: np.ndarray | None = None
        # per pressure reading its barometric height [m] and the time it spans [s]
        self._pressure, self._force = PendingReadings(columns=2), PendingReadings()
        self._last_z, self._last_new_s = np.nan, -np.inf     # the last new reading's
        self._readings, self._first_reading_s = 0, np.nan
        self._jumps_s: list[float] = []         # when the offset jumps came [s]
        self.distrusted_s: float | None = None  # when the filter stopped fusing it [s]
        self._through = None                    # epochs before this one are processed
        self._epochs = Epochs()
        self._change: ChangeInProgress | None = None
        self._climbs: list[Climb] = []         # steps' climbs not wholly in h yet
        self._stairs: list[tuple[float, float]] = []    # stairs steps' cycles [s]
        self._last_step_s = -np.inf
        self.late_steps = 0
        self._unreported: list[HeightChange] = []
        self.changes: list[HeightChange] = []
        self.jumps = 0
        self.dropped = {"pressure_nonfinite": 0, "pressure_implausible": 0,
                        "pressure_out_of_order": 0, "force_nonfinite": 0,
                        "force_out_of_order": 0}

    # --- the state -----------------------------------------------------------------------
    @property
    def fused(self) -> bool:
        """Whether the barometer is in (a reading has been processed)."""
        return self.x is not None

    def status(self) -> BarometerStatus:
        """Whether the barometer goes into the height, and why not
        (:class:`BarometerStatus`)."""
        span = self._pressure.last_t - self._first_reading_s
        rate = (self._readings - 1) / span if self._readings > 1 and span > 0 else 0.0
        if not self.config.enabled:
            state, why = "not fused", "turned off (barometer.enabled: false)"
        elif not self._readings:
            state, why = "absent", f"no {IMU_PRESSURE} reading"
        elif self.distrusted_s is not None:
            state, why = "not fused", self._distrust_reason()
        elif not self.fused:
            state, why = "not fused", "its readings wait for the first step (the height " \
                "is fused at each step)"
        else:
            state, why = "fused", ""
        return BarometerStatus(state, why, self.jumps, rate)

    def _distrust_reason(self) -> str:
        return (f"its offset jumped {OFFSET_JUMPS_MAX_PER_MIN + 1} times within a minute by "
                f"{self.distrusted_s:.1f} s (more than {OFFSET_JUMPS_MAX_PER_MIN} a minute is "
                f"no barometer to trust): not fused from then on, the height from the steps "
                f"alone")

    @property
    def height_m(self) -> float:
        """h [m] above the start, the steps' climbs not yet processed included."""
        if not self.fused:
            return self._h
        return float(self.x[H]) + sum(c.v * (1.0 - c.applied) for c in self._climbs)

    @property
    def sigma_m(self) -> float:
        """σ of h [m]."""
        if not self.fused:
            return float(np.sqrt(self._var))
        return float(np.sqrt(self.P[H, H] + sum(c.var * (1.0 - c.applied)
                                                for c in self._climbs)))

    @property
    def floor(self) -> int:
        """The floor at h: round(h / floor height), as pdr_pocket.stairs counts it."""
        return self._floor(self.height_m)

    def _floor(self, h: float) -> int:
        return int(np.round(h / self.floor_height_m))

    @property
    def rides(self) -> list[HeightChange]:
        """The lift and escalator rides so far."""
        return [change for change in self.changes if change.ride]

    # --- the entry points ----------------------------------------------------------------
    def pressure(self, t_s, pressure_pa) -> None:
        """Barometer readings: stamps [s] and pressures [Pa], 1-D arrays alike. NaN,
        late or non-increasing readings and glitches beyond 30-110 kPa are dropped and
        counted; ValueError when the readings are plausible in hPa or kPa instead."""
        readings = self._finite(t_s, pressure_pa, "pressure")
        if readings is None:
            return
        t, p = readings
        plausible = plausible_pressure(p)
        if not plausible.all():
            unit = misgiven_unit(p[~plausible])
            if unit is not None:
                raise ValueError(
                    f"pressure {float(np.median(p[~plausible])):g} Pa is no air pressure "
                    f"near the ground (30-110 kPa) but is one in {unit}: give Pa "
                    f"(sensor_msgs/FluidPressure), i.e. multiply by "
                    f"{MISGIVEN_UNITS_PA[unit]:g}")
            self.dropped["pressure_implausible"] += int(np.count_nonzero(~plausible))
            t, p = t[plausible], p[plausible]
        ordered = self._ordered(t, self._pressure, "pressure")
        t, p = t[ordered], p[ordered]
        if not len(t):
            return
        if self.coefficients is None:
            self.coefficients = HeightCoefficients.from_config(
                self.config, float(metres_per_pascal(p[0])))
            self._first_reading_s = float(t[0])
        self._readings += len(t)
        z = height_m(p)
        self._pressure.add(t, np.column_stack([z, self._spans(t, z)]))

    def _spans(self, t: np.ndarray, z: np.ndarray) -> np.ndarray:
        """The time [s] each reading (stamps ``t``, heights ``z``) spans (the module
        docstring): since the last new reading, at most READING_SPAN_MAX_S; 1/25 s for the
        first ever; 0 for a reading that repeats the one before."""
        new = z != np.concatenate([[self._last_z], z[:-1]])
        since = np.maximum.accumulate(np.concatenate([[self._last_new_s],
                                                      np.where(new, t, -np.inf)]))
        span = np.minimum(t - since[:-1], READING_SPAN_MAX_S)
        span[~np.isfinite(span)] = 1.0 / PRESSURE_NOISE_RATE_HZ
        self._last_z, self._last_new_s = float(z[-1]), float(since[-1])
        return np.where(new, span, 0.0)

    def vertical_force(self, t_s, f_up_mps2) -> None:
        """The accelerometer's specific force along the navigation frame's up axis: stamps
        [s] and f_up [m/s²] (≈ +g at rest), 1-D arrays alike. NaN, late or
        non-increasing samples are dropped and counted."""
        samples = self._finite(t_s, f_up_mps2, "force")
        if samples is None:
            return
        t, f = samples
        ordered = self._ordered(t, self._force, "force")
        self._force.add(t[ordered], f[ordered])

    def step(self, t_s: float, v_m: float, v_var_m2: float, on_stairs: bool,
             duration_s: float) -> StepHeight:
        """A step: its time ``t_s`` [s] (the pitch maximum that ends its gait cycle), its
        climb ``v_m`` [m] with variance ``v_var_m2`` [m²] over the cycle of
        ``duration_s`` [s] before it; ``on_stairs``: a stairs step. Every reading stamped
        before ``t_s`` must have been given. Returns the fused height, its σ, the floor and
        the rides that ended since the last step."""
        t_s = float(t_s)
        if not t_s >= self._last_step_s:
            raise ValueError(f"a step at {t_s} s after one at {self._last_step_s} s: "
                             f"steps come in time order")
        self._last_step_s = t_s
        start = t_s - max(float(duration_s), 0.0)
        if on_stairs:
            self._stairs.append((start, t_s))
        climb = None
        if (v_m or v_var_m2) and (self.fused or self._pressure.t):
            processed_s = self._processed_s()
            if start < processed_s:
                self.late_steps += 1
            climb = Climb(max(start, processed_s), max(t_s, processed_s), float(v_m),
                           max(float(v_var_m2),
                               (self.config.step_vertical_sigma_fraction * v_m) ** 2))
            self._climbs.append(climb)
        self.advance(t_s)
        if not self.fused:          # no barometer (yet): the step as the navigator has it
            if climb is not None:
                self._climbs.remove(climb)
            self._h += v_m
            self._var += v_var_m2
        rides, self._unreported = tuple(self._unreported), []
        return StepHeight(self.height_m, self.sigma_m, self.floor, rides)

    def _processed_s(self) -> float:
        """Up to when the epochs are processed [s]."""
        return -np.inf if self._through is None else self._through * self.config.epoch_s

    def advance(self, t_s: float) -> None:
        """Process the epochs that end by ``t_s`` [s]: every reading stamped before it
        must have been given, and no step yet to come may climb from before it (the
        module docstring). :meth:`step` does this itself; call it at the end of a walk, or
        while the person stands with ``t_s`` a longest gait cycle before the last
        reading, to judge the changes before it; a time already processed changes
        nothing."""
        epoch_s = self.config.epoch_s
        end = int(np.floor(float(t_s) / epoch_s))
        if self._through is not None and end < self._through:
            return
        first = self._through
        if not self.fused:
            first = self._first_pressure_epoch(first)
            if first is None or end <= first:   # no reading yet: nothing to process
                self._force.take(end, end, epoch_s)
                self._through = end
                return
        if end <= first:
            return
        self._through = end
        count = end - first
        zi, readings = self._pressure.take(first, end, epoch_s)
        fi, f = self._force.take(first, end, epoch_s)
        _, z_mean, _ = epoch_means(zi, readings[:, 0], count)
        nz = np.bincount(zi, weights=readings[:, 1], minlength=count) * PRESSURE_NOISE_RATE_HZ
        nf, f_mean, f_sigma = epoch_means(fi, f, count)
        still = (nf > 1) & (f_sigma < self.config.still_force_sigma_mps2)
        for i in range(count):
            self._epoch(first + i, float(z_mean[i]), float(nz[i]), float(f_mean[i]),
                        bool(still[i]))

    # --- the readings --------------------------------------------------------------------
    def _finite(self, t_s, values, sensor: str) -> tuple[np.ndarray, np.ndarray] | None:
        """A sensor's stamps and values as 1-D arrays without the non-finite ones (counted
        as ``<sensor>_nonfinite``); None when the barometer is off."""
        t = np.atleast_1d(np.asarray(t_s, float))
        v = np.atleast_1d(np.asarray(values, float))
        if t.ndim != 1 or t.shape != v.shape:
            raise ValueError(f"the stamps and the {sensor} values must be 1-D arrays of one "
                             f"length, got shapes {t.shape} and {v.shape}")
        if not self.config.enabled:
            return None
        finite = np.isfinite(t) & np.isfinite(v)
        self.dropped[f"{sensor}_nonfinite"] += int(np.count_nonzero(~finite))
        return t[finite], v[finite]

    def _ordered(self, t: np.ndarray, samples: PendingReadings, sensor: str) -> np.ndarray:
        """Whether each stamp increases on every one before it and lies in an epoch not
        yet processed (the others counted as ``<sensor>_out_of_order``)."""
        before = np.maximum.accumulate(np.concatenate([[samples.last_t], t[:-1]]))
        ok = t > before
        if self._through is not None:
            ok &= np.floor(t / self.config.epoch_s) >= self._through
        self.dropped[f"{sensor}_out_of_order"] += int(np.count_nonzero(~ok))
        return ok

    def _first_pressure_epoch(self, through: int | None) -> int | None:
        if not self._pressure.t:
            return None
        first = int(np.floor(self._pressure.t[0][0] / self.config.epoch_s))
        return first if through is None else max(first, through)

    # --- the filter ----------------------------------------------------------------------
    def _epoch(self, k: int, z: float, n: float, force: float, still: bool) -> None:
        """One epoch k with ``n`` readings' worth (the module docstring): predict, update
        with its mean barometric height, look for changes (not once the barometer is
        distrusted)."""
        c = self.coefficients
        if self.fused:
            self._predict()
        self._climb((k + 0.5) * c.epoch_s)      # z is the height at the epoch's middle
        r = c.reading_var_m2 / max(n, 1.0 / PRESSURE_NOISE_RATE_HZ) + c.correlated_var_m2
        if not self.fused:                      # the first epoch with readings
            self.x = np.array([self._h, z - self._h, 0.0])
            self.P = np.diag([self._var, r, c.drift_var_m2ps2])
        elif n > 0 and self.distrusted_s is None:
            self._update(z, r, (k + 0.5) * c.epoch_s)
        self._climb((k + 1) * c.epoch_s)
        e = self._epochs
        e.append(start_s=k * c.epoch_s, z=z, n=n, force=force, still=still,
                 h=float(self.x[H]))
        if self.distrusted_s is None:
            self._detect(len(e) - 1)

    def _predict(self) -> None:
        c = self.coefficients
        dt = c.epoch_s
        transition = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, dt], [0.0, 0.0, c.drift_decay]])
        self.x = transition @ self.x
        self.P = transition @ self.P @ transition.T + np.diag(
            [0.0, c.offset_walk_var_m2, c.drift_var_m2ps2 * (1.0 - c.drift_decay**2)])

    def _climb(self, t_s: float) -> None:
        """Put into h the steps' climbs up to ``t_s`` [s]."""
        dv = dvar = 0.0
        for climb in self._climbs:
            share = climb.share(t_s)
            dv += climb.v * (share - climb.applied)
            dvar += climb.var * (share - climb.applied)
            climb.applied = share
        self._climbs = [climb for climb in self._climbs if climb.applied < 1.0]
        if self.fused:
            self.x[H] += dv
            self.P[H, H] += dvar
        else:
            self._h += dv
            self._var += dvar

    def _update(self, z: float, r: float, t_s: float) -> None:
        """z = h + b + n at ``t_s`` [s], var(n) = r; an innovation beyond the gate is a
        jump of b, and too many of them end the fusion (the module docstring)."""
        nu = z - self.x[H] - self.x[B]
        ph = self.P[:, H] + self.P[:, B]            # P·Hᵀ, H = [1, 1, 0]
        s = ph[H] + ph[B] + r
        if nu * nu > self.coefficients.gate_nis * s:
            if self._jumped(t_s):
                return
            self.P[B, B] += self.coefficients.jump_var_m2
            ph = self.P[:, H] + self.P[:, B]
            s = ph[H] + ph[B] + r
        gain = ph / s
        self.x = self.x + gain * nu
        self.P = self.P - np.outer(gain, ph)

    def _jumped(self, t_s: float) -> bool:
        """Count an offset jump at ``t_s`` [s]; True when, the barometric height still
        (no change in progress: a ride jumps at every epoch until it is judged), it makes
        more than OFFSET_JUMPS_MAX_PER_MIN such jumps within a minute: the barometer is
        distrusted from then on (said once, as an InputWarning)."""
        self.jumps += 1
        if self._change is not None:
            return False
        self._jumps_s = [t for t in self._jumps_s if t > t_s - SECONDS_PER_MINUTE] + [t_s]
        if len(self._jumps_s) <= OFFSET_JUMPS_MAX_PER_MIN:
            return False
        self.distrusted_s = t_s
        warnings.warn(InputWarning(IMU_PRESSURE, self._distrust_reason()), stacklevel=2)
        return True

    # --- changes of the barometric height ------------------------------------------------
    def _detect(self, e: int) -> None:
        """The change detector at epoch index e (the module docstring)."""
        c = self.coefficients
        span, settle = c.motion_epochs, c.settle_epochs
        epochs = self._epochs
        moving = False
        if e - span - settle >= epochs.first:     # a level to measure a change from
            speed = (epochs.value("z", e) - epochs.value("z", e - span)) / (span * c.epoch_s)
            moving = bool(abs(speed) >= self.config.motion_speed_mps)   # NaN: not moving
        change = self._change
        if change is None:
            if moving:
                self._change = ChangeInProgress(e, e)
        elif moving:
            change.last, change.still_epochs = e, 0
        else:
            change.still_epochs += 1
            if change.still_epochs >= settle:
                self._judge(change)
                self._change = None
        if self._change is not None and e - self._change.first > c.max_change_epochs:
            self._record(HeightChangeKind.UNRESOLVED, epochs.value("start_s", self._change.first),
                         epochs.value("start_s", e) + c.epoch_s, np.nan, np.nan, 0)
            self._change = None
        keep = (self._change.first if self._change is not None else e) - 2 * span - settle
        if keep - epochs.first > 4 * (c.max_change_epochs + 2 * span + settle):
            epochs.forget_before(keep)
            self._stairs = [s for s in self._stairs if s[1] >= epochs.value("start_s", keep)]

    def _judge(self, change: ChangeInProgress) -> None:
        """Measure a change that has ended and decide what it was."""
        c, epochs = self.coefficients, self._epochs
        lo = change.first - c.motion_epochs     # the motion lies within [lo, change.last]
        before_lo = lo - c.settle_epochs
        after_lo, after_hi = change.last + 1, change.last + 1 + c.settle_epochs
        if before_lo < epochs.first:
            self._record(HeightChangeKind.UNRESOLVED,
                         epochs.value("start_s", max(lo, epochs.first)),
                         epochs.value("start_s", change.last) + c.epoch_s, np.nan, np.nan, 0)
            return
        before, after = epochs.array("z", before_lo, lo), epochs.array("z", after_lo, after_hi)
        if not (np.isfinite(before).any() and np.isfinite(after).any()):
            self._record(HeightChangeKind.UNRESOLVED, epochs.value("start_s", lo),
                         epochs.value("start_s", change.last) + c.epoch_s, np.nan, np.nan, 0)
            return
        level_before, level_after = float(np.nanmean(before)), float(np.nanmean(after))
        span_s = (after_lo + after_hi - before_lo - lo) / 2.0 * c.epoch_s
        height = level_after - level_before - float(self.x[BDOT]) * span_s
        z = epochs.array("z", lo, after_lo)
        start, end = passages(z, level_before, level_after)
        start_s = epochs.value("start_s", lo + start)
        end_s = epochs.value("start_s", lo + end) + c.epoch_s
        h_before = epochs.value("h", lo - 1)
        accel = force_height(self.config, epochs, lo, change.last + 1, lo + start, lo + end)
        kind = change_kind(self.config, self._stairs, height, start_s, end_s, z[start:end + 1],
                           accel)
        if kind is None:
            return
        if kind in RIDE_KINDS:
            moved = h_before + height - float(self.x[H])
            self.x[H] += moved
            self.x[B] -= moved
            epochs.shift_h(lo, moved)         # h since it began
            g = np.array([1.0, -1.0, 0.0])
            self.P = self.P + np.outer(g, g) * change_height_variance(c, epochs, before, after)
        floors = self._floor(float(self.x[H])) - self._floor(h_before)
        self._record(kind, start_s, end_s, height, accel, floors)


    def _record(self, kind: HeightChangeKind, start_s: float, end_s: float, height: float,
                accel: float, floors: int) -> None:
        change = HeightChange(kind, float(start_s), float(end_s), float(height), int(floors),
                              float(accel))
        self.changes.append(change)
        if change.ride:
            self._unreported.append(change)


