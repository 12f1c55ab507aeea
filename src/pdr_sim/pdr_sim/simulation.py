"""From a scenario and an IMU profile to the messages of a simulated run.

:func:`simulate` samples the trajectory model of the placement (the foot,
:mod:`pdr_sim.foot_trajectory`, or the thigh in a trouser pocket,
:mod:`pdr_sim.thigh_trajectory`), computes the true signals (:mod:`pdr_sim.signals`) and
corrupts them with the profile's errors (:mod:`pdr_core.sensors.imu_errors`), all vectorised. The
result holds ``imu/data`` (sensor_msgs/Imu, REP-145, covariances from the white-noise
level), ``imu/mag`` (sensor_msgs/MagneticField) and ``ground_truth/pose``
(geometry_msgs/PoseStamped, every sample) as batches; the foot placement adds
``ground_truth/stance`` (pdr_msgs/Stance, every sample: where the sensor's true velocity
and turn rate are zero, :func:`foot_truth`), the pocket placement ``ground_truth/step``
(pdr_msgs/Step, one per true step, at its end) and ``ground_truth/landmarks``
(pdr_msgs/Landmark, every corner and flight of stairs). With ``pressure`` (opt-in,
``pdr-sim generate --pressure``) a barometer beside the IMU adds ``imu/pressure``
(sensor_msgs/FluidPressure [Pa], at the barometer's own rate, :func:`barometer_batch`);
its random draws come from a stream of their own, so everything else is the same
with and without it.
:func:`simulation_record` holds the complete configuration and the truth that has no
topic (the sensor's constant biases, revisits, activity periods), so that any run can be
reproduced and evaluated from its bag.
"""
from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pdr_core import topics
from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError
from pdr_core.frames import MAP_FRAME, SENSOR_FRAME
from pdr_core.io.batch import MessageBatch
from pdr_core.io.msgtypes import FLUID_PRESSURE, IMU, LANDMARK, MAGNETIC_FIELD, POSE_STAMPED, STEP
from pdr_core.maths.rotations import quaternion_xyzw
from pdr_core.sensors.atmosphere import pressure_pa
from pdr_core.sensors.imu_errors import (
    BarometerErrors,
    BarometerRun,
    ImuErrors,
    barometer_readings,
    corrupt,
    turn_on_bias,
)
from pdr_core.sensors.imu_profiles import PA_PER_HPA, PROFILES, profile
from pdr_core.sensors.magnetic_field import TABLE_3_3, IronDistortion, MagneticField, homogeneous
from pdr_core.vocabulary import ACTIVITY_NAMES, LandmarkType
from pdr_sim import signals
from pdr_sim.foot_trajectory import FootTrajectory, sample_times
from pdr_sim.pocket_scenario import PocketScenario, load_pocket_scenario, pocket_scenario_from_dict
from pdr_sim.scenario import MagneticFieldSpec, Scenario, load_scenario, scenario_from_dict
from pdr_sim.step_fit import pattern_from_file
from pdr_sim.thigh_trajectory import ThighTrajectory
from pdr_sim.trajectory import Trajectory, TrajectoryModel

START_TIME_NS = 1_700_000_000 * 1_000_000_000   # stamps start here (2023-11-14T22:13:20Z)
STANCE = "pdr_msgs/msg/Stance"
STATIONARY_SPEED_MPS = 1e-9      # ground_truth/stance: the sensor's true speed below this
STATIONARY_RATE_RADPS = 1e-9     # ... and its true turn rate below this
TRUTH_DETECTOR = 255             # pdr_msgs/Stance.DETECTOR_TRUTH
MIN_RATE_HZ, MAX_RATE_HZ = 50.0, 1000.0
PLACEMENTS = ("foot", "pocket")
WORKERS = max(1, min(4, os.cpu_count() or 1))
BAROMETER_STREAM = 3        # the seed's child stream after the gyro's, accel's and mag's


