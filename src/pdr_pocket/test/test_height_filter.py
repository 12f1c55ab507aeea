"""The height filter (pdr_pocket.height_filter) on a building walk built here: level
walking, stairs up two floors with each step's v off by up to ±20 %, a lift ride down three
floors and one up one floor standing still (the vertical force's pulses included), the
weather's worst drift (1 hPa/h), a 0.3 hPa offset of the barometer for a minute while
standing and walking level, and a phone's barometer (0.03 hPa white noise at 25 Hz in
0.01 hPa steps)."""
from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np
import pytest

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.sensors.atmosphere import pressure_pa
from pdr_core.sensors.barometry import PA_PER_HPA, HeightChangeKind
from pdr_core.vocabulary import FLOOR_HEIGHT_M
from pdr_pocket.config import BarometerConfig
from pdr_pocket.height_filter import HeightFilter

FLOOR_M = FLOOR_HEIGHT_M            # 3.5 m
BARO_HZ, FORCE_HZ = 25.0, 100.0
T0_S = 1000.013                     # the stamps start off the epochs' grid
SITE_M = 120.0                      # the building's ground floor above sea level
DRIFT_HPA_PER_H = 1.0
NOISE_HPA, QUANTUM_HPA = 0.03, 0.01
OFFSET_HPA = 0.3
FORCE_BIAS_MPS2 = 0.05              # f_up at rest is not exactly g
CYCLE_S = 1.1                       # a gait cycle, the step's duration
STEP_VAR_M2 = 0.02**2               # the navigator's σ of v (StairsConfig.vertical_sigma_m)


@dataclass
class Walk:
    """A walk's true height at FORCE_HZ, its readings and its steps:
    (t [s], v [m], var [m²], on_stairs, true height at the step [m], duration [s])."""

    t: np.ndarray
    height: np.ndarray
    baro_t: np.ndarray
    baro_pa: np.ndarray
    force_t: np.ndarray
    force: np.ndarray
    steps: list
    offset_s: tuple[float, float]


class Builder:
    """A walk segment by segment at FORCE_HZ: heights, accelerations, walking or not."""

    def __init__(self, rng: np.random.Generator) -> None:
        self.rng = rng
        self.h: list[np.ndarray] = [np.zeros(1)]
        self.acc: list[np.ndarray] = [np.zeros(1)]
        self.walking: list[np.ndarray] = [np.zeros(1, bool)]
        self.steps: list[tuple] = []

    @property
    def now(self) -> int:
        return sum(len(h) for h in self.h)

    def _add(self, h, acc, walking) -> None:
        self.h.append(h)
        self.acc.append(acc)
        self.walking.append(np.full(len(h), walking))

    def stand(self, seconds: float) -> None:
        n = int(seconds * FORCE_HZ)
        self._add(np.full(n, self.h[-1][-1]), np.zeros(n), False)

    def walk(self, cycles: int, riser_m: float = 0.0) -> None:
        """Gait cycles, level or each climbing two risers."""
        n = int(CYCLE_S * FORCE_HZ)
        for _ in range(cycles):
            h0, v = self.h[-1][-1], 2 * riser_m
            self._add(h0 + v * np.arange(1, n + 1) / n, np.zeros(n), True)
            t = (self.now - 1) / FORCE_HZ
            noisy = v * (1.0 + self.rng.uniform(-0.2, 0.2))
            self.steps.append((T0_S + t, noisy, STEP_VAR_M2 if v else 0.0, v != 0.0,
                               h0 + v, CYCLE_S))

    def lift(self, height_m: float, speed_mps: float, peak_mps2: float) -> None:
        """A ride: a sin² acceleration pulse to ``speed_mps``, a cruise, the same pulse
        back to rest."""
        pulse_s = 2.0 * speed_mps / peak_mps2
        cruise_s = max(0.0, abs(height_m) / speed_mps - pulse_s)
        tp = np.arange(int(pulse_s * FORCE_HZ)) / FORCE_HZ
        pulse = peak_mps2 * np.sin(np.pi * tp / pulse_s) ** 2 * np.sign(height_m)
        acc = np.concatenate([pulse, np.zeros(int(cruise_s * FORCE_HZ)), -pulse])
        velocity = np.cumsum(acc) / FORCE_HZ
        self._add(self.h[-1][-1] + np.cumsum(velocity) / FORCE_HZ, acc, False)

    def escalator(self, height_m: float, speed_mps: float) -> None:
        n = int(abs(height_m) / speed_mps * FORCE_HZ)
        self._add(self.h[-1][-1] + height_m * np.arange(1, n + 1) / n, np.zeros(n), False)

    def walk_of(self, offset: tuple[float, float] | None) -> Walk:
        """The readings: f_up with walking's swings or standing's sway, and the pressure
        with the weather, the offset [s from the start] and the barometer's noise."""
        rng = self.rng
        h, acc = np.concatenate(self.h), np.concatenate(self.acc)
        walking = np.concatenate(self.walking)
        t = np.arange(len(h)) / FORCE_HZ
        force = STANDARD_GRAVITY_MPS2 + FORCE_BIAS_MPS2 + acc + np.where(
            walking, 2.0 * np.sin(2 * np.pi * 2 * t / CYCLE_S) + rng.normal(0, 0.4, len(t)),
            0.02 * np.sin(2 * np.pi * 0.3 * t) + rng.normal(0, 0.03, len(t)))
        baro_t = np.arange(0.0, t[-1], 1.0 / BARO_HZ)
        p = pressure_pa(SITE_M + np.interp(baro_t, t, h))
        p += DRIFT_HPA_PER_H * PA_PER_HPA * baro_t / 3600.0
        if offset is not None:
            p += OFFSET_HPA * PA_PER_HPA * ((baro_t >= offset[0]) & (baro_t < offset[1]))
        p += rng.normal(0.0, NOISE_HPA * PA_PER_HPA, len(p))
        p = np.round(p / (QUANTUM_HPA * PA_PER_HPA)) * QUANTUM_HPA * PA_PER_HPA
        span = offset or (np.inf, np.inf)
        return Walk(T0_S + t, h, T0_S + baro_t, p, T0_S + 0.004 + t, force, self.steps,
                    (T0_S + span[0], T0_S + span[1]))


