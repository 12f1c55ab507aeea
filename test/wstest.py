"""Helpers for the cross-package tests: paths, the offline CLIs run in the test's process,
and the workspace's processes in one ROS domain."""
from __future__ import annotations

import contextlib
import fcntl
import functools
import hashlib
import importlib
import io
import os
import shutil
import signal
import subprocess
import sys
import time
import traceback
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pytest

from pdr_core.io.bag import BagReader, write_batches
from pdr_core.io.batch import MessageBatch
from pdr_core.io.msgtypes import IMU
from pdr_core.sensors.imu_checks import MAX_PLAUSIBLE_ACCEL_MPS2, MAX_PLAUSIBLE_RATE_RADPS

ROOT = Path(__file__).resolve().parents[1]
# The real recordings (../shared/data beside the repository; PDR_SHARED_DATA overrides).
# A clone without them still runs every other test: those that need one skip, naming the
# missing path, unless PDR_REQUIRE_SHARED_DATA=1 (CI: .ci/run) makes that a failure.
SHARED_DATA = Path(os.environ.get("PDR_SHARED_DATA", ROOT.parent / "shared" / "data"))
REQUIRE_SHARED_DATA = os.environ.get("PDR_REQUIRE_SHARED_DATA", "0") not in ("", "0")

# The recordings, by name (a glob of a missing folder would silently test nothing)
PYSHOE_TRIALS = ("2017-11-22-11-22-03", "2017-11-22-11-30-14", "2017-11-22-11-49-03",
                 "2017-11-27-11-13-10", "2017-11-27-11-24-07", "2017-12-15-18-03-05",
                 "2018-02-22-10-10-29")
PYSHOE = [SHARED_DATA / "foot" / "pyshoe_vicon" / f"{trial}.csv" for trial in PYSHOE_TRIALS]
PYSHOE_CLIMB = SHARED_DATA / "foot" / "pyshoe_vicon" / "2018-02-09-11-19-39.csv"  # the foot climbs
XIO = SHARED_DATA / "foot" / "xio_gait_tracking" / "short_walk.csv"
OXFORD = SHARED_DATA / "pocket" / "oxford_step_counter" / "user1_frontpocket_1506422223341.csv"
THIGH = SHARED_DATA / "pocket" / "thigh_revalew"
# Two phones' own Sensor Logger exports, held in the hand (pdr-sim import-phone)
SENSOR_LOGGER = SHARED_DATA / "phone" / "sensor_logger"
SENSOR_LOGGER_EXPORTS = {"android": SENSOR_LOGGER / "inhand-27-steps-Matan",
                         "ios": SENSOR_LOGGER / "inhand-28-steps-Ido"}

# Import arguments of the recordings (README, "Evaluate on your own recording")
PYSHOE_ARGS = ["--time-col", "t_s", "--acc-cols", "acc_x_mps2,acc_y_mps2,acc_z_mps2",
               "--gyro-cols", "gyr_x_radps,gyr_y_radps,gyr_z_radps",
               "--pos-cols", "gt_x_m,gt_y_m,gt_z_m"]
PYSHOE_NAV_ARGS = [*PYSHOE_ARGS, "--pos-axes=-x,y,z"]  # the VICON frame is mirrored
XIO_COLUMNS = ["--time-col", "Time (s)", "--drop-duplicates",
               "--acc-cols", "Accelerometer X (g),Accelerometer Y (g),Accelerometer Z (g)",
               "--gyro-cols", "Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s)"]
XIO_ARGS = [*XIO_COLUMNS, "--acc-unit", "g", "--gyro-unit", "deg/s"]
OXFORD_ARGS = ["--no-header", "--time-col", "0", "--time-unit", "ns", "--acc-cols", "1,2,3"]
THIGH_ARGS = ["--time-col", "time", "--acc-cols", "accel_x,accel_y,accel_z",
              "--gyro-cols", "gyro_x,gyro_y,gyro_z", "--mag-cols", "mag_x,mag_y,mag_z",
              "--mag-unit", "ut"]
BACK_POCKET = OXFORD.parent / "opt_Samsung_Dario_Hard_BackPocket_1" / "accelerometer.csv"
BACK_POCKET_ARGS = ["--no-header", "--time-col", "0", "--time-unit", "ns",
                    "--acc-cols", "2,3,4"]
THIGHS = ("norm_thigh_1", "fast_thigh_1", "jog_thigh_1", "tug_thigh_1", "s_up_thigh_1",
          "s_down_thigh_1", "s_both_thigh_1")
