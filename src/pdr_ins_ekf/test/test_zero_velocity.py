"""Stance detectors on the simulator's noiseless walk, where true stance is known.

Zampella et al. 2011, section IV-A: the original detector's median filter keeps
'stance' for the first samples of every swing; the limited and the retarded windows
remove that (the effect on the EKF's along-track error is tested with the filter).
"""
import numpy as np
import pytest

from pdr_ins_ekf.zero_velocity import (
    AngularRateEnergyDetector,
    ConditionVoteDetector,
    MagnitudeDetector,
    MovingVarianceDetector,
    ShoeDetector,
)
from pdr_sim import signals
from pdr_sim.foot_trajectory import FootTrajectory
from pdr_sim.scenario import scenario_from_dict

RATE = 100.0


@pytest.fixture(scope="module")
def walk():
    data = {"timing": "linear", "segments": [{"type": "standing", "duration_s": 2.0},
                                             {"type": "straight", "steps": 20},
                                             {"type": "standing", "duration_s": 1.0}]}
    traj = FootTrajectory(scenario_from_dict(data, "walk")).sample(RATE)
    still = np.linalg.norm(traj.velocity, axis=1) == 0
    onsets = np.flatnonzero(still[:-1] & ~still[1:]) + 1
    return signals.specific_force(traj), signals.angular_rate(traj), still, onsets


def late_stance(mask, onsets):
    """Samples wrongly called stance right after each swing onset (mean per step)."""
    counts = []
    for k in onsets:
        n = 0
        while mask[k + n]:
            n += 1
        counts.append(n)
    return float(np.mean(counts))


def test_original_detector_extends_stance_into_the_swing(walk):
    accel, gyro, _, onsets = walk
    original = ConditionVoteDetector(variant="original").detect(accel, gyro, RATE).mask
    assert late_stance(original, onsets) >= 3.0


@pytest.mark.parametrize("variant", ["limited", "retarded"])
def test_limited_and_retarded_windows_end_stance_at_the_onset(walk, variant):
    accel, gyro, still, onsets = walk
    mask = ConditionVoteDetector(variant=variant).detect(accel, gyro, RATE).mask
    assert late_stance(mask, onsets) <= 1.0
    assert (mask & still).sum() >= 0.6 * still.sum(), "most of the true stance is found"


@pytest.mark.parametrize("detector, false_in_swing", [
    (ShoeDetector(), 0.0), (AngularRateEnergyDetector(), 0.0),
    # accelerometer-only detectors can be fooled where the foot's acceleration is steady
    (MovingVarianceDetector(), 0.05), (MagnitudeDetector(), 0.05)],
    ids=lambda d: type(d).__name__ if not isinstance(d, float) else "")
def test_skog_detectors_find_stance_and_little_swing(walk, detector, false_in_swing):
    accel, gyro, still, _ = walk
    result = detector.detect(accel, gyro, RATE)
    assert result.mask.shape == still.shape == result.statistic.shape
    swing = np.linalg.norm(gyro, axis=1) > 0.5
    assert (result.mask & swing).sum() <= false_in_swing * swing.sum()
    assert (result.mask & still).sum() >= 0.5 * still.sum()


def test_bad_parameters():
    with pytest.raises(ValueError, match="variant"):
        ConditionVoteDetector(variant="centred")
    with pytest.raises(ValueError, match="w2_samples must be >= 1"):
        ConditionVoteDetector(w2_samples=0)