@dataclass(frozen=True)
class SimulationConfig:
    """Everything that determines a run."""

    scenario: Scenario | PocketScenario
    scenario_data: dict
    imu: str = "xsens_mtw"
    imu_overrides: dict = field(default_factory=dict)
    rate_hz: float = 100.0
    seed: int = 0
    gravity_mps2: float = STANDARD_GRAVITY_MPS2
    placement: str = "foot"
    pressure: bool = False          # also the barometer: imu/pressure

    def __post_init__(self) -> None:
        if not MIN_RATE_HZ <= self.rate_hz <= MAX_RATE_HZ:
            raise InputError("--rate", f"must be within {MIN_RATE_HZ:g}-{MAX_RATE_HZ:g} Hz, "
                                       f"got {self.rate_hz:g}")
        if self.imu not in PROFILES:
            raise InputError("--imu", f"unknown profile '{self.imu}' "
                                      f"(known: {', '.join(PROFILES)})")
        if self.placement not in PLACEMENTS:
            raise InputError("--placement", f"must be one of {', '.join(PLACEMENTS)}, "
                                            f"got '{self.placement}'")
        if isinstance(self.scenario, PocketScenario) != (self.placement == "pocket"):
            raise InputError("--placement", f"scenario '{self.scenario.name}' is not a "
                                            f"{self.placement} scenario")


@dataclass(frozen=True)
class Simulation:
    """A simulated run: ground truth, true and measured signals, and message batches."""

    config: SimulationConfig
    trajectory: Trajectory
    true_gyro: np.ndarray
    true_accel: np.ndarray
    true_mag: np.ndarray
    imu: MessageBatch
    mag: MessageBatch
    pose: MessageBatch
    truth: dict[str, MessageBatch]        # placement-specific truth topics (bag names)
    gyro_bias: np.ndarray                 # (3,) constant + turn-on gyro bias [rad/s]
    model: TrajectoryModel
    pressure: MessageBatch | None = None  # imu/pressure, with config.pressure
    barometer: BarometerRun | None = None     # what the barometer drew, with it

    @property
    def batches(self) -> dict[str, MessageBatch]:
        """Every topic of the run, by bag name."""
        barometer = {} if self.pressure is None else {topics.IMU_PRESSURE: self.pressure}
        return {topics.IMU_DATA: self.imu, topics.IMU_MAG: self.mag, **barometer,
                topics.GROUND_TRUTH_POSE: self.pose, **self.truth}


def load_placement_scenario(name_or_path: str,
                            placement: str) -> tuple[Scenario | PocketScenario, dict]:
    """A built-in scenario or YAML file of the placement, and its raw mapping."""
    return load_pocket_scenario(name_or_path) if placement == "pocket" else \
        load_scenario(name_or_path)


def scenario_of(data: dict, where: str, placement: str) -> Scenario | PocketScenario:
    """Validate a scenario mapping of the placement (after overrides)."""
    return pocket_scenario_from_dict(data, where) if placement == "pocket" else \
        scenario_from_dict(data, where)


def magnetic_environment(spec: MagneticFieldSpec) -> tuple[MagneticField, IronDistortion | None]:
    """The field model and optional sensor distortion of a scenario's environment."""
    where = "environment.magnetic_field"
    try:
        h_inf = homogeneous(spec.preset) if spec.vector_ut is None else \
            np.asarray(spec.vector_ut) * 1e-6
    except ValueError as exc:
        raise InputError(f"{where}.preset", str(exc)) from exc
    distortion = None
    if spec.distortion == "table_3_3":
        distortion = IronDistortion(**TABLE_3_3)
    elif isinstance(spec.distortion, dict):
        try:
            distortion = IronDistortion(xi=float(spec.distortion["xi"]),
                                        offset=tuple(spec.distortion["offset"]),
                                        M=tuple(map(tuple, spec.distortion["M"])))
        except (KeyError, TypeError, ValueError) as exc:
            raise InputError(f"{where}.distortion",
                             f"needs xi, offset [3], M [3x3] ({exc})") from exc
    elif spec.distortion is not None:
        raise InputError(f"{where}.distortion", f"table_3_3 or a mapping, got {spec.distortion!r}")
    if spec.indoor is not None:
        try:
            spec.indoor.frame(h_inf)
        except ValueError as exc:
            raise InputError(f"{where}.indoor.azimuth_sigma_deg", str(exc)) from exc
    return MagneticField(tuple(h_inf), spec.cylinders, spec.indoor), distortion


