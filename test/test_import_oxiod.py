"""``pdr-sim import-oxiod`` on the three OxIOD sequences of ../shared/data/attitude/oxiod (issue
53): the truth attitude it writes agrees with the phone's own gyroscope and accelerometer.

What holds, measured on the imported bags (docs/bags.md, "OxIOD"):

- over 0.1 s windows (10 rows) without a truth glitch, the truth's rotation and the
  integrated gyroscope differ by a median 0.37°, 1.92° and 1.80° (handheld_data1_seq2,
  multi_devices_iPhone_6_seq1, multi_users_user2_seq4), and by less than 5° in 99.96 %,
  99.44 % and 98.43 % of the windows. The last two are worse because their rows are not
  quite the same instant: the gyroscope matches the truth best 20 and 3 rows later (1 in
  the first);
- the specific force's median norm is 9.689, 9.645 and 9.881 m/s²;
- the direction of gravity in the phone's frame from the truth and from the accelerometer,
  each averaged over 1 s, differ by a median 2.1°, 2.6° and 6.0° (95th percentile 5.1°,
  5.7°, 10.7°): the phone sat a few degrees off the Vicon object's axes, most in the
  third (Core Motion's own gravity estimate shows the same 5.7° there).

Without the 180° turn about z between the Vicon object and the phone, gravity from the
truth is 40-173° off (median): the turn is checked too.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
from scipy.ndimage import uniform_filter1d
from scipy.spatial.transform import Rotation

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.io.bag import BagReader
from pdr_core.io.batch import MessageBatch
from pdr_core.io.oxiod import attitude_jumps
from wstest import SHARED_DATA, cli, needs_shared

OXIOD = SHARED_DATA / "attitude" / "oxiod"
# The sequences, their rows and the truth's glitches (attitude jumps > 0.5 rad between
# rows), counted once by hand from the files
SEQUENCES = {"handheld_data1_seq2": (23446, 7), "multi_devices_iPhone_6_seq1": (18049, 6),
             "multi_users_user2_seq4": (21781, 8)}
WINDOW_ROWS = 10                  # 0.1 s
WINDOW_ERROR_DEG = 5.0            # the gyroscope and the truth agree within this ...
WINDOW_SHARE = 0.97               # ... in at least this share of the windows
WINDOW_MEDIAN_DEG = 2.5
FORCE_MEDIAN_TOLERANCE_MPS2 = 0.25
LOW_PASS_ROWS = 100               # 1 s
GRAVITY_MEDIAN_DEG = 7.0
GRAVITY_P95_DEG = 12.0


@dataclass
class Imported:
    name: str
    stdout: str
    imu: MessageBatch
    pose: MessageBatch

    @property
    def attitude(self) -> Rotation:
        """C_world_phone of each row."""
        return Rotation.from_quat(self.pose["pose.orientation"])

    @property
    def jumps(self) -> np.ndarray:
        return attitude_jumps(self.pose["pose.orientation"])


@pytest.fixture(scope="module", params=[pytest.param(name, marks=needs_shared(OXIOD / name))
                                        for name in SEQUENCES])
def sequence(request, tmp_path_factory) -> Imported:
    out = tmp_path_factory.mktemp(request.param) / "bag"
    result = cli("pdr-sim", "import-oxiod", OXIOD / request.param, "--out", out)
    assert result.returncode == 0, result.stderr
    reader = BagReader(out)
    return Imported(request.param, result.stdout, reader.read("/imu/data"),
                    reader.read("/ground_truth/pose"))


def window_errors_deg(imu: MessageBatch, attitude: Rotation, jumps: np.ndarray) -> np.ndarray:
    """Per 0.1 s window without a truth glitch: the angle [deg] between the truth's rotation
    over it and the gyroscope's, integrated sample by sample."""
    dt = float(np.median(np.diff(imu.t_s)))
    starts = np.arange(0, len(imu) - WINDOW_ROWS, WINDOW_ROWS)
    gyro = Rotation.identity(len(starts))
    for row in range(WINDOW_ROWS):
        gyro = gyro * Rotation.from_rotvec(imu["angular_velocity"][starts + row] * dt)
    truth = attitude[starts].inv() * attitude[starts + WINDOW_ROWS]
    glitches = np.concatenate(([0], np.cumsum(jumps)))
    clean = glitches[starts + WINDOW_ROWS + 1] == glitches[starts + 1]
    return np.degrees((gyro.inv() * truth).magnitude())[clean]


def gravity_angles_deg(imu: MessageBatch, attitude: Rotation, jumps: np.ndarray) -> np.ndarray:
    """Per row away from a glitch: the angle [deg] between the up direction in the phone's
    frame from the truth and the specific force, each averaged over 1 s."""
    force = uniform_filter1d(imu["linear_acceleration"], LOW_PASS_ROWS, axis=0)
    up = uniform_filter1d(attitude.inv().apply([0.0, 0.0, 1.0]), LOW_PASS_ROWS, axis=0)
    near_glitch = uniform_filter1d(jumps.astype(float), LOW_PASS_ROWS + 20) > 0
    cosine = np.sum(force * up, axis=1) / np.linalg.norm(force, axis=1) / np.linalg.norm(up, axis=1)
    return np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0)))[~near_glitch]


def test_the_summary_says_what_went_in(sequence):
    rows, glitches = SEQUENCES[sequence.name]
    assert len(sequence.imu) == len(sequence.pose) == rows
    assert f"{rows} samples from 0.000 s, {(rows - 1) / 100:.3f} s at 100.0 Hz mean" \
        in sequence.stdout
    assert "magnetometer: yes; truth: attitude and position" in sequence.stdout
    assert f"; {glitches} truth glitches (attitude jumps > 0.5 rad" in sequence.stdout
    assert int(sequence.jumps.sum()) == glitches


def test_the_truth_attitude_turns_as_the_gyroscope_does(sequence):
    errors = window_errors_deg(sequence.imu, sequence.attitude, sequence.jumps)
    assert len(errors) > 1500
    assert np.mean(errors < WINDOW_ERROR_DEG) >= WINDOW_SHARE
    assert np.median(errors) <= WINDOW_MEDIAN_DEG


def test_the_specific_force_is_about_g(sequence):
    norm = np.linalg.norm(sequence.imu["linear_acceleration"], axis=1)
    assert abs(np.median(norm) - STANDARD_GRAVITY_MPS2) <= FORCE_MEDIAN_TOLERANCE_MPS2


def test_gravity_from_the_truth_points_where_the_accelerometer_says(sequence):
    angles = gravity_angles_deg(sequence.imu, sequence.attitude, sequence.jumps)
    assert np.median(angles) <= GRAVITY_MEDIAN_DEG
    assert np.percentile(angles, 95) <= GRAVITY_P95_DEG
    unturned = sequence.attitude * Rotation.from_euler("z", np.pi)   # the Vicon object's frame
    assert np.median(gravity_angles_deg(sequence.imu, unturned, sequence.jumps)) > 30.0