# Every shared recording of a foot or a pocket: name -> (file, import-csv arguments, the
# navigator it is for)
SHARED_RECORDINGS = {
    **{p.stem: (p, PYSHOE_ARGS, "foot") for p in [*PYSHOE, PYSHOE_CLIMB]},
    "xio": (XIO, XIO_ARGS, "foot"),
    **{name: (THIGH / name / "imu.csv", THIGH_ARGS, "pocket") for name in THIGHS},
    "oxford_front": (OXFORD, OXFORD_ARGS, "pocket"),
    "oxford_back": (BACK_POCKET, BACK_POCKET_ARGS, "pocket")}


def needs_shared(*paths: Path) -> pytest.MarkDecorator:
    """Mark a test (or, as ``pytestmark``, a module) that reads these shared recordings:
    test/conftest.py skips it when one is missing, or fails it under
    PDR_REQUIRE_SHARED_DATA=1."""
    return pytest.mark.shared_data(*paths)


def missing_shared(paths) -> str | None:
    """The reason to skip a test that needs ``paths``, or None when all are there."""
    missing = [p for p in paths if not Path(p).exists()]
    if not missing:
        return None
    return (f"{missing[0]}: shared recording missing (clone the repository beside shared/ "
            "or set PDR_SHARED_DATA)")


# The offline CLIs and the module of each one's ``main`` (its console script's entry point)
CLIS = {"pdr-sim": "pdr_sim.cli", "pdr-pocket": "pdr_pocket.cli",
        "pdr-ekf": "pdr_ins_ekf.cli", "pdr-drift": "pdr_drift.cli", "pdr-eval": "pdr_eval.cli"}


def installed(prog: str) -> str:
    """The executable ``prog`` of the built workspace (install/PKG/lib/PKG/PROG, what
    ``./ws PROG`` runs)."""
    [exe] = ROOT.glob(f"install/*/lib/*/{prog}")
    return str(exe)


def command(prog: str) -> str:
    """What ``./ws PROG`` executes: the workspace's executable of that name, else ``prog``
    from the PATH."""
    return next(map(str, ROOT.glob(f"install/*/lib/*/{prog}")), prog)