@lru_cache(maxsize=1)
def building_walk() -> Walk:
    """12 minutes: up two floors by the stairs, down three by lift, the offset, up one by
    lift, down one by the stairs: the end is a floor below the start."""
    b = Builder(np.random.default_rng(41))
    b.stand(20.0)
    b.walk(50)
    b.walk(10, 0.175)
    b.walk(3)                       # the landing
    b.walk(10, 0.175)
    b.walk(80)
    b.stand(10.0)
    b.lift(-3 * FLOOR_M, 2.0, 1.0)
    b.stand(8.0)
    b.walk(50)
    offset_start = b.now / FORCE_HZ + 10.0
    b.stand(30.0)                   # the offset starts while standing ...
    b.walk(100)                     # ... and ends while walking level
    b.stand(8.0)
    b.lift(FLOOR_M, 1.0, 0.6)
    b.stand(8.0)
    b.walk(50)
    b.walk(10, -0.175)
    b.walk(100)
    b.stand(10.0)
    return b.walk_of((offset_start, offset_start + 60.0))


def run(walk: Walk, filter_: HeightFilter, chunks: np.ndarray | None = None,
        pressure: bool = True) -> list:
    """The step outputs: every reading fed at once before the first step, or in chunks
    cut at the stamps ``chunks`` [s], each one fed as soon as a step needs it."""
    cuts = [walk.t[-1] + 1] if chunks is None else [*np.sort(chunks), walk.t[-1] + 1]
    fed, outputs = 0, []

    def feed_until(t_s: float) -> None:
        nonlocal fed
        while fed < len(cuts):
            lo, hi = -np.inf if fed == 0 else cuts[fed - 1], cuts[fed]
            if lo > t_s:
                return
            if pressure:
                b = (walk.baro_t >= lo) & (walk.baro_t < hi)
                filter_.pressure(walk.baro_t[b], walk.baro_pa[b])
            f = (walk.force_t >= lo) & (walk.force_t < hi)
            filter_.vertical_force(walk.force_t[f], walk.force[f])
            fed += 1

    for t_s, v, var, stairs, _, duration in walk.steps:
        feed_until(t_s)
        outputs.append(filter_.step(t_s, v, var, stairs, duration))
    feed_until(walk.t[-1])
    filter_.advance(walk.t[-1])
    return outputs


@lru_cache(maxsize=1)
def building_run() -> tuple[HeightFilter, list]:
    filter_ = HeightFilter(BarometerConfig(), FLOOR_M)
    return filter_, run(building_walk(), filter_)


def test_every_level_step_is_on_its_floor_lifts_included():
    walk = building_walk()
    _, outputs = building_run()
    wrong = [(round(s[0] - T0_S, 1), out.floor, round(s[4] / FLOOR_M))
             for s, out in zip(walk.steps, outputs, strict=True)
             if not s[3] and out.floor != round(s[4] / FLOOR_M)]
    assert wrong == []
    assert {round(s[4] / FLOOR_M) for s in walk.steps} == {0, 1, 2, -1}


