"""CSV export (pdr_core.io.csv_export): the columns a bag's topics give, each topic at its
own stamps with empty cells between, and a log that pdr_core.io.csv_import reads back to the
same samples."""
import numpy as np
import pytest

from pdr_core.errors import InputError
from pdr_core.io.csv_export import LogTable, import_arguments, log_table, write_csv
from pdr_core.io.csv_import import CsvImuFormat, import_csv
from pdr_core.io.msgtypes import IMU, MAGNETIC_FIELD

START_NS = 1_700_000_000_123_456_789


def imu_batch(n=50, gyro=True, seed=0):
    """``n`` samples at about 100 Hz with jittered stamps, at rest with noise."""
    from pdr_core.io.batch import MessageBatch

    rng = np.random.default_rng(seed)
    stamps = START_NS + np.cumsum(rng.integers(9_000_000, 11_000_000, n)) - 9_000_000
    rate_cov = np.zeros((n, 9))
    if not gyro:
        rate_cov[:, 0] = -1.0
    return MessageBatch(IMU, stamps, "imu_link", {
        "orientation": np.tile([0.0, 0.0, 0.0, 1.0], (n, 1)),
        "orientation_covariance": np.zeros((n, 9)),
        "angular_velocity": rng.normal(0, 0.01, (n, 3)),
        "angular_velocity_covariance": rate_cov,
        "linear_acceleration": rng.normal([0, 0, 9.81], 0.05, (n, 3)),
        "linear_acceleration_covariance": np.zeros((n, 9))})


def mag_batch(stamps, growth=1e-3):
    """Readings in Munich's field, each ``growth`` times the field larger than the last."""
    from pdr_core.io.batch import MessageBatch

    n = len(stamps)
    return MessageBatch(MAGNETIC_FIELD, stamps, "imu_link", {
        "magnetic_field": np.outer(1 + growth * np.arange(n), [21e-6, -43e-6, 1e-8]),
        "magnetic_field_covariance": np.zeros((n, 9))})


def test_without_gyroscope_the_rates_are_left_out():
    table = log_table(imu_batch(gyro=False))
    assert table.columns == ["t_s", "acc_x_mps2", "acc_y_mps2", "acc_z_mps2"]
    assert "--gyro-cols" not in import_arguments(table)


def test_each_topic_is_written_at_its_own_stamps_with_empty_cells_between(tmp_path):
    imu = imu_batch()
    t = imu.stamp_ns
    # one reading 0.02 s before the first sample, one at the 40th
    first, second = t[0] - 20_000_000, t[40]
    table = log_table(imu, mag_batch(np.array([first, second]), growth=1.0))
    assert table.origin_ns == first and len(table.values) == len(imu) + 1
    assert np.array_equal(table.values[:, 0], (np.sort(np.r_[t, first]) - first) * 1e-9)
    mag = table.values[:, table.columns.index("mag_x_t")]
    acc = table.values[:, table.columns.index("acc_x_mps2")]
    assert np.array_equal(mag[[0, 41]], [21e-6, 42e-6])
    assert np.isnan(np.delete(mag, [0, 41])).all() and np.isnan(acc[0])
    assert np.array_equal(acc[1:], imu["linear_acceleration"][:, 0])
    write_csv(tmp_path / "log.csv", table)
    lines = (tmp_path / "log.csv").read_text().splitlines()
    assert lines[1] == "0.0,,,,,,,2.1e-05,-4.3e-05,1e-08"
    assert lines[2].endswith(",,,") and not lines[42].endswith(",")


def test_the_log_reads_back_to_the_same_samples(tmp_path):
    imu = imu_batch()
    mag = mag_batch(imu.stamp_ns[::2] + 3_000_000)
    table = log_table(imu, mag)
    write_csv(tmp_path / "log.csv", table)
    args = import_arguments(table)
    opts = dict(zip(args[::2], args[1::2], strict=True))
    cols = {name: tuple(value.split(",")) for name, value in opts.items()}
    fmt = CsvImuFormat(time_col="t_s", acc_cols=cols["--acc-cols"],
                       gyro_cols=cols["--gyro-cols"], mag_cols=cols["--mag-cols"],
                       mag_unit=opts["--mag-unit"])
    back = import_csv(tmp_path / "log.csv", fmt)
    assert np.array_equal(back.imu.stamp_ns, imu.stamp_ns - imu.stamp_ns[0])
    assert np.array_equal(back.mag.stamp_ns, mag.stamp_ns - imu.stamp_ns[0])
    assert np.array_equal(back.imu["linear_acceleration"], imu["linear_acceleration"])
    assert np.array_equal(back.imu["angular_velocity"], imu["angular_velocity"])
    assert np.array_equal(back.mag["magnetic_field"], mag["magnetic_field"])


def test_an_existing_file_is_kept_unless_overwrite(tmp_path):
    out = tmp_path / "log.csv"
    out.write_text("mine\n")
    table = LogTable(["t_s"], np.array([[0.0], [0.5]]))
    with pytest.raises(InputError, match="output exists already"):
        write_csv(out, table)
    assert out.read_text() == "mine\n"
    write_csv(out, table, overwrite=True)
    assert out.read_text() == "t_s\n0.0\n0.5\n"
    assert [p.name for p in tmp_path.iterdir()] == ["log.csv"]