def trajectory_model(scenario: Scenario | PocketScenario) -> TrajectoryModel:
    """The trajectory model of a scenario's placement."""
    if isinstance(scenario, PocketScenario):
        return ThighTrajectory(scenario)
    return foot_model(scenario)


def foot_model(scenario: Scenario) -> FootTrajectory:
    """The foot trajectory of a scenario, with its fitted step pattern if it has one."""
    if scenario.pattern != "fitted":
        return FootTrajectory(scenario)
    try:
        return FootTrajectory(scenario, fitted=pattern_from_file(scenario.fitted_pattern))
    except (OSError, KeyError, TypeError, ValueError) as exc:
        raise InputError(scenario.fitted_pattern, f"cannot read the fitted pattern ({exc})") \
            from exc


def _covariance(density: tuple[float, float, float], rate_hz: float, n: int) -> np.ndarray:
    """(n, 9) read-only rows of the white-noise covariance per sample [unit²]."""
    return np.broadcast_to(np.diag(np.square(density) * rate_hz).ravel(), (n, 9))


def _true_signals(model: TrajectoryModel, t: np.ndarray, config: SimulationConfig,
                  field_model: MagneticField) -> tuple[Trajectory, np.ndarray, np.ndarray,
                                                       np.ndarray]:
    traj = model.at(t)
    return (traj, signals.angular_rate(traj, config.scenario.environment.latitude_deg),
            signals.specific_force(traj, config.gravity_mps2),
            signals.magnetic_field(traj, field_model))


def simulate(config: SimulationConfig, errors: ImuErrors | None = None,
             workers: int = WORKERS, model: TrajectoryModel | None = None) -> Simulation:
    """Run the simulation (errors default to the configured profile, the trajectory to the
    scenario's: ``model`` gives another, e.g. :mod:`pdr_sim.paired_foot`'s).

    The trajectory and true signals are computed on ``workers`` threads over consecutive
    blocks of samples, and the three sensors' errors on one thread each (NumPy releases
    the GIL in its array loops). Each sensor draws from its own generator spawned from
    the seed, so the result depends only on the configuration, not on ``workers``.
    """
    errors = errors or profile(config.imu, config.imu_overrides)
    model = model or trajectory_model(config.scenario)
    field_model, distortion = magnetic_environment(config.scenario.environment.magnetic_field)
    blocks = np.array_split(sample_times(model.duration_s, config.rate_hz), workers)
    with ThreadPoolExecutor(workers) as pool:
        parts = list(pool.map(lambda t: _true_signals(model, t, config, field_model), blocks))
        traj = Trajectory.concatenate([p[0] for p in parts])
        true_gyro, true_accel, true_mag = (np.concatenate([p[i] for p in parts])
                                           for i in (1, 2, 3))
        rngs = np.random.default_rng(config.seed).spawn(3)
        triads = (errors.gyro, errors.accel, errors.mag)
        biases = [turn_on_bias(triad, rng) for triad, rng in zip(triads, rngs, strict=True)]
        gyro, accel, mag = pool.map(
            lambda args: corrupt(args[0], args[1], config.rate_hz, args[2], bias=args[3]),
            zip((true_gyro, true_accel, true_mag), triads, rngs, biases, strict=True))
    if distortion is not None:
        mag = distortion.distort(mag, float(np.linalg.norm(field_model.h_inf_t)))
    n = len(traj.t)
    stamps = _stamps(traj.t)
    no_orientation = np.zeros(9)
    no_orientation[0] = -1.0
    imu = MessageBatch(IMU, stamps, SENSOR_FRAME, {
        "orientation": np.broadcast_to([0.0, 0.0, 0.0, 1.0], (n, 4)),
        "orientation_covariance": np.broadcast_to(no_orientation, (n, 9)),
        "angular_velocity": gyro,
        "angular_velocity_covariance": _covariance(errors.gyro.white_density, config.rate_hz, n),
        "linear_acceleration": accel,
        "linear_acceleration_covariance": _covariance(errors.accel.white_density,
                                                      config.rate_hz, n)})
    mag_batch = MessageBatch(MAGNETIC_FIELD, stamps, SENSOR_FRAME, {
        "magnetic_field": mag,
        "magnetic_field_covariance": _covariance(errors.mag.white_density, config.rate_hz, n)})
    pose = MessageBatch(POSE_STAMPED, stamps, MAP_FRAME, {
        "pose.position": traj.position, "pose.orientation": quaternion_xyzw(traj.attitude)})
    truth = pocket_truth(model) if isinstance(model, ThighTrajectory) else \
        foot_truth(traj, stamps)
    pressure, barometer = barometer_batch(model, errors.baro, config.seed) if config.pressure \
        else (None, None)
    return Simulation(config, traj, true_gyro, true_accel, true_mag, imu, mag_batch, pose,
                      truth, biases[0][0, 0], model, pressure, barometer)


