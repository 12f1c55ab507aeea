"""The ZUPT EKF on the simulator's noiseless walk (Zampella et al. 2011, section IV-A)."""
import numpy as np
import pytest

from pdr_ins_ekf.kernel_data import GYRO
from pdr_ins_ekf.zero_velocity import ConditionVoteDetector
from pdr_ins_ekf.zupt_ekf import FilterConfig, ZuptEkf, run
from pdr_sim.scenario import scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate

WALK = {"segments": [{"type": "standing", "duration_s": 2.0}, {"type": "straight", "steps": 100},
                     {"type": "standing", "duration_s": 1.0}]}


@pytest.fixture(scope="module")
def noiseless_walk():
    sim = simulate(SimulationConfig(scenario_from_dict(WALK, "walk"), WALK, "ideal", {}, 100.0))
    return sim.imu.t_s - sim.imu.t_s[0], sim.imu["linear_acceleration"], \
        sim.imu["angular_velocity"], sim.trajectory.position


def position_error(walk, variant):
    t, accel, gyro, truth = walk
    stance = ConditionVoteDetector(variant=variant).detect(accel, gyro, 100.0).mask
    out = run(t, accel, gyro, stance, FilterConfig(), slice(0, 100))
    return out.position - truth


def final_error(walk, variant):
    return position_error(walk, variant)[-1]


def test_retarded_window_ends_100_steps_within_a_centimetre(noiseless_walk):
    assert np.linalg.norm(final_error(noiseless_walk, "retarded")) < 0.01


@pytest.mark.parametrize("variant", ["limited", "retarded"])
def test_limited_and_retarded_windows_end_within_a_centimetre_along_track(noiseless_walk,
                                                                          variant):
    assert abs(final_error(noiseless_walk, variant)[0]) < 0.01


def test_original_detector_leaves_a_growing_along_track_error(noiseless_walk):
    original = position_error(noiseless_walk, "original")[:, 0]
    half = len(original) // 2
    assert original[-1] < -0.2, "the stance stretched into the swing shortens every step"
    assert original[-1] < 1.8 * original[half] < 0, "and the error grows with the steps"
    assert abs(original[-1]) > 30 * abs(final_error(noiseless_walk, "limited")[0])


def test_configuration_is_checked():
    with pytest.raises(ValueError, match="ZARU needs the gyro bias states"):
        FilterConfig(zaru=True)
    with pytest.raises(ValueError, match="bias_model must be one of"):
        FilterConfig(bias_model="flicker")


def test_fifteen_states_estimate_a_gyro_bias_with_zaru():
    config = FilterConfig(bias_model="random_walk", zaru=True)
    ekf = ZuptEkf(config, np.eye(3))
    bias = np.array([0.01, -0.02, 0.005])
    for _ in range(2000):
        ekf.predict(np.array([0.0, 0.0, 9.80665]), bias, 0.01)
        ekf.zupt()
        ekf.zaru(bias)
    np.testing.assert_allclose(ekf.b[GYRO], bias, atol=1e-4)
    assert np.allclose(ekf.P, ekf.P.T) and np.linalg.eigvalsh(ekf.P).min() >= 0


def _turning_in_place(config, seconds=5.0, rate_hz=100.0, turn_radps=0.2):
    """A foot at rest but for a constant yaw rate, every sample taken for stance: the
    gyro bias estimate after ``seconds``."""
    n = int(seconds * rate_hz)
    ekf = ZuptEkf(config, np.eye(3))
    f = np.tile([0.0, 0.0, 9.80665], (n, 1))
    w = np.tile([0.0, 0.0, turn_radps], (n, 1))
    dt = np.full(n, 1.0 / rate_hz)
    dt[0] = 0.0
    ekf.run_block(f, w, dt, np.ones(n, bool))
    return ekf.b[GYRO]


def test_zaru_gate_keeps_a_turn_in_place_out_of_the_gyro_bias():
    """A turn on the spot has v = 0 but ω ≠ 0: its rate is not a bias. With the gate
    (zaru_gate_nis, χ² at 0.999) the ZARU is refused and the bias stays at its start;
    without it the ZARU takes the turn for a bias."""
    gated = FilterConfig(bias_model="random_walk", zaru=True)
    ungated = FilterConfig(bias_model="random_walk", zaru=True, zaru_gate_nis=1e300)
    assert np.abs(_turning_in_place(gated)).max() < 1e-9
    assert _turning_in_place(ungated)[2] > 0.15


def test_zaru_gate_passes_a_bias_within_its_uncertainty():
    """A still foot with a gyro bias of 2σ of the initial bias uncertainty: the ZARU
    runs, and the bias is found (the gate refuses only what the covariance calls
    implausible)."""
    config = FilterConfig(bias_model="random_walk", zaru=True)
    bias = 2 * config.init_gyro_bias_sigma_radps
    assert _turning_in_place(config, turn_radps=bias)[2] == pytest.approx(bias, rel=0.05)


@pytest.mark.parametrize("gate", [0.0, -1.0])
def test_zaru_gate_must_be_positive(gate):
    with pytest.raises(ValueError, match="zaru_gate_nis"):
        FilterConfig(bias_model="random_walk", zaru=True, zaru_gate_nis=gate)
