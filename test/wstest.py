"""Helpers for the cross-package tests: paths, and ``./ws`` processes in one ROS domain."""
from __future__ import annotations

import os
import signal
import subprocess
import time
from pathlib import Path

import numpy as np

from pdr_core.bag import write_batches
from pdr_core.batch import MessageBatch
from pdr_core.msgtypes import IMU

ROOT = Path(__file__).resolve().parents[1]
WS = ROOT / "ws"
# The real recordings (../shared/data beside the repository; PDR_SHARED_DATA overrides).
SHARED_DATA = Path(os.environ.get("PDR_SHARED_DATA", ROOT.parent / "shared" / "data"))
if not SHARED_DATA.is_dir():
    raise FileNotFoundError(f"{SHARED_DATA}: the shared recordings are missing; clone the "
                            "repository beside shared/ or set PDR_SHARED_DATA")

# Import arguments of the recordings (README, "Recording, replay and import")
PYSHOE = sorted((SHARED_DATA / "foot" / "pyshoe_vicon").glob("*.csv"))
PYSHOE_ARGS = ["--time-col", "t_s", "--acc-cols", "acc_x_mps2,acc_y_mps2,acc_z_mps2",
               "--gyro-cols", "gyr_x_radps,gyr_y_radps,gyr_z_radps",
               "--pos-cols", "gt_x_m,gt_y_m,gt_z_m"]
PYSHOE_NAV_ARGS = [*PYSHOE_ARGS, "--pos-axes=-x,y,z"]  # the VICON frame is mirrored
XIO = SHARED_DATA / "foot" / "xio_gait_tracking" / "short_walk.csv"
XIO_COLUMNS = ["--time-col", "Time (s)", "--drop-duplicates",
               "--acc-cols", "Accelerometer X (g),Accelerometer Y (g),Accelerometer Z (g)",
               "--gyro-cols", "Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s)"]
XIO_ARGS = [*XIO_COLUMNS, "--acc-unit", "g", "--gyro-unit", "deg/s"]


class Processes:
    """Starts ``./ws`` executables in one ROS domain; stops what is left at teardown."""

    def __init__(self, domain_id: int, log_dir: Path) -> None:
        self.env = {**os.environ, "ROS_DOMAIN_ID": str(domain_id)}
        self.log_dir = log_dir
        self.started: list[subprocess.Popen] = []

    def start(self, *args: str, name: str) -> subprocess.Popen:
        """Start ``./ws ARGS``; its stdout and stderr go to LOG_DIR/NAME.log."""
        log = (self.log_dir / f"{name}.log").open("w")
        proc = subprocess.Popen([str(WS), *args], env=self.env, stdout=log,
                                stderr=subprocess.STDOUT, cwd=ROOT)
        proc.log_path = self.log_dir / f"{name}.log"
        self.started.append(proc)
        return proc

    def run(self, *args: str, timeout: float = 120) -> subprocess.CompletedProcess:
        """Run ``./ws ARGS`` to completion, capturing its output."""
        return subprocess.run([str(WS), *args], env=self.env, capture_output=True, text=True,
                              timeout=timeout, cwd=ROOT)

    @staticmethod
    def stop(proc: subprocess.Popen, sig: int = signal.SIGINT, timeout: float = 30) -> int:
        proc.send_signal(sig)
        return proc.wait(timeout=timeout)

    def cleanup(self) -> None:
        for proc in self.started:
            if proc.poll() is None:
                proc.kill()
                proc.wait()


def wait_for_log(proc: subprocess.Popen, *texts: str, timeout: float = 60.0) -> None:
    """Wait until the process's log holds every one of ``texts`` (a start handshake)."""
    deadline = time.monotonic() + timeout
    while not all(t in log_text(proc) for t in texts):
        if proc.poll() is not None or time.monotonic() > deadline:
            raise AssertionError(f"{proc.args[1]} never logged {texts}:\n{log_text(proc)}")
        time.sleep(0.05)


def log_text(proc: subprocess.Popen) -> str:
    return Path(proc.log_path).read_text()


def imu_bag(path, n, rate_hz=200.0, seed=0):
    """A bag of ``n`` random Imu messages at ``rate_hz`` (bag_play and bag_record tests);
    returns the batch."""
    rng = np.random.default_rng(seed)
    stamps = 1_700_000_000_000_000_000 + np.round(np.arange(n) * 1e9 / rate_hz).astype(np.int64)
    cov = np.zeros((n, 9))
    cov[:, 0] = -1.0
    batch = MessageBatch(IMU, stamps, "imu_link", {
        "orientation": np.tile([0.0, 0.0, 0.0, 1.0], (n, 1)),
        "orientation_covariance": cov,
        "angular_velocity": rng.normal(size=(n, 3)),
        "angular_velocity_covariance": rng.normal(size=(n, 9)),
        "linear_acceleration": rng.normal(size=(n, 3)) * 20,
        "linear_acceleration_covariance": rng.normal(size=(n, 9)),
    })
    write_batches(path, {"/imu/data": batch})
    return batch


def play(procs, bag, *params):
    """Run bag_play on ``bag`` with ``name:=value`` parameters, waiting for a subscriber."""
    args = ["bag_play", "--ros-args", "-p", f"bag:={bag}", "-p", "wait_for_subscribers:=1"]
    for p in params:
        args += ["-p", p]
    return procs.run(*args)
