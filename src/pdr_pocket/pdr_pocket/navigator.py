"""The pocket navigator: from IMU samples to steps and a 3D position (Muñoz Díaz 2016,
chapters 3, 4 and 6).

:class:`PocketNavigator` composes, per chunk of samples (one sample live, a whole record
offline, the same result either way):

1. the orientation filter (:mod:`pdr_pocket.orientation`, chapter 3), or without a
   gyroscope (``gyro=None``) the tilt of the gravity direction alone: the specific force
   through a second-order low-pass at ``gravity_cutoff_hz`` (1.5 Hz keeps the gait
   cycle's fundamental, 0.6–1.1 Hz, and drops the heel strikes and harmonics), with the
   heading unknown (yaw 0, σ 180°: the position's covariance says so);
2. the thigh frame and pitch (:mod:`pdr_pocket.compiled_mounting`); samples seen while the
   axes are still being learned (the first ``flexion_min_s`` of walking) are kept for
   ``replay_s`` and given the axes once known, so the first steps are not lost;
3. the pitch-maximum step detector (:mod:`pdr_pocket.steps`, Section 4.1);
4. per step: the activity (Section 4.1.3), the stride (Eq. (4.2), or the configured
   model), the vertical displacement (Eqs. (4.4)-(4.5)), the heading (the circular mean
   of the thigh's heading over the cycle, which cancels the hip sway, less
   ``heading_drift_correction_deg_per_s`` times the time: the offline drift correction)
   and the position filter (Eq. (5.1), chapter 6).

Between steps each sample's activity is the last step's, or standing/sitting from the
thigh's tilt after ``rest_after_s`` without a step. External corrections (Eqs. (6.2)-(6.3))
go through :meth:`PocketNavigator.apply_correction`.
"""
from __future__ import annotations

import copy
from dataclasses import dataclass, field

import numpy as np

from pdr_core.angles import wrap_angle
from pdr_core.gait import MAX_WALKING_SPEED_MPS, WALK_RATIO_MAX_M_PER_SPM, stride_bound_m
from pdr_core.rotations import rotation_from_euler, tilt_from_specific_force
from pdr_core.vocabulary import STAIRS_ACTIVITIES, Activity
from pdr_pocket.activity import StepShape, activity_classifier, rest_activity
from pdr_pocket.compiled_mounting import (
    MountingInputs,
    MountingOutputs,
    MountingParams,
    gravity_loop,
    mounting_loop,
    new_gravity_state,
    new_mounting_state,
    thigh_angles,
)
from pdr_pocket.compiled_orientation import BIAS_Z_CORRECTION, N_UPDATES, YAW_CORRECTION
from pdr_pocket.compiled_peaks import EV_MAX, EV_MIN, EV_T_CONFIRM, EV_T_MAX
from pdr_pocket.config import PocketConfig
from pdr_pocket.orientation import CORRECTION_NAMES, AttitudeEstimate, OrientationFilter
from pdr_pocket.placement import PlacementClassifier
from pdr_pocket.position import PSI, PositionFilter
from pdr_pocket.stairs import Staircases, vertical_displacement_m
from pdr_pocket.step_length import STRIDE_MODELS, StrideInputs, stride_model
from pdr_pocket.steps import FootfallDetector, PitchMaximumDetector

THIGH_UP, THIGH_FLEXION = np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0])
LEVEL_VERTICAL_VAR_M2 = 0.0
GRAVITY_TILT_SIGMA_RAD = np.radians(5.0)    # tilt from the low-passed specific force
MOTION_TIME_CONSTANT_S = 0.5                # of the accelerometer's motion measure
# a cascade of two first-order low-passes has its −3 dB point at √(√2 − 1)/(2πτ)
CASCADE_FACTOR = np.sqrt(np.sqrt(2.0) - 1.0)
NO_GAIT_MIN_MOVING_S = 5.0                  # moving this long without a step: no thigh gait
# the request's field of each correction (pdr_msgs/srv/ApplyCorrection)
CORRECTION_FIELDS = {YAW_CORRECTION: "yaw", BIAS_Z_CORRECTION: "gyro_bias_z"}


@dataclass(frozen=True)
class StepRecord:
    """One step (pdr_msgs/Step fields, SI) with the pose after it."""

    index: int
    t: float                    # the pitch maximum [s]
    t_confirm: float            # when it was known (the navigator's output time) [s]
    length: float
    vertical_displacement: float
    heading: float
    pitch_max: float
    pitch_min: float
    duration: float
    activity: int
    position: np.ndarray
    covariance: np.ndarray
    floor: int
    vertical_force_range: float     # max − min of the vertical specific force [m/s²]

    @property
    def pitch_amplitude(self) -> float:
        return self.pitch_max - self.pitch_min


