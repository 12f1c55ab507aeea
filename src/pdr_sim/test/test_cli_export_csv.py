"""``pdr-sim export-csv`` then the ``import-csv`` command it prints (their ``main``, in the
test's process: wstest.cli): every topic of a bag comes back, each at its own stamps, the
values to the float64 and the stamps to the ns from the log's origin (docs/bags.md)."""
import shlex

import numpy as np
from scipy.spatial.transform import Rotation

from pdr_core.io.bag import BagReader, write_batches
from pdr_core.io.batch import MessageBatch
from pdr_core.io.csv_import import imu_batch, mag_batch, pose_batch
from pdr_core.io.msgtypes import FLUID_PRESSURE
from wstest import cli

START_NS = 1_700_000_000_123_456_789
TOPICS = ("/imu/data", "/imu/mag", "/imu/pressure", "/ground_truth/pose")


def stamps(rng, n, interval_ns, offset_ns=0):
    """``n`` increasing stamps about ``interval_ns`` apart, jittered, from START_NS."""
    jitter = rng.integers(-interval_ns // 10, interval_ns // 10, n)
    return START_NS + offset_ns + np.arange(n) * interval_ns + jitter


def phone_bag(path, seed=0):
    """A 3 s recording: IMU at 100 Hz (a walk's specific force and rates), magnetometer at
    50 Hz and barometer at 10 Hz on clocks of their own, the truth at 100 Hz (positions
    and attitudes, some with w < 0), and a topic export-csv does not write."""
    rng = np.random.default_rng(seed)
    t_imu = stamps(rng, 300, 10_000_000)
    acc = rng.normal([0.0, 0.0, 9.81], 2.0, (300, 3))
    imu = imu_batch(t_imu, "imu_link", acc, rng.normal(0.0, 1.0, (300, 3)))
    t_mag = stamps(rng, 150, 20_000_000, offset_ns=3_000_000)
    mag = mag_batch(t_mag, "imu_link", rng.normal([20e-6, 0.0, -40e-6], 1e-6, (150, 3)))
    t_baro = stamps(rng, 30, 100_000_000, offset_ns=-7_000_000)
    baro = MessageBatch(FLUID_PRESSURE, t_baro, "imu_link", {
        "fluid_pressure": rng.normal(101_325.0, 5.0, 30), "variance": np.zeros(30)})
    truth = pose_batch(t_imu[::2], "map", rng.normal(0.0, 3.0, (150, 3)),
                       Rotation.random(150, random_state=seed).as_quat())
    write_batches(path, {"/imu/data": imu, "/imu/mag": mag, "/imu/pressure": baro,
                         "/ground_truth/pose": truth, "/outside/pressure": baro})
    return path


def test_export_then_the_printed_import_gives_back_every_topic(tmp_path):
    bag = phone_bag(tmp_path / "bag")
    exported = cli("pdr-sim", "export-csv", bag, "--out", tmp_path / "log.csv")
    assert exported.returncode == 0, exported.stderr
    original = BagReader(bag).read_batches(list(TOPICS))
    origin = min(int(original[topic].stamp_ns[0]) for topic in TOPICS)
    lines = exported.stdout.splitlines()
    assert lines[0].endswith(f"; t_s = 0 at the stamp {origin} ns")
    assert lines[1] == "not written: /outside/pressure"
    command = shlex.split(lines[-1].removeprefix("read it back with: "))
    assert command[:2] == ["pdr-sim", "import-csv"]
    imported = cli("pdr-sim", *command[1:], cwd=tmp_path)
    assert imported.returncode == 0, imported.stderr
    assert "300 imu/data messages, 150 imu/mag, 30 imu/pressure, 150 ground_truth/pose " \
           "with attitude" in imported.stdout
    back = BagReader(tmp_path / command[command.index("--out") + 1]).read_batches(list(TOPICS))
    for topic in TOPICS:
        assert np.array_equal(back[topic].stamp_ns, original[topic].stamp_ns - origin), topic
    for topic, field in (("/imu/data", "linear_acceleration"), ("/imu/data", "angular_velocity"),
                         ("/imu/mag", "magnetic_field"), ("/imu/pressure", "fluid_pressure"),
                         ("/ground_truth/pose", "pose.position")):
        assert np.array_equal(back[topic][field], original[topic][field]), field
    # the same rotations; import-csv writes them with w >= 0
    sign = np.where(original["/ground_truth/pose"]["pose.orientation"][:, 3] < 0, -1.0, 1.0)
    np.testing.assert_allclose(back["/ground_truth/pose"]["pose.orientation"],
                               original["/ground_truth/pose"]["pose.orientation"] * sign[:, None],
                               rtol=0, atol=1e-15)


def test_a_bag_without_gyroscope_and_only_imu_data_reads_back(tmp_path):
    rng = np.random.default_rng(1)
    t = stamps(rng, 200, 10_000_000)
    imu = imu_batch(t, "imu_link", rng.normal([0.0, 0.0, 9.81], 1.0, (200, 3)), None)
    write_batches(tmp_path / "bag", {"/imu/data": imu})
    exported = cli("pdr-sim", "export-csv", tmp_path / "bag", "--out", tmp_path / "log.csv")
    assert exported.returncode == 0 and "not written" not in exported.stdout
    assert (tmp_path / "log.csv").read_text().split("\n", 1)[0] == \
        "t_s,acc_x_mps2,acc_y_mps2,acc_z_mps2"
    command = shlex.split(exported.stdout.splitlines()[-1].removeprefix("read it back with: "))
    assert cli("pdr-sim", *command[1:], cwd=tmp_path).returncode == 0
    back = BagReader(tmp_path / "BAG").read("/imu/data")
    assert np.array_equal(back["linear_acceleration"], imu["linear_acceleration"])
    assert (back["angular_velocity_covariance"][:, 0] == -1).all()


def test_an_existing_log_is_kept(tmp_path):
    bag = phone_bag(tmp_path / "bag")
    (tmp_path / "log.csv").write_text("mine\n")
    result = cli("pdr-sim", "export-csv", bag, "--out", tmp_path / "log.csv")
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr == f"pdr-sim: error: {tmp_path / 'log.csv'}: output exists already " \
                            "(remove it or pass --overwrite)\n"
    assert (tmp_path / "log.csv").read_text() == "mine\n"