def cli(prog: str, *args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    """``prog ARGS`` (an offline CLI of :data:`CLIS`) run to completion by its ``main`` in
    this process, from ``cwd``: what its console script runs, without the 1-1.5 s of an
    interpreter start and its imports. Its stdout and stderr are captured, and its exit
    status is the return code: ``sys.exit``'s, or 1 with the traceback on stderr for an
    uncaught exception, as Python gives. The console scripts themselves are started as
    processes by test_cli_help.py."""
    main = importlib.import_module(CLIS[prog]).main
    out, err = io.StringIO(), io.StringIO()
    with contextlib.chdir(cwd), contextlib.redirect_stdout(out), \
            contextlib.redirect_stderr(err):
        code = _exit_status(main, [str(arg) for arg in args])
    return subprocess.CompletedProcess([prog, *args], code, out.getvalue(), err.getvalue())


def _exit_status(main, argv: list[str]) -> int:
    """The exit status of ``main(argv)`` as a process of it would give."""
    try:
        main(argv)
    except SystemExit as exited:
        if exited.code is None or isinstance(exited.code, int):
            return exited.code or 0
        print(exited.code, file=sys.stderr)
        return 1
    except Exception:
        traceback.print_exc()
        return 1
    return 0


class Processes:
    """Starts the workspace's executables in one ROS domain; stops what is left at
    teardown. They start as ``./ws`` would start them, from install/, in the test's
    environment (``make test`` sources tools/env.sh), without ``./ws``'s bootstrap check
    and environment set-up: 0.4 s of a core for each of the suite's node starts. The
    README's blocks and the demo's scripts run ``./ws`` itself."""

    def __init__(self, domain_id: int, log_dir: Path) -> None:
        self.env = {**os.environ, "ROS_DOMAIN_ID": str(domain_id)}
        self.log_dir = log_dir
        self.started: list[subprocess.Popen] = []

    def start(self, *args: str, name: str) -> subprocess.Popen:
        """Start ``ARGS`` as ``./ws ARGS`` would; its stdout and stderr go to
        LOG_DIR/NAME.log."""
        log = (self.log_dir / f"{name}.log").open("w")
        proc = subprocess.Popen([command(args[0]), *args[1:]], env=self.env, stdout=log,
                                stderr=subprocess.STDOUT, cwd=ROOT)
        proc.log_path = self.log_dir / f"{name}.log"
        self.started.append(proc)
        return proc

    def run(self, *args: str, timeout: float = 120) -> subprocess.CompletedProcess:
        """Run ``ARGS`` as ``./ws ARGS`` would, to completion, capturing its output: an
        offline CLI in this process (:func:`cli`), any other executable as a process."""
        if args[0] in CLIS:
            return cli(*args)
        return subprocess.run([command(args[0]), *args[1:]], env=self.env, capture_output=True,
                              text=True, timeout=timeout, cwd=ROOT)

    @staticmethod
    def stop(proc: subprocess.Popen, sig: int = signal.SIGINT, timeout: float = 30) -> int:
        proc.send_signal(sig)
        return proc.wait(timeout=timeout)

    def cleanup(self) -> None:
        for proc in self.started:
            if proc.poll() is None:
                proc.kill()
                proc.wait()


IMPORTS_ENV = "PDR_TEST_IMPORTS"    # the session's folder of imported recordings


def imported(csv: Path, import_args: list[str]) -> Path:
    """The bag ``pdr-sim import-csv CSV --out BAG IMPORT_ARGS`` writes (its ``main``, in
    this process), imported once per test session: kept in the session's folder
    (``$PDR_TEST_IMPORTS``, a temporary directory test/conftest.py makes and removes,
    shared by the xdist workers; never in the repository) under a key of the file's path,
    size, time and the arguments. A worker that finds another importing the same file
    waits for it. Read it, do not write to it."""
    stat = csv.stat()
    key = hashlib.sha256(repr((str(csv), stat.st_size, stat.st_mtime_ns,
                               import_args)).encode()).hexdigest()[:16]
    folder = Path(os.environ[IMPORTS_ENV])
    bag = folder / f"{csv.stem}_{key}"
    with open(folder / f"{key}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not bag.exists():
            partial = folder / f"{csv.stem}_{key}.partial"
            shutil.rmtree(partial, ignore_errors=True)
            result = cli("pdr-sim", "import-csv", csv, "--out", partial, *import_args)
            assert result.returncode == 0, f"{csv}: import-csv failed: {result.stderr}"
            partial.rename(bag)
    return bag


def wait_for_log(proc: subprocess.Popen, *texts: str, timeout: float = 60.0) -> None:
    """Wait until the process's log holds every one of ``texts`` (a start handshake)."""
    deadline = time.monotonic() + timeout
    while not all(t in log_text(proc) for t in texts):
        if proc.poll() is not None or time.monotonic() > deadline:
            raise AssertionError(f"{proc.args[1]} never logged {texts}:\n{log_text(proc)}")
        time.sleep(0.05)


@contextmanager
def kept_figures() -> Iterator[list]:
    """The Matplotlib figures the plotting functions draw, kept open (they close them)
    so that a test can read their titles, axes and limits; closed at the end."""
    import matplotlib.pyplot as plt

    kept, close = [], plt.close
    plt.close = kept.append
    try:
        yield kept
    finally:
        plt.close = close
        for fig in kept:
            close(fig)


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


def drop_reason(stamp_ns: int, last_kept_ns: int | None, accel, gyro) -> str | None:
    """What the live nodes must do with one IMU sample, written from their documented rule
    (docs/nodes.md): drop a NaN/Inf one, then one beyond any IMU's range (4000 m/s²,
    350 rad/s), then one stamped not after the last kept; the count's key, or None when
    the sample is kept."""
    values = np.r_[np.asarray(accel, float), np.asarray(gyro, float)]
    if not np.isfinite(values).all():
        return "non_finite"
    if (np.abs(values[:3]) > MAX_PLAUSIBLE_ACCEL_MPS2).any() or \
            (np.abs(values[3:]) > MAX_PLAUSIBLE_RATE_RADPS).any():
        return "implausible"
    if last_kept_ns is not None and stamp_ns <= last_kept_ns:
        return "stamp_not_increasing"
    return None


@functools.cache
def pocket_walk(seconds: float = 30.0):
    """The first ``seconds`` of bags/pocket_walk: stamps [ns], specific force [m/s²], rate
    [rad/s] and field [T] (the live adapter's tests: test_fuzz, test_take_lines)."""
    reader = BagReader(ROOT / "bags" / "pocket_walk")
    imu, mag = reader.read("/imu/data"), reader.read("/imu/mag")
    n = int(np.searchsorted(imu.stamp_ns, imu.stamp_ns[0] + seconds * 1e9))
    return (imu.stamp_ns[:n], imu["linear_acceleration"][:n], imu["angular_velocity"][:n],
            mag["magnetic_field"][:n])


def samples_of(sim, gyro: bool = True, mag: bool = True):
    """A pdr_sim simulation's IMU (and magnetometer) samples by name
    (pdr_pocket.samples.Samples) on its own time axis [s]: without the gyroscope or the
    magnetometer when told."""
    from pdr_pocket.samples import Samples

    return Samples(sim.trajectory.t, sim.imu["linear_acceleration"],
                   sim.imu["angular_velocity"] if gyro else None,
                   sim.mag["magnetic_field"] if mag else None)

