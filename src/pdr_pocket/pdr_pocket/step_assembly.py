"""The pocket navigator's steps (Muñoz Díaz 2016, chapter 4 and Eq. (5.1)): from the
stream the pitch source gives (pdr_pocket.pitch_source) to steps with their pose.

- the step detector (:mod:`pdr_pocket.steps`): the pitch maxima (Section 4.1), or
  without a gyroscope the footfalls;
- per step: the activity (Section 4.1.3), the stride (the placement's model, bounded by
  what a person walks, pdr_pocket.placement and pdr_core.walking.gait), the vertical displacement
  (Eqs. (4.4)-(4.5)) checked against a staircase's (pdr_pocket.stairs), the heading (the
  circular mean of the thigh's heading over the cycle, which cancels the hip sway, less
  ``heading_drift_correction_deg_per_s`` times the time: the offline drift correction)
  and the position filter (Eq. (5.1), chapter 6);
- with a barometer (``imu/pressure``), the height: each step's climb fused with the
  barometric height (:mod:`pdr_pocket.height_filter`), the floors from it, and the lift
  and escalator rides it finds, said by the first step after them; without one, the
  steps' climbs alone, as before;
- per sample between steps: the last step's activity, or standing/sitting from the
  thigh's tilt after ``rest_after_s`` without a step;
- what is implausible in the result (the warnings).

:class:`StepAssembly` keeps what a step needs from the samples before it (the cycle's
heading, vertical specific force and tilt), so the chunks can be cut anywhere.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from pdr_core.maths.angles import wrap_angle
from pdr_core.maths.rotations import about_vertical, covariance_about_vertical
from pdr_core.vocabulary import STAIRS_ACTIVITIES, Activity, Ride
from pdr_core.walking.gait import MAX_WALKING_SPEED_MPS, WALK_RATIO_MAX_M_PER_SPM, stride_bound_m
from pdr_pocket.activity import StepShape, activity_classifier, rest_activity
from pdr_pocket.compiled_peaks import EV_MAX, EV_MIN, EV_T_CONFIRM, EV_T_MAX
from pdr_pocket.config import PocketConfig, StairsConfig
from pdr_pocket.height_filter import HeightFilter
from pdr_pocket.height_records import StepHeight
from pdr_pocket.pitch_source import PitchChunk
from pdr_pocket.placement import PlacementClassifier
from pdr_pocket.position import PositionFilter
from pdr_pocket.records import RIDES, StepRecord
from pdr_pocket.samples import Samples
from pdr_pocket.stairs import Staircases, vertical_displacement_m
from pdr_pocket.step_length import STRIDE_MODELS, StepLengthConfig, StrideInputs, stride_model
from pdr_pocket.steps import FootfallDetector, PitchMaximumDetector


class StepAssembly:
    """Steps from the pitch source's stream, chunk by chunk (the module docstring)."""

    def __init__(self, config: PocketConfig) -> None:
        c = config
        self.config = config
        self.detector = PitchMaximumDetector(c.steps)
        self.classifier = activity_classifier(c.activity)
        self.strides = {name: stride_model(c.step_length, c.person.height_m, name)
                        for name in STRIDE_MODELS}
        self.placement = PlacementClassifier(c.step_length)
        self.bounded_steps = 0                  # strides cut to what a person walks
        self.bounded_models: set[str] = set()   # ... by the models that gave them
        self.staircases = Staircases(c.stairs)
        self.height = HeightFilter(c.barometer, c.stairs.floor_height_m)
        self.barometer = False                  # a pressure reading has come
        self.height_m = 0.0                     # the height the steps have published [m]
        self.position = PositionFilter(c.position, stride_offset_sigma_m=(
            c.position.calibrated_stride_offset_sigma_m if c.step_length.calibrated
            else c.position.stride_offset_sigma_m))
        self.steps: list[StepRecord] = []
        # per-cycle accumulators since the last confirmed step
        self.sum_cos = self.sum_sin = 0.0
        self.vz_max, self.vz_min = -np.inf, np.inf
        self.tilt_var_max = 0.0                 # the tilt's largest variance [rad²]
        self.last_confirm = -np.inf
        self.last_activity = Activity.WALKING

    def take_lines(self, step_length: StepLengthConfig, stairs: StairsConfig) -> None:
        """The level stride line (``step_length``'s a_H, b_H and ``calibrated``) and the
        stairs lines (``stairs``' a_U, b_U, a_D, b_D) for the steps confirmed from now on:
        the stride models and Eqs. (4.4)-(4.5) read them; the placement found, the
        staircases' flight check and the position filter's state go on as they are."""
        self.config = replace(self.config, step_length=step_length, stairs=stairs)
        self.strides = {name: stride_model(step_length, self.config.person.height_m, name)
                        for name in STRIDE_MODELS}

    def use_sensors(self, gyroscope: bool) -> None:
        """Choose the step detector and the activities by the signals there are (the
        first samples tell): without a gyroscope the pitch comes from the gravity
        direction alone (pdr_pocket.pitch_source), too rough for its maxima: the footfalls
        count the steps (pdr_pocket.steps.FootfallDetector) and every step is level
        (pdr_pocket.activity.LevelOnlyActivity)."""
        self.detector = PitchMaximumDetector(self.config.steps) if gyroscope \
            else FootfallDetector(self.config.steps)
        self.classifier = activity_classifier(self.config.activity, gyroscope)

    def sense_height(self, samples: Samples, chunk: PitchChunk) -> None:
        """Give the height filter the chunk's barometer readings [Pa] and, from the first
        reading ever on, the specific force along the navigation frame's up [m/s²] (its
        lift detector's), before the chunk's steps. Without a barometer, nothing."""
        if samples.pressure is None or not self.config.barometer.enabled:
            if not self.barometer:
                return
            readings = np.zeros(len(samples), bool)
        else:
            readings = np.isfinite(samples.pressure)
        start = 0
        if not self.barometer:
            if not readings.any():
                return
            self.barometer, start = True, int(np.argmax(readings))
        if readings.any():
            self.height.pressure(samples.t[readings], samples.pressure[readings])
        self.height.vertical_force(samples.t[start:], chunk.vertical_force[start:])

    @property
    def footfalls(self) -> int:
        """Footfalls of both feet so far: those the footfall detector counted, else two
        per step."""
        if isinstance(self.detector, FootfallDetector):
            return self.detector.footfalls
        return 2 * len(self.steps)

    def add(self, chunk: PitchChunk) -> list[StepRecord]:
        """The steps the chunk's stream confirms (the module docstring)."""
        t, pitch, heading, forces, variances = chunk.stream
        vz = forces[:, 0]
        events, restarts = self._events(t, pitch, forces[:, 1], chunk.remounts_t)
        cuts = np.searchsorted(t, events[:, EV_T_CONFIRM], side="right")
        out = []
        start = 0
        for i, (event, cut) in enumerate(zip(events, cuts, strict=True)):
            self._accumulate(heading[start:cut], vz[start:cut], variances[start:cut, 1])
            start = cut
            if i in restarts:
                self.classifier.restart()
            out.append(self._step(event, float(variances[cut - 1, 0])))
        if len(events) in restarts:
            self.classifier.restart()
        self._accumulate(heading[start:], vz[start:], variances[start:, 1])
        return out

    def _events(self, t: np.ndarray, pitch: np.ndarray, force: np.ndarray,
                remounts_t: list[float]) -> tuple[np.ndarray, set[int]]:
        """The detector's confirmed maxima, and the indices of the events before which
        the mounting changed: there the detector starts afresh, and so do the level steps
        of the activities (θ is measured anew; the swings while the phone turned are not
        the gait's)."""
        parts, restarts, start = [], set(), 0
        for cut in np.searchsorted(t, remounts_t, side="left"):
            parts.append(self.detector.push(t[start:cut], pitch[start:cut], force[start:cut]))
            self.detector.restart()
            restarts.add(sum(len(p) for p in parts))
            start = cut
        parts.append(self.detector.push(t[start:], pitch[start:], force[start:]))
        return np.concatenate(parts), restarts

    def _accumulate(self, heading: np.ndarray, vz: np.ndarray, tilt_var: np.ndarray) -> None:
        ok = np.isfinite(heading)
        self.sum_cos += float(np.cos(heading[ok]).sum())
        self.sum_sin += float(np.sin(heading[ok]).sum())
        if len(vz):
            self.vz_max = max(self.vz_max, float(vz.max()))
            self.vz_min = min(self.vz_min, float(vz.min()))
            self.tilt_var_max = max(self.tilt_var_max, float(tilt_var.max()))

    def _step(self, event: np.ndarray, yaw_var: float) -> StepRecord:
        c = self.config
        t_max, t_confirm = float(event[EV_T_MAX]), float(event[EV_T_CONFIRM])
        duration = self._duration(t_max)
        amplitude_deg = float(np.degrees(event[EV_MAX] - event[EV_MIN]))
        drift = np.radians(c.position.heading_drift_correction_deg_per_s)
        heading = float(np.arctan2(self.sum_sin, self.sum_cos) - drift * t_max)
        turn = heading - self.steps[-1].heading if self.steps else 0.0
        activity = self.classifier.classify(StepShape(
            float(event[EV_MAX]), float(event[EV_MIN]), float(wrap_angle(turn)),
            duration, float(np.sqrt(self.tilt_var_max))))
        vertical_range = self.vz_max - self.vz_min
        climbed = vertical_displacement_m(activity, amplitude_deg, c.stairs)
        index = len(self.steps)
        activity, vertical = self.staircases.admit(index, t_max, activity, climbed, heading)
        # the stride is the level line's unless the step is published as stairs: one whose
        # flight the check refused is level, its stride too
        on_line = activity == Activity.WALKING
        length = self._walked(StrideInputs(amplitude_deg, duration, vertical_range)) \
            if on_line else c.step_length.stairs_stride_m
        on_stairs = activity in STAIRS_ACTIVITIES
        stairs_var = c.stairs.vertical_sigma_m**2
        # the height filter takes each stairs step's own climb over its own cycle, the one
        # the flight check holds back included (it publishes it a step late); the climbs of
        # held steps it refuses are taken back at the step that refuses them
        withdrawn = self.staircases.check.take_withdrawn()
        climb = (climbed if on_stairs else 0.0) - withdrawn
        climb_var = stairs_var if withdrawn or on_stairs else 0.0
        fused = self.height.step(t_max, climb, climb_var, on_stairs,
                                 duration) if self.barometer else None
        held = fused if fused is not None and self.height.fused else None
        if held is not None:
            vertical, self.height_m = held.height_m - self.height_m, held.height_m
        length_var = c.step_length.length_sigma_m**2
        vertical_var = stairs_var if on_stairs else (c.position.level_grade_sigma * length)**2
        # a flight's first step: the classifier's level prior may have called the step
        # before it level, whose climb (about this one's) the height then lacks
        missed = climbed**2 if on_stairs and self.last_activity not in STAIRS_ACTIVITIES \
            else 0.0
        self.position.step(length, vertical, heading, yaw_var, length_var, vertical_var,
                           duration, on_line, missed)
        if held is not None:
            self.position.hold_height(held.sigma_m**2)
        floor = held.floor if held is not None else \
            self.staircases.floor(self.position.position[2])
        ride, ride_height = _ride(fused)
        # the climbs the flight check holds back are not in z yet: 0 or all of them
        held_var = sum(self.staircases.check.held) ** 2
        covariance, published = self.position.covariance, self.position.published_covariance
        covariance[2, 2] += held_var
        published[2, 2] += held_var
        velocity = step_velocity(length, climbed if on_stairs else 0.0, heading, duration,
                                 (length_var, vertical_var, self.position.step_heading_var))
        record = StepRecord(
            index=index, t=t_max, t_confirm=t_confirm, length=length,
            vertical_displacement=vertical, heading=heading, pitch_max=float(event[EV_MAX]),
            pitch_min=float(event[EV_MIN]), duration=duration, activity=activity,
            position=self.position.position, covariance=covariance, floor=floor,
            vertical_force_range=vertical_range, ride=ride, ride_height=ride_height,
            velocity=velocity[0], velocity_covariance=velocity[1],
            odometry_covariance=published)
        self.steps.append(record)
        self.sum_cos = self.sum_sin = 0.0
        self.vz_max, self.vz_min = -np.inf, np.inf
        self.tilt_var_max = 0.0
        self.last_confirm = t_confirm
        self.last_activity = activity
        return record

    def bound_warning(self) -> str | None:
        """What to say when strides needed the bound (None otherwise)."""
        if not self.bounded_steps:
            return None
        return (f"{self.bounded_steps} of {len(self.steps)} strides were longer than a "
                f"person walks at their cadence and were cut to it (walk ratio "
                f"{WALK_RATIO_MAX_M_PER_SPM} m per step/min): the stride model "
                f"({', '.join(sorted(self.bounded_models))}) does not hold for this "
                f"placement or sensor; calibrate it (pdr-pocket calibrate-step) or choose "
                f"another")

    def speed_warning(self) -> str | None:
        """What to say when the level steps, taken together, walk faster than a person
        walks (pdr_core.walking.gait.MAX_WALKING_SPEED_MPS; None otherwise)."""
        level = [s for s in self.steps if s.activity == Activity.WALKING]
        walked_s = sum(s.duration for s in level)
        if not walked_s:
            return None
        speed = sum(s.length for s in level) / walked_s
        if speed <= MAX_WALKING_SPEED_MPS:
            return None
        return (f"the level steps walk {speed:.1f} m/s, faster than a person walks "
                f"({MAX_WALKING_SPEED_MPS:g} m/s): the strides or the step times are wrong "
                f"(stamps in another unit, a run, or a stride model that does not hold)")

    def _walked(self, x: StrideInputs) -> float:
        """The stride [m] of the placement's model (pdr_pocket.placement), at most what a
        person walks at the cycle's cadence (pdr_core.walking.gait.stride_bound_m); a stride cut to
        it is counted."""
        model = self.placement.add(x).model
        length = self.strides[model].length(x)
        bound = stride_bound_m(x.duration_s, self.config.person.height_m)
        if length <= bound:
            return length
        self.bounded_steps += 1
        self.bounded_models.add(model)
        return bound

    def _duration(self, t_max: float) -> float:
        """The cycle's duration [s]: since the last step's maximum, or after a stop the
        last cycle's (the nominal one before any)."""
        c = self.config.steps
        if self.steps and t_max - self.steps[-1].t <= c.max_step_period_s:
            return t_max - self.steps[-1].t
        return self.steps[-1].duration if self.steps else c.nominal_step_period_s

    def activity(self, t: np.ndarray, tilt: np.ndarray, steps: list[StepRecord],
                  before: tuple[float, int]) -> np.ndarray:
        """Per sample: the last confirmed step's activity, or standing/sitting from the
        tilt after ``rest_after_s`` without a step; ``before``: the confirmation time and
        activity of the last step before the chunk."""
        confirms = np.array([before[0], *(s.t_confirm for s in steps)])
        labels = np.array([before[1], *(s.activity for s in steps)], dtype=np.uint8)
        idx = np.maximum(np.searchsorted(confirms, t, side="right") - 1, 0)
        resting = t - confirms[idx] > self.config.activity.rest_after_s
        return np.where(resting, rest_activity(tilt, self.config.activity),
                        labels[idx]).astype(np.uint8)

    def turn_partial_heading(self, turned_rad: float) -> None:
        """The heading summed since the last step, turned as the yaw was: a correction
        counts from the step it was made at (the one that found the landmark), whether it
        comes right after that step's sample (``pdr-pocket run --drift online``) or some
        samples later over the service (``pocket_pdr``), so both give the same next step."""
        c, s = np.cos(turned_rad), np.sin(turned_rad)
        self.sum_cos, self.sum_sin = (c * self.sum_cos - s * self.sum_sin,
                                      s * self.sum_cos + c * self.sum_sin)


