"""The foot INS's heading drift and what the landmark corrections take off it (issue 44's
study; Zampella et al. 2011 and Wang et al. 2020 show the heading growing with the z gyro
bias, which ZUPTs do not observe).

The walk: twenty minutes around a block (pdr_sim scenario ``block_laps``, thirteen laps of
90 s, every corner revisited), an Xsens MTw (``xsens_mtw``) whose z gyro warms by
:data:`WARMUP_BIAS_DEG_PER_S` with the time constant :data:`WARMUP_TIME_CONSTANT_S` after
the start (pdr_core.sensors.imu_errors' warm-up): the rest alignment at the start calibrates the
bias the gyro has then, and the 0.05 °/s it takes on afterwards is what the navigator
cannot see. The navigator is config/foot_drift.yaml (15 states), run without corrections
and with ``--drift online`` (pdr_ins_ekf.drift_loop) and the drift estimator's
config/landmark_drift_foot.yaml, per seed of the sensor errors.
"""
from __future__ import annotations

from dataclasses import dataclass

from pdr_core.config_files import shipped_config_dir
from pdr_core.io.batch import MessageBatch
from pdr_drift.config import load_drift_config
from pdr_ins_ekf.config import load_run_config
from pdr_ins_ekf.drift_loop import navigate_online
from pdr_ins_ekf.foot_offline import final_errors_against
from pdr_ins_ekf.offline import navigate

WALK = "block_laps"
IMU = "xsens_mtw"
WARMUP_BIAS_DEG_PER_S = 0.05
WARMUP_TIME_CONSTANT_S = 60.0
RATE_HZ = 100.0
NAVIGATOR_CONFIG = "foot_drift.yaml"
DRIFT_CONFIG = "landmark_drift_foot.yaml"


def drift_walk(seed: int) -> dict[str, MessageBatch]:
    """The simulated walk of a seed (module docstring): its batches by bag topic."""
    from pdr_sim.scenario import load_scenario
    from pdr_sim.simulation import SimulationConfig, simulate

    scenario, data = load_scenario(WALK)
    warmup = {"gyro": {"warmup_bias_deg_per_s": [0.0, 0.0, WARMUP_BIAS_DEG_PER_S],
                       "warmup_time_constant_s": WARMUP_TIME_CONSTANT_S}}
    return simulate(SimulationConfig(scenario, data, IMU, warmup, RATE_HZ, seed)).batches


@dataclass(frozen=True)
class DriftOutcome:
    """Final yaw error [deg] and final position error [m] without and with the
    corrections, and the corrections accepted."""

    seed: int
    uncorrected_yaw_deg: float
    corrected_yaw_deg: float
    uncorrected_position_m: float
    corrected_position_m: float
    corrections: int


def drift_outcome(seed: int) -> DriftOutcome:
    """The study of one seed (module docstring)."""
    from pdr_core import topics

    batches = drift_walk(seed)
    imu, truth = batches[topics.IMU_DATA], batches[topics.GROUND_TRUTH_POSE]
    config = load_run_config(shipped_config_dir("pdr_ins_ekf") / NAVIGATOR_CONFIG)
    plain = final_errors_against(navigate(imu, config), truth)
    corrected_run, log = navigate_online(
        imu, config, load_drift_config(shipped_config_dir("pdr_drift") / DRIFT_CONFIG))
    corrected = final_errors_against(corrected_run, truth)
    return DriftOutcome(seed, abs(plain["final_yaw_error_deg"]),
                        abs(corrected["final_yaw_error_deg"]),
                        plain["final_position_error_m"], corrected["final_position_error_m"],
                        sum(1 for _, ok, _ in log.corrections if ok))