@dataclass
class NavigatorOutput:
    """A chunk's results: the attitude per sample, the thigh pitch and heading [rad] (NaN
    while the axes are unknown), the activity per sample and the steps confirmed."""

    attitude: AttitudeEstimate
    pitch: np.ndarray
    heading: np.ndarray
    activity: np.ndarray
    steps: list[StepRecord] = field(default_factory=list)

    @staticmethod
    def concatenate(outputs: list[NavigatorOutput]) -> NavigatorOutput:
        """One output of consecutive chunks' outputs."""
        a = [o.attitude for o in outputs]
        attitude = AttitudeEstimate(*(np.concatenate([getattr(x, f) for x in a]) for f in
                                      ("t", "attitude", "bias", "covariance", "detected",
                                       "ran")))
        return NavigatorOutput(attitude, np.concatenate([o.pitch for o in outputs]),
                               np.concatenate([o.heading for o in outputs]),
                               np.concatenate([o.activity for o in outputs]),
                               [s for o in outputs for s in o.steps])


def mounting_params(config: PocketConfig) -> MountingParams:
    m = config.mounting
    return MountingParams(m.rpy_deg is not None, config.orientation.gravity_mps2,
                          np.radians(m.rest_rate_deg_per_s), m.rest_acc_mps2, m.rest_min_s,
                          np.radians(m.standing_max_angle_deg),
                          np.radians(m.moved_min_angle_deg),
                          np.radians(m.moving_rate_deg_per_s), m.flexion_time_constant_s,
                          m.flexion_min_s, np.radians(m.turned_min_angle_deg), m.turned_min_s,
                          m.turned_time_constant_s, np.radians(m.turned_angle_deg),
                          np.radians(m.turned_pitch_angle_deg),
                          np.radians(m.walking_pitch_deg), True)


def configured_axes(rpy_deg) -> tuple[np.ndarray, np.ndarray]:
    """u and f in the sensor frame of a mounting C_s^t given as ZYX roll, pitch, yaw."""
    c_s_t = rotation_from_euler(*np.radians(rpy_deg)).as_matrix()
    return c_s_t.T @ THIGH_UP, c_s_t.T @ THIGH_FLEXION