def _stamps(t_s: np.ndarray) -> np.ndarray:
    return START_TIME_NS + np.round(np.asarray(t_s) * 1e9).astype(np.int64)


def barometer_rng(seed: int) -> np.random.Generator:
    """The barometer's random stream: the seed's child :data:`BAROMETER_STREAM`, beside
    (and independent of) the three sensors' streams, which stay as they were without it."""
    return np.random.default_rng(seed).spawn(BAROMETER_STREAM + 1)[BAROMETER_STREAM]


def barometer_batch(model: TrajectoryModel, errors: BarometerErrors,
                    seed: int) -> tuple[MessageBatch, BarometerRun]:
    """``imu/pressure`` of a run and what its barometer drew: at the barometer's rate
    (``errors.rate_hz``) from the start, the standard atmosphere's pressure
    (pdr_core.sensors.atmosphere) at the sensor's true height z [m] above the map's z = 0, where it
    is ``errors.reference_pa``, with the barometer's errors (pdr_core.sensors.imu_errors); stamps
    from the simulated time, frame the IMU's, ``variance`` the white noise's [Pa²]."""
    t = sample_times(model.duration_s, errors.rate_hz)
    true = pressure_pa(model.at(t).position[:, 2], errors.reference_pa)
    readings, run = barometer_readings(true, t, errors, barometer_rng(seed))
    return MessageBatch(FLUID_PRESSURE, _stamps(t), SENSOR_FRAME, {
        "fluid_pressure": readings,
        "variance": np.full(len(t), errors.noise_pa**2)}), run


def foot_truth(traj: Trajectory, stamps: np.ndarray) -> dict[str, MessageBatch]:
    """``ground_truth/stance`` of a foot walk, one per IMU sample: ``stationary`` where
    the foot is at rest, its sensor's true speed below :data:`STATIONARY_SPEED_MPS`
    (1e-9 m/s) and its true turn rate below :data:`STATIONARY_RATE_RADPS` (1e-9 rad/s),
    i.e. zero but for rounding, where both a ZUPT and a ZARU hold: standing and a still
    foot flat. A turn in place (v = 0, ω ≠ 0) is not stationary, nor is a foot rolling
    about its heel, ball or toes (the sensor on the instep moves with ω × r, however
    slowly), nor a landing impact. ``statistic`` is the true speed [m/s] (the truth's own
    test quantity), ``detector`` :data:`TRUTH_DETECTOR`."""
    speed = np.linalg.norm(traj.velocity, axis=1)
    rate = np.linalg.norm(traj.body_rate, axis=1)
    n = len(speed)
    return {topics.GROUND_TRUTH_STANCE: MessageBatch(STANCE, stamps, SENSOR_FRAME, {
        "stationary": (speed < STATIONARY_SPEED_MPS) & (rate < STATIONARY_RATE_RADPS),
        "statistic": speed, "detector": np.full(n, TRUTH_DETECTOR, np.uint8)})}