def test_the_lift_rides_are_found_with_their_floors():
    filter_, outputs = building_run()
    rides = filter_.rides
    assert [(r.kind, r.floors) for r in rides] == [(HeightChangeKind.LIFT, -3),
                                                   (HeightChangeKind.LIFT, 1)]
    assert rides[0].height_m == pytest.approx(-3 * FLOOR_M, abs=0.3)
    assert rides[1].height_m == pytest.approx(FLOOR_M, abs=0.3)
    for ride in rides:      # the accelerometer's double integral agrees roughly
        assert 0.5 < ride.accel_height_m / ride.height_m < 2.0
        assert 2.0 < ride.end_s - ride.start_s < 10.0     # 10-90 % of 7 s and 9 s
    # each ride is reported once, by the first step after it
    assert [r for out in outputs for r in out.rides] == rides


def test_the_end_height_is_within_half_a_metre_with_the_weather_drifting():
    walk = building_walk()
    filter_, _ = building_run()
    assert walk.t[-1] - walk.t[0] > 600.0
    assert abs(filter_.height_m - walk.height[-1]) <= 0.5
    assert filter_.floor == -1
    # the drift was learned: 1 hPa/h is −8.3 m/h of barometric height
    assert filter_.x[2] * 3600.0 == pytest.approx(-8.3, abs=3.0)


def test_the_offset_changes_no_floor_and_is_no_ride():
    walk = building_walk()
    filter_, outputs = building_run()
    start, end = walk.offset_s
    around = [c for c in filter_.changes if start - 5 < c.start_s < end + 5]
    assert [c.kind for c in around] == [HeightChangeKind.OFFSET, HeightChangeKind.OFFSET]
    assert around[0].height_m == pytest.approx(-2.5, abs=0.4)
    assert around[1].height_m == pytest.approx(2.5, abs=0.4)
    during = [(out.floor, out.height_m) for s, out in zip(walk.steps, outputs, strict=True)
              if start <= s[0] <= end + 10]
    assert len(during) > 20 and {floor for floor, _ in during} == {-1}
    assert max(abs(h + FLOOR_M) for _, h in during) < 0.5
    assert filter_.jumps >= 2


def test_random_chunks_give_exactly_what_the_whole_walk_gives():
    walk = building_walk()
    _, whole = building_run()
    rng = np.random.default_rng(7)
    for count in (5, 300):
        chunks = rng.uniform(walk.t[0], walk.t[-1], count)
        filter_ = HeightFilter(BarometerConfig(), FLOOR_M)
        pieces = run(walk, filter_, chunks)
        assert repr(pieces) == repr(whole)
        assert repr(filter_.changes) == repr(building_run()[0].changes)


def test_without_pressure_the_heights_are_the_steps_own():
    walk = building_walk()
    v = np.array([s[1] for s in walk.steps])
    var = np.array([s[2] for s in walk.steps])
    # no pressure topic, and a barometer switched off in the configuration
    for config, pressure in ((BarometerConfig(), False), (BarometerConfig(enabled=False), True)):
        filter_ = HeightFilter(config, FLOOR_M)
        outputs = run(walk, filter_, pressure=pressure)
        assert [out.height_m for out in outputs] == np.cumsum(v).tolist()
        assert [out.sigma_m for out in outputs] == np.sqrt(np.cumsum(var)).tolist()
        assert not filter_.fused and filter_.rides == []


def test_a_standing_escalator_ride_is_a_ride_and_the_offset_step_is_not():
    b = Builder(np.random.default_rng(3))
    b.stand(20.0)
    b.walk(10)
    b.stand(10.0)
    b.escalator(4.5, 0.3)           # 15 s, no pulses
    b.stand(10.0)
    b.walk(10)
    walk = b.walk_of(None)
    filter_ = HeightFilter(BarometerConfig(), FLOOR_M)
    outputs = run(walk, filter_)
    assert [(r.kind, r.floors) for r in filter_.rides] == [(HeightChangeKind.ESCALATOR, 1)]
    assert outputs[-1].height_m == pytest.approx(4.5, abs=0.3)
    assert not np.isfinite(filter_.rides[0].accel_height_m)
    no_escalators = HeightFilter(BarometerConfig(escalators=False), FLOOR_M)
    assert run(walk, no_escalators)[-1].floor == 0 and no_escalators.rides == []