def step_velocity(length_m: float, climb_m: float, heading_rad: float, duration_s: float,
                  variances: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
    """A step's mean velocity over its cycle in the map frame (ENU) [m/s] and its
    covariance [m²/s²]: the stride s and the step's own climb v over its duration T along
    the heading ψ (Eq. (5.1) over T), from the variances (σ_s², σ_v², σ_ψ,step²) [m², m²,
    rad²] as Σ = R(ψ)·diag(σ_s², s²·σ_ψ,step², σ_v²)·R(ψ)ᵀ/T². Across the step only the
    step's own heading error: the yaw error it shares with the attitude is common to the
    body frame the odometry's twist is expressed in. T is a detector's count of samples:
    its error (a sample, under 1 % of a cycle) is left out."""
    length_var, climb_var, heading_var = variances
    local = np.diag([length_var, length_m**2 * heading_var, climb_var])
    velocity = about_vertical([length_m, 0.0, climb_m], heading_rad) / duration_s
    return velocity, covariance_about_vertical(local, heading_rad) / duration_s**2


def _ride(fused: StepHeight | None) -> tuple[int, float]:
    """The ride (pdr_core.vocabulary.Ride, :data:`pdr_pocket.records.RIDES`) that ended
    before a step and the height it took [m]: the last one's kind, their heights summed;
    (Ride.NONE, 0) without one."""
    if fused is None or not fused.rides:
        return Ride.NONE, 0.0
    return RIDES[fused.rides[-1].kind], float(sum(r.height_m for r in fused.rides))