class PocketNavigator:
    def __init__(self, config: PocketConfig) -> None:
        self.config = config
        self.reset()

    def reset(self) -> None:
        c = self.config
        self.orientation = OrientationFilter(c.orientation)
        self.gravity_state = new_gravity_state()
        self.mounting_params = mounting_params(c)
        axes = configured_axes(c.mounting.rpy_deg) if c.mounting.rpy_deg is not None \
            else (None, None)
        self.mounting = new_mounting_state(*axes)
        self.gyroscope: bool | None = None      # known from the first samples
        self.detector = PitchMaximumDetector(c.steps)
        self.classifier = activity_classifier(c.activity)
        self.strides = {name: stride_model(c.step_length, c.person.height_m, name)
                        for name in STRIDE_MODELS}
        self.placement = PlacementClassifier(c.step_length)
        self.bounded_steps = 0                  # strides cut to what a person walks
        self.bounded_models: set[str] = set()   # ... by the models that gave them
        self.staircases = Staircases(c.stairs)
        self.position = PositionFilter(c.position)
        self.steps: list[StepRecord] = []
        self.pending: tuple | None = None       # (t, C, forces, variances) held
        # per-cycle accumulators since the last confirmed step
        self.sum_cos = self.sum_sin = 0.0
        self.vz_max, self.vz_min = -np.inf, np.inf
        self.tilt_var_max = 0.0                 # the tilt's largest variance [rad²]
        self.last_confirm = -np.inf
        self.last_activity = Activity.WALKING
        self.corrections = {"accepted": 0, "refused": 0}
        self.changes_seen = 0.0
        self.remounts_t: list[float] = []       # mounting changes of this chunk
        self.seen_s = self.moving_s = 0.0       # data seen, and moving [s]
        self.last_t: float | None = None

    def copy_state(self) -> PocketNavigator:
        """A copy to run on from here (a correction taken as of an earlier sample): its
        state deep-copied, its list of steps a new list of the same frozen records (a deep
        copy of them at every step would grow with the walk)."""
        steps, self.steps = self.steps, []
        try:
            duplicate = copy.deepcopy(self)
        finally:
            self.steps = steps
        duplicate.steps = list(steps)
        return duplicate

    # --- processing -----------------------------------------------------------------
    def process(self, t, gyro, accel, mag=None) -> NavigatorOutput:
        """Samples at times t [s] (N,), gyro [rad/s] (or None: no gyroscope), accel
        [m/s²], mag [T] (N, 3)."""
        t = np.asarray(t, float)
        accel = np.ascontiguousarray(accel, dtype=float)
        if self.gyroscope is None and len(t):
            self._sensors(gyro is not None)
        if gyro is None:
            attitude, rate = self._gravity_tilt(t, accel)
        else:
            attitude = self.orientation.run(t, gyro, accel, mag)
            rate = np.linalg.norm(gyro, axis=1)
        n = len(t)
        thigh = MountingOutputs.empty(n)
        pitch, heading, known, up, flex, changes = thigh
        # without a gyroscope the checks that read the phone's turns are off (the gravity
        # direction's pitch is too rough for them); the mean walking pitch's stays on: a
        # phone put in the pocket while walking leaves u at the first sample's force
        params = self.mounting_params if gyro is not None else \
            self.mounting_params._replace(turned_angle=np.inf, turned_min_s=np.inf,
                                          skew_check=False)
        mounting_loop(self.mounting, params, MountingInputs(
            t, np.ascontiguousarray(rate), accel, attitude.attitude), thigh)
        self._count_motion(t, rate)
        self.remounts_t.extend(t[np.flatnonzero(np.diff(changes, prepend=self.changes_seen))])
        self.changes_seen = changes[-1] if n else self.changes_seen
        # the vertical specific force (the stride model's range) and the norm (footfalls)
        forces = np.column_stack([np.einsum("nj,nj->n", attitude.attitude[:, 2, :], accel),
                                  np.linalg.norm(accel, axis=1)])
        # per sample: the yaw's variance (the step's heading) and the tilt's (how far the
        # pitch can be trusted)
        variances = np.column_stack([attitude.covariance[:, 2, 2],
                                     np.maximum(attitude.covariance[:, 0, 0],
                                                attitude.covariance[:, 1, 1])])
        stream = self._stream(t, attitude.attitude, forces, variances, pitch, heading, known,
                              up, flex)
        before = (self.last_confirm, self.last_activity)
        steps = self._steps(stream)
        tilt = np.arccos(np.clip(np.einsum("nj,nj->n", attitude.attitude[:, 2, :], up), -1, 1))
        return NavigatorOutput(attitude, pitch, heading,
                               self._activity(t, tilt, steps, before), steps)

    def _count_motion(self, t: np.ndarray, rate: np.ndarray) -> None:
        """Add the chunk's time, and its time moving (the turn rate, or without a
        gyroscope the accelerometer's motion measure, above ``moving_rate_deg_per_s``)."""
        if not len(t):
            return
        dt = np.diff(t, prepend=t[0] if self.last_t is None else self.last_t)
        self.last_t = float(t[-1])
        self.seen_s += float(dt.sum())
        self.moving_s += float(dt[rate > np.radians(
            self.config.mounting.moving_rate_deg_per_s)].sum())

    def no_step_reason(self) -> str | None:
        """Why no step was found, when none was (None otherwise): the signals were still
        (standing, or stamps in the wrong unit), or something moved that was no thigh's
        gait (the phone in a hand or a bag)."""
        if self.steps:
            return None
        if self.moving_s < NO_GAIT_MIN_MOVING_S:
            return (f"no walking found: the signals were still for {self.seen_s:.1f} s "
                    f"(moving {self.moving_s:.1f} s; standing, or a time column in the wrong "
                    "unit?)")
        return (f"motion but no thigh gait: {self.moving_s:.1f} s of {self.seen_s:.1f} s "
                "moving without a step; is the phone in a trouser pocket?")

    def _sensors(self, gyroscope: bool) -> None:
        """Choose the step detector and the activities by the signals there are (the
        first samples tell): without a gyroscope the pitch comes from the gravity
        direction alone (:meth:`_gravity_tilt`), too rough for its maxima: the footfalls
        count the steps (pdr_pocket.steps.FootfallDetector) and every step is level
        (pdr_pocket.activity.LevelOnlyActivity)."""
        self.gyroscope = gyroscope
        self.detector = PitchMaximumDetector(self.config.steps) if gyroscope \
            else FootfallDetector(self.config.steps)
        self.classifier = activity_classifier(self.config.activity, gyroscope)

    @property
    def footfalls(self) -> int:
        """Footfalls of both feet so far: those the footfall detector counted, else two
        per step."""
        if isinstance(self.detector, FootfallDetector):
            return self.detector.footfalls
        return 2 * len(self.steps)

    def detection(self) -> dict:
        """What counted the steps and what named their activities, and why (the report
        and the node's log say it)."""
        if self.gyroscope is None:
            return {"step_detector": self.detector.name, "pitch_from": "no sample yet",
                    "activities": self.classifier.name}
        pitch_from = "the orientation filter (gyroscope and accelerometer)" \
            if self.gyroscope else "the gravity direction alone (no gyroscope: the " \
            "accelerometer's low-passed specific force)"
        activities = self.classifier.name if self.gyroscope else \
            "level only (no gyroscope: the gravity direction's pitch holds no stairs evidence)"
        return {"step_detector": self.detector.name, "pitch_from": pitch_from,
                "activities": activities}

    def _gravity_tilt(self, t: np.ndarray, accel: np.ndarray
                      ) -> tuple[AttitudeEstimate, np.ndarray]:
        """Without a gyroscope: C_b^n of the gravity direction's tilt (yaw 0, unknown) and
        the motion measure scaled to a turn rate for the thigh frame's rest and motion
        tests. Its vertical, the low-passed specific force, carries the legs' accelerations,
        too rough for the walking checks of a phone turned in the pocket: they are off, and
        a moved phone is found at the next rest."""
        m = self.config.mounting
        n = len(t)
        gravity, motion = np.empty((n, 3)), np.empty(n)
        tau = CASCADE_FACTOR / (2 * np.pi * m.gravity_cutoff_hz)
        gravity_loop(self.gravity_state, tau, MOTION_TIME_CONSTANT_S, t, accel, gravity, motion)
        roll, pitch = tilt_from_specific_force(gravity)
        c = rotation_from_euler(roll, pitch, np.zeros(n)).as_matrix().reshape(n, 3, 3)
        covariance = np.zeros((n, 6, 6))
        covariance[:, 0, 0] = covariance[:, 1, 1] = GRAVITY_TILT_SIGMA_RAD**2
        covariance[:, 2, 2] = np.pi**2
        attitude = AttitudeEstimate(t, c, np.zeros((n, 3)), covariance,
                                    np.zeros((n, 4), dtype=bool),
                                    np.zeros((n, N_UPDATES), dtype=bool))
        scale = np.radians(m.moving_rate_deg_per_s) / m.accel_motion_mps2
        return attitude, motion * scale

    def _stream(self, t, c, forces, variances, pitch, heading, known, up, flex):
        """The samples the detector sees, in order: (t, θ, heading, the vertical
        specific force and its norm (N, 2), yaw and tilt variances (N, 2)), with the
        pending samples given the axes of the first known sample after them. Runs of
        known and unknown samples are taken whole."""
        change = np.flatnonzero(np.diff(known.astype(np.int8))) + 1
        segments = []
        for a, b in zip([0, *change], [*change, len(t)], strict=True):
            if a == b:
                continue
            if not known[a]:
                self._hold(t[a:b], c[a:b], forces[a:b], variances[a:b])
                continue
            if self.pending is not None:
                segments.append(self._replay(up[a], flex[a], t, pitch, heading))
            segments.append((t[a:b], pitch[a:b], heading[a:b], forces[a:b], variances[a:b]))
        if not segments:
            return (*(np.empty(0) for _ in range(3)), np.empty((0, 2)), np.empty((0, 2)))
        return tuple(np.concatenate(parts) for parts in zip(*segments, strict=True))

    def _hold(self, t, c, forces, variances) -> None:
        """Keep samples while the axes are unknown, the last ``replay_s`` of them."""
        held = (t, c, forces, variances) if self.pending is None else tuple(
            np.concatenate([old, new]) for old, new in
            zip(self.pending, (t, c, forces, variances), strict=True))
        first = np.searchsorted(held[0], held[0][-1] - self.config.mounting.replay_s,
                                side="left")
        self.pending = tuple(x[first:] for x in held)

    def _replay(self, up, flex, t, pitch, heading):
        """The held samples with the axes now known; those of this chunk are reported."""
        tp, cp, vp, yp = self.pending
        self.pending = None
        angles = np.array([thigh_angles(c, up, flex) for c in cp]).reshape(-1, 2)
        mine = tp >= t[0]
        index = np.searchsorted(t, tp[mine])
        pitch[index], heading[index] = angles[mine, 0], angles[mine, 1]
        return tp, angles[:, 0], angles[:, 1], vp, yp

    def _steps(self, stream) -> list[StepRecord]:
        t, pitch, heading, forces, variances = stream
        vz = forces[:, 0]
        events, restarts = self._events(t, pitch, forces[:, 1])
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

    def _events(self, t: np.ndarray, pitch: np.ndarray, force: np.ndarray
                ) -> tuple[np.ndarray, set[int]]:
        """The detector's confirmed maxima, and the indices of the events before which
        the mounting changed: there the detector starts afresh, and so do the level steps
        of the activities (θ is measured anew; the swings while the phone turned are not
        the gait's)."""
        parts, restarts, start = [], set(), 0
        for cut in np.searchsorted(t, self.remounts_t, side="left"):
            parts.append(self.detector.push(t[start:cut], pitch[start:cut], force[start:cut]))
            self.detector.restart()
            restarts.add(sum(len(p) for p in parts))
            start = cut
        parts.append(self.detector.push(t[start:], pitch[start:], force[start:]))
        self.remounts_t = []
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
        length = self._walked(StrideInputs(amplitude_deg, duration, vertical_range)) \
            if activity == Activity.WALKING else c.step_length.stairs_stride_m
        vertical = vertical_displacement_m(activity, amplitude_deg, c.stairs)
        index = len(self.steps)
        activity, vertical = self.staircases.admit(index, t_max, activity, vertical, heading)
        on_stairs = activity in STAIRS_ACTIVITIES
        self.position.step(length, vertical, heading, yaw_var, c.step_length.length_sigma_m**2,
                           c.stairs.vertical_sigma_m**2 if on_stairs else LEVEL_VERTICAL_VAR_M2,
                           duration)
        record = StepRecord(index, t_max, t_confirm, length, vertical, heading,
                            float(event[EV_MAX]), float(event[EV_MIN]), duration, activity,
                            self.position.position, self.position.covariance,
                            self.staircases.floor(self.position.position[2]),
                            vertical_range)
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
        walks (pdr_core.gait.MAX_WALKING_SPEED_MPS; None otherwise)."""
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

    def warnings(self) -> list[str]:
        """What is implausible or missing in the result so far (the report's and the
        log's warnings, the plot's title)."""
        return [w for w in (self.no_step_reason(), self.bound_warning(), self.speed_warning())
                if w is not None]

    def _walked(self, x: StrideInputs) -> float:
        """The stride [m] of the placement's model (pdr_pocket.placement), at most what a
        person walks at the cycle's cadence (pdr_core.gait.stride_bound_m); a stride cut to
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

    def _activity(self, t: np.ndarray, tilt: np.ndarray, steps: list[StepRecord],
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

    # --- corrections (Eqs. (6.2)-(6.3)) -----------------------------------------------
    def apply_correction(self, yaw_rad: float, yaw_var: float, bias_z: float, bias_var: float,
                         position=None, position_cov=None) -> tuple[bool, str]:
        """Add ``yaw_rad`` [rad] to the heading and ``bias_z`` [rad/s] to the z gyro bias, as
        Kalman updates with their variances (Eq. (6.2); a part whose value and variance are
        both 0 is not given), and fix the position [m] with its covariance (3, 3) [m²] (Eq.
        (6.3)) when ``position`` is given (pdr_msgs/srv/ApplyCorrection's fields).

        All or nothing: every part is checked and gated once, against the covariances
        before any part is applied; one refused part refuses the whole correction, changes
        nothing, and the message names each refused part and why. A correction with no
        part is refused: nothing to apply. Returns (accepted, message)."""
        parts = [(kind, value, variance) for kind, value, variance in (
            (YAW_CORRECTION, yaw_rad, yaw_var), (BIAS_Z_CORRECTION, bias_z, bias_var))
            if not (value == 0 and variance == 0)]
        if not parts and position is None:
            self.corrections["refused"] += 1
            return False, ("nothing to apply: yaw, gyro_bias_z and their variances are 0 and "
                           "has_position is false")
        problem = _invalid(yaw_rad, yaw_var, bias_z, bias_var, position, position_cov)
        nis: list[float] = []
        if problem is None:
            problem, nis = self._gate_correction(parts, position, position_cov)
        if problem is not None:
            self.corrections["refused"] += 1
            return False, f"nothing applied: {problem}"
        self.corrections["accepted"] += 1
        return True, ", ".join(
            self._apply_parts(parts, nis, position, position_cov))

    def _gate_correction(self, parts, position, position_cov
                         ) -> tuple[str | None, list[float]]:
        """Why the parts (kind, value to add, variance) and the position fix would be
        refused, every part gated against the covariances as they are now (None: all
        pass), and the NIS of each."""
        f = self.orientation
        zero = "; ".join(
            f"{CORRECTION_FIELDS[kind]}_variance is 0: a {CORRECTION_FIELDS[kind]} of "
            f"{value:+.4g} {CORRECTION_NAMES[kind][1]} needs a positive variance"
            for kind, value, variance in parts if variance == 0)
        if zero:
            return zero, []
        if f.state is None:
            return "the navigator has not started (no IMU sample yet)", []
        gated = [f.gate(kind, self._corrected(kind, value), variance)
                 for kind, value, variance in parts]
        if position is not None:
            gated.append(self.position.gate_position(position, position_cov))
        problems = "; ".join(problem for problem, _ in gated if problem is not None)
        return problems or None, [nis for _, nis in gated]

    def _corrected(self, kind: int, value: float) -> float:
        """The yaw [rad] or the z gyro bias [rad/s] with ``value`` added."""
        f = self.orientation
        return f.yaw + value if kind == YAW_CORRECTION else float(f.state.bias[2]) + value

    def _apply_parts(self, parts, nis, position, position_cov) -> list[str]:
        """Apply what :meth:`_gate_correction` passed, in the request's order, each as a
        measurement of the state before any (not gated again); what was done, in words."""
        f, done = self.orientation, []
        targets = [self._corrected(kind, value) for kind, value, _ in parts]
        for (kind, value, variance), target, part_nis in zip(
                parts, targets, nis[:len(parts)], strict=True):
            before = f.yaw
            f.apply(kind, target, variance)
            name, unit = CORRECTION_NAMES[kind]
            degrees = f"{np.degrees(value):+.2f}°, " if kind == YAW_CORRECTION else ""
            done.append(f"{name} {value:+.4g} {unit} ({degrees}NIS {part_nis:.2f})")
            if kind == YAW_CORRECTION:
                self._turn_partial_heading(f.yaw - before)
                self.position.correct_heading(self.position.x[PSI] + value, variance,
                                              f.yaw_variance)
            else:
                self.position.limit_drift(variance)
        if position is not None:
            self.position.apply_position(position, position_cov)
            done.append(f"position fix (NIS {nis[-1]:.2f})")
        return done

    def _turn_partial_heading(self, turned_rad: float) -> None:
        """The heading summed since the last step, turned as the yaw was: a correction
        counts from the step it was made at (the one that found the landmark), whether it
        comes right after that step's sample (``pdr-pocket run --drift online``) or some
        samples later over the service (``pocket_pdr``), so both give the same next step."""
        c, s = np.cos(turned_rad), np.sin(turned_rad)
        self.sum_cos, self.sum_sin = (c * self.sum_cos - s * self.sum_sin,
                                      s * self.sum_cos + c * self.sum_sin)


def _invalid(yaw, yaw_var, bias_z, bias_var, position, position_cov) -> str | None:
    """Why the request's numbers cannot be used (None: they can), each named by its field
    of pdr_msgs/srv/ApplyCorrection, in the service's order."""
    problems = [f"{name} {value!r} is not finite" if not np.isfinite(value) else
                f"{name} {value!r} is negative" for name, value, variance in (
                    ("yaw", yaw, False), ("yaw_variance", yaw_var, True),
                    ("gyro_bias_z", bias_z, False), ("gyro_bias_z_variance", bias_var, True))
                if not np.isfinite(value) or (variance and value < 0)]
    if position is not None:
        cov = np.asarray(position_cov, float).reshape(3, 3)
        if not np.isfinite(position).all():
            problems.append(f"position {list(map(float, position))} is not finite")
        if not np.isfinite(cov).all():
            problems.append("position_covariance is not finite")
        elif np.any(np.diag(cov) < 0):
            problems.append(f"position_covariance has a negative variance "
                            f"(diagonal {np.diag(cov).tolist()} m²)")
    return "; ".join(problems) or None