def test_stairs_the_steps_took_for_level_walking_climb_by_the_barometer():
    """Two flights whose steps the navigator called level (v = 0): slow, smooth changes
    while walking, so escalators, and each one's height goes to h."""
    b = Builder(np.random.default_rng(11))
    b.stand(20.0)
    b.walk(20)
    b.walk(10, 0.175)
    b.walk(4)
    b.walk(10, 0.175)
    b.walk(20)
    walk = b.walk_of(None)
    walk.steps = [(t, 0.0, 0.0, False, h, d) for t, _, _, _, h, d in walk.steps]
    filter_ = HeightFilter(BarometerConfig(), FLOOR_M)
    outputs = run(walk, filter_)
    assert [(r.kind, r.floors) for r in filter_.rides] == [(HeightChangeKind.ESCALATOR, 1)] * 2
    assert outputs[-1].height_m == pytest.approx(7.0, abs=0.3) and outputs[-1].floor == 2


def test_a_step_climbing_from_before_the_processed_time_still_climbs():
    """advance() beyond where a step to come climbs from breaks the contract: the step
    climbs in the next epoch instead, counted."""
    f = HeightFilter(BarometerConfig(), FLOOR_M)
    t = 100.0 + np.arange(250) / BARO_HZ
    f.pressure(t, pressure_pa(SITE_M + 0.3 * (t >= 105.0)))   # it climbed at 105 s
    f.advance(105.0)
    out = f.step(104.8, 0.3, 0.0, True, 1.0)
    assert f.late_steps == 1 and out.height_m == pytest.approx(0.3)
    f.advance(t[-1])
    assert f.height_m == pytest.approx(0.3, abs=0.1)


def test_a_lift_without_its_vertical_force_is_taken_for_an_offset():
    """The pulses are the lift's evidence: a standing pressure change of three floors in
    9 s without them (the force flat) is the barometer's."""
    b = Builder(np.random.default_rng(5))
    b.stand(20.0)
    b.walk(10)
    b.stand(10.0)
    b.lift(-3 * FLOOR_M, 2.0, 1.0)
    b.stand(10.0)
    b.walk(10)
    walk = b.walk_of(None)
    flat = replace(walk, force=np.where(np.abs(walk.force - STANDARD_GRAVITY_MPS2) < 1.5,
                                        STANDARD_GRAVITY_MPS2, walk.force))
    filter_ = HeightFilter(BarometerConfig(), FLOOR_M)
    assert run(flat, filter_)[-1].floor == 0
    assert filter_.rides == [] and filter_.changes[-1].kind == HeightChangeKind.OFFSET
    with_force = HeightFilter(BarometerConfig(), FLOOR_M)
    assert run(walk, with_force)[-1].floor == -3


def test_bad_readings_are_dropped_and_counted_or_named():
    f = HeightFilter(BarometerConfig(), FLOOR_M)
    t = 100.0 + np.arange(50) / BARO_HZ
    p = np.full(50, 101_000.0)
    p[3] = np.nan
    p[7] = 0.0                                  # a glitch
    f.pressure(t, p)
    f.pressure(t[:10], p[:10])                  # again: stamps that do not increase
    f.vertical_force([100.0, 100.01, 100.005, np.nan], [9.8, 9.8, 9.8, 9.8])
    assert f.dropped == {"pressure_nonfinite": 2, "pressure_implausible": 2,
                         "pressure_out_of_order": 8, "force_nonfinite": 1,
                         "force_out_of_order": 1}
    f.step(102.0, 0.0, 0.0, False, 1.0)
    f.pressure([101.5, 102.5], [101_000.0, 101_000.0])    # 101.5 s: already processed
    assert f.dropped["pressure_out_of_order"] == 9
    with pytest.raises(ValueError, match="in hPa"):
        f.pressure([103.0], [1013.25])          # hPa given as Pa
    with pytest.raises(ValueError, match="in kPa"):
        f.pressure([103.0], [101.325])
    with pytest.raises(ValueError, match="time order"):
        f.step(101.0, 0.0, 0.0, False, 1.0)
    with pytest.raises(ValueError, match="1-D arrays of one length"):
        f.pressure([1.0, 2.0], [101_000.0])


@pytest.mark.parametrize(("key", "value"), [
    ("pressure_noise_hpa", 0.0), ("epoch_s", -0.5), ("offset_jump_gate_probability", 1.0),
    ("lift_min_still_fraction", 0.0), ("lift_height_ratio_max", 1.0),
    ("pressure_resolution_hpa", -0.01), ("motion_window_s", 0.1),
    ("escalator_max_speed_mps", 0.1)])
def test_a_bad_setting_is_named(key, value):
    with pytest.raises(ValueError, match=key):
        BarometerConfig(**{key: value})