def pocket_truth(model: ThighTrajectory) -> dict[str, MessageBatch]:
    """``ground_truth/step`` and ``ground_truth/landmarks`` of a pocket walk."""
    steps = model.true_steps
    step = MessageBatch(STEP, _stamps(steps.end_s), MAP_FRAME, {
        "index": np.arange(len(steps.end_s), dtype=np.uint32), "length": steps.length,
        "vertical_displacement": steps.vertical_displacement, "heading": steps.heading,
        "pitch_max": steps.pitch_max, "pitch_min": steps.pitch_min,
        "pitch_amplitude": steps.pitch_amplitude, "duration": steps.duration,
        "activity": steps.activity, "ride": np.zeros(len(steps.end_s), np.uint8),
        "ride_height": np.zeros(len(steps.end_s))})     # the rides are in the record
    marks = model.landmarks
    landmark = MessageBatch(LANDMARK, _stamps([m.time_s for m in marks]), MAP_FRAME, {
        "id": np.array([m.id for m in marks], dtype=np.uint32),
        "type": np.array([m.type for m in marks], dtype=np.uint8),
        "position": np.array([m.position for m in marks]).reshape(-1, 3),
        "position_covariance": np.zeros((len(marks), 9)),
        "yaw_before": np.array([m.yaw_before for m in marks]),
        "yaw_after": np.array([m.yaw_after for m in marks]),
        "floor": np.array([m.floor for m in marks], dtype=np.int32)})
    return {topics.GROUND_TRUTH_STEP: step, topics.GROUND_TRUTH_LANDMARKS: landmark}


def simulation_record(sim: Simulation) -> dict[str, Any]:
    """The complete configuration of a run and the truth no topic carries, as stored with
    its bag: the gyroscope's constant (fixed + turn-on) bias per axis [rad/s and °/s] and,
    for the pocket, the landmarks with the earlier visit each revisits, the activity
    periods [s from the start] and any lift rides; with the barometer, the weather drift
    and the sudden offsets it drew or was given (``pressure``)."""
    config = sim.config
    record = {"placement": config.placement, "scenario": config.scenario_data,
              "imu_profile": config.imu, "imu_overrides": config.imu_overrides,
              "rate_hz": config.rate_hz, "seed": config.seed,
              "gravity_mps2": config.gravity_mps2, "start_time_ns": START_TIME_NS,
              "true_gyro_bias_radps": [float(b) for b in sim.gyro_bias],
              "true_gyro_bias_deg_per_s": [float(np.degrees(b)) for b in sim.gyro_bias]}
    if isinstance(sim.model, ThighTrajectory):
        record["landmarks"] = [
            {"id": m.id, "type": LandmarkType(m.type).label,
             "time_s": round(m.time_s, 3), "floor": m.floor, "revisit_of": m.revisit_of,
             "position_m": [round(v, 3) for v in m.position]} for m in sim.model.landmarks]
        record["periods"] = [{"activity": ACTIVITY_NAMES[p.activity],
                              "start_s": round(p.start_s, 3), "end_s": round(p.end_s, 3)}
                             for p in sim.model.periods]
        if sim.model.plan.rides:
            record["lift_rides"] = [
                {"start_s": round(r.start_s, 3), "end_s": round(r.end_s, 3),
                 "rise_m": round(r.rise_m, 3), "floors": r.floors}
                for r in sim.model.plan.rides]
    if sim.barometer is not None:
        record["pressure"] = {
            "topic": topics.IMU_PRESSURE,
            "drift_hpa_per_h": round(sim.barometer.drift_pa_per_s * 3600.0 / PA_PER_HPA, 4),
            "offsets": [{"at_s": round(o.start_s, 3),
                         "size_hpa": round(o.size_pa / PA_PER_HPA, 4),
                         "duration_s": round(o.duration_s, 3)} for o in sim.barometer.offsets]}
    return record

