"""CSV import: units, axes, columns and refused rows."""
import warnings
from dataclasses import replace

import numpy as np
import pytest

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError, InputWarning
from pdr_core.io.csv_import import CsvImuFormat, axis_matrix, import_csv
from pdr_core.io.csv_rows import MIN_ROWS_CONSTANT_AXIS, constant_columns

HEADER = "time,ax,ay,az,gx,gy,gz,px,py,pz\n"


def write_csv(path, rows, header=HEADER):
    path.write_text(header + "".join(",".join(str(v) for v in row) + "\n" for row in rows))
    return path


def rows(n=5):
    return [[0.01 * i, 0.0, 0.0, 1.0, 90.0, 0.0, 0.0, i, 2 * i, 0.0] for i in range(n)]


FMT = CsvImuFormat(time_col="time", acc_cols=("ax", "ay", "az"), acc_unit="g",
                   gyro_cols=("gx", "gy", "gz"), gyro_unit="deg/s", pos_cols=("px", "py", "pz"))


def test_units_are_converted_to_si(tmp_path):
    result = import_csv(write_csv(tmp_path / "a.csv", rows()), FMT)
    np.testing.assert_allclose(result.imu["linear_acceleration"][:, 2], STANDARD_GRAVITY_MPS2)
    np.testing.assert_allclose(result.imu["angular_velocity"][:, 0], np.pi / 2)
    np.testing.assert_array_equal(result.imu.stamp_ns, np.arange(5) * 10_000_000)
    np.testing.assert_array_equal(result.pose["pose.position"][:, 1], 2 * np.arange(5))
    assert result.imu["orientation_covariance"][0, 0] == -1.0
    assert result.imu["angular_velocity_covariance"][0, 0] == 0.0
    assert list(result.imu.frame_id) == ["imu_link"] * 5 and result.pose.frame_id[0] == "map"


def test_columns_by_index_without_header_and_time_in_ns(tmp_path):
    path = write_csv(tmp_path / "b.csv", [[1_000_000 * i, 0.1, 0.2, 9.8] for i in range(4)],
                     header="")
    fmt = CsvImuFormat(time_col="0", time_unit="ns", acc_cols=("1", "2", "3"), header=False)
    result = import_csv(path, fmt)
    assert len(result.imu) == 4 and result.pose is None
    np.testing.assert_array_equal(result.imu.stamp_ns, np.arange(4) * 1_000_000)
    assert result.imu["angular_velocity_covariance"][0, 0] == -1.0, "no gyro: rates unknown"


def test_axis_remap_with_signs(tmp_path):
    np.testing.assert_array_equal(axis_matrix(("-y", "x", "z")) @ [1, 2, 3], [-2, 1, 3])
    fmt = CsvImuFormat(time_col="time", acc_cols=("ax", "ay", "az"), acc_unit="g",
                       axes=("z", "-x", "y"))
    result = import_csv(write_csv(tmp_path / "c.csv", rows()), fmt)
    np.testing.assert_allclose(result.imu["linear_acceleration"][0],
                               [STANDARD_GRAVITY_MPS2, -0.0, 0.0])


def test_per_sensor_remap(tmp_path):
    fmt = CsvImuFormat(time_col="time", acc_cols=("ax", "ay", "az"), acc_unit="g",
                       gyro_cols=("gx", "gy", "gz"), gyro_unit="deg/s", acc_axes=("-x", "-y", "-z"))
    result = import_csv(write_csv(tmp_path / "k.csv", rows()), fmt)
    np.testing.assert_allclose(result.imu["linear_acceleration"][0],
                               [0.0, 0.0, -STANDARD_GRAVITY_MPS2])
    np.testing.assert_allclose(result.imu["angular_velocity"][0], [np.pi / 2, 0.0, 0.0])


@pytest.mark.parametrize("axes", [("x", "x", "z"), ("x", "y", "w")])
def test_bad_axes(axes):
    with pytest.raises(InputError, match="--axes"):
        axis_matrix(axes)


def test_nan_cell_is_refused_with_its_row_and_column(tmp_path):
    data = rows()
    data[3][2] = float("nan")
    path = write_csv(tmp_path / "d.csv", data)
    with pytest.raises(InputError) as refused:
        import_csv(path, FMT)
    assert str(refused.value) == (
        f"{path}: row 5, column ay: empty or NaN, while other columns of the IMU "
        "(ax,ay,az,gx,gy,gz) hold values (a sensor not yet started, or a value lost?) (1 such "
        "rows; --drop-invalid drops them)")
    result = import_csv(path, CsvImuFormat(**{**FMT.__dict__, "drop_invalid": True}))
    assert len(result.imu) == 4 and result.rows_invalid == 1


def test_time_going_backwards_is_refused(tmp_path):
    data = rows()
    data[2][0] = 0.0
    path = write_csv(tmp_path / "e.csv", data)
    with pytest.raises(InputError, match=r"row 4, column time: time 0\.000000000 does not "
                                         r"increase over the IMU's previous reading \(1 such"):
        import_csv(path, FMT)
    result = import_csv(path, CsvImuFormat(**{**FMT.__dict__, "drop_invalid": True}))
    np.testing.assert_array_equal(result.imu.stamp_ns, [0, 10_000_000, 30_000_000, 40_000_000])


def test_exact_duplicate_rows(tmp_path):
    data = rows()
    data.insert(2, list(data[1]))
    path = write_csv(tmp_path / "f.csv", data)
    with pytest.raises(InputError, match="row 4: exact duplicate of the previous row"):
        import_csv(path, FMT)
    result = import_csv(path, CsvImuFormat(**{**FMT.__dict__, "drop_duplicates": True}))
    assert len(result.imu) == 5 and result.rows_duplicate == 1 and result.rows_read == 6


def test_same_time_with_other_values_is_not_a_duplicate(tmp_path):
    data = rows()
    data.insert(2, list(data[1]))
    data[2][1] = 5.0
    with pytest.raises(InputError, match="does not increase"):
        import_csv(write_csv(tmp_path / "g.csv", data),
                   CsvImuFormat(**{**FMT.__dict__, "drop_duplicates": True}))


def test_unknown_column_lists_the_columns(tmp_path):
    fmt = CsvImuFormat(time_col="t", acc_cols=("ax", "ay", "az"))
    with pytest.raises(InputError, match=r"no column 't' \(columns: time, ax"):
        import_csv(write_csv(tmp_path / "h.csv", rows()), fmt)


def test_unparsable_and_missing_files(tmp_path):
    path = tmp_path / "i.csv"
    path.write_text(HEADER + "0,1,2,3,4,5,6,7,8,9\n0.01,1,2,oops,4,5,6,7,8,9\n")
    with pytest.raises(InputError, match=r"i\.csv: row 3, column az: 'oops' is not a number$"):
        import_csv(path, FMT)
    path.write_text(HEADER + "0,1,2,3,4,5,6,7,8,9\n0.01,1,2,3,4,5,6,7,8\n")
    with pytest.raises(InputError, match=r"i\.csv: row 3: 9 cells, but the first data row "
                                         r"has 10$"):
        import_csv(path, FMT)
    with pytest.raises(InputError, match="no such file"):
        import_csv(tmp_path / "none.csv", FMT)


def test_unknown_unit(tmp_path):
    fmt = CsvImuFormat(time_col="time", acc_cols=("ax", "ay", "az"), acc_unit="furlong")
    with pytest.raises(InputError, match="--acc-unit: unknown unit 'furlong'"):
        import_csv(write_csv(tmp_path / "j.csv", rows()), fmt)


def test_position_remap(tmp_path):
    fmt = CsvImuFormat(time_col="time", acc_cols=("ax", "ay", "az"), acc_unit="g",
                       pos_cols=("px", "py", "pz"), pos_axes=("-x", "y", "z"))
    result = import_csv(write_csv(tmp_path / "m.csv", rows()), fmt)
    np.testing.assert_array_equal(result.pose["pose.position"][:, 0], -np.arange(5))


def phone_log(path, n, header=True, seed=0):
    """``n`` rows of a phone's log at 200 Hz: t_ns, accuracy (always 3), ax, ay, az [m/s²]
    (noise about g), gx, gy, gz [rad/s] (all 0: a gyroscope quantised at rest)."""
    rng = np.random.default_rng(seed)
    data = np.column_stack([np.arange(n) * 5_000_000, np.full(n, 3.0),
                            rng.normal([0.0, 0.0, 9.81], 0.02, (n, 3)), np.zeros((n, 3))])
    np.savetxt(path, data, delimiter=",", comments="",
               header="t_ns,accuracy,ax,ay,az,gx,gy,gz" if header else "")
    return path


@pytest.mark.parametrize("header, acc_cols, named", [
    (True, ("accuracy", "ay", "az"), "accuracy"),
    (True, ("1", "3", "4"), "accuracy"),        # by index, named by its header
    (False, ("2", "3", "1"), "1"),              # no header: by its index
])
@pytest.mark.parametrize("force", [False, True])
def test_a_constant_accelerometer_column_is_refused_even_with_force(tmp_path, header, acc_cols,
                                                                    named, force):
    path = phone_log(tmp_path / "phone.csv", MIN_ROWS_CONSTANT_AXIS, header)
    which = "third" if acc_cols[2] == named else "first"
    fmt = CsvImuFormat(time_col="0", time_unit="ns", acc_cols=acc_cols, header=header,
                       accept_implausible=force)
    with pytest.raises(InputError) as refused:
        import_csv(path, fmt)
    assert str(refused.value) == (
        f"{path}: column {named}, the {which} of --acc-cols, is 3 in all 1000 rows: constant "
        "over the whole recording, so it cannot be an accelerometer axis (a sensor's accuracy "
        "or status column?); check --acc-cols (--force does not accept a constant axis)")


def test_a_short_constant_column_and_a_constant_gyroscope_are_imported(tmp_path):
    short = phone_log(tmp_path / "short.csv", MIN_ROWS_CONSTANT_AXIS - 1)
    fmt = CsvImuFormat(time_col="t_ns", time_unit="ns", acc_cols=("accuracy", "ay", "az"))
    assert len(import_csv(short, fmt).imu) == MIN_ROWS_CONSTANT_AXIS - 1
    still = phone_log(tmp_path / "still.csv", 2 * MIN_ROWS_CONSTANT_AXIS)
    fmt = CsvImuFormat(time_col="t_ns", time_unit="ns", acc_cols=("ax", "ay", "az"),
                       gyro_cols=("gx", "gy", "gz"))
    assert not import_csv(still, fmt).imu["angular_velocity"].any()
    # one value that differs makes a column no longer constant
    assert list(constant_columns(np.c_[np.ones(1000), np.r_[np.ones(999), 1.0001]])) == [0]


# --- the barometer column (issue 41) -------------------------------------------------------
def pressure_log(path, scale=1.0, n=20, nan_row=None):
    """A log with a barometer column ``p`` of about 1000 hPa times ``scale``."""
    body = [[0.01 * i, 0.0, 0.0, 9.8, (1000.0 + 0.01 * (i % 3)) * scale] for i in range(n)]
    if nan_row is not None:
        body[nan_row][4] = "nan"
    return write_csv(path, body, header="t,ax,ay,az,p\n")


PRESSURE_FMT = CsvImuFormat(time_col="t", acc_cols=("ax", "ay", "az"), pressure_col="p")


@pytest.mark.parametrize("unit, scale", [("hpa", 1.0), ("pa", 100.0)])
def test_a_pressure_column_in_hpa_or_pa_becomes_fluid_pressure_in_pa(tmp_path, unit, scale):
    path = pressure_log(tmp_path / "p.csv", scale)
    result = import_csv(path, replace(PRESSURE_FMT, pressure_unit=unit))
    pressure = result.pressure
    assert pressure.msgtype == "sensor_msgs/msg/FluidPressure" and len(pressure) == 20
    np.testing.assert_allclose(pressure["fluid_pressure"][:3], [100_000.0, 100_001.0, 100_002.0])
    np.testing.assert_array_equal(pressure.stamp_ns, result.imu.stamp_ns)
    assert list(pressure.frame_id) == list(result.imu.frame_id)
    assert import_csv(path, replace(PRESSURE_FMT, pressure_col=None,
                                    pressure_unit=unit)).pressure is None


@pytest.mark.parametrize("unit, scale, read, fix", [
    ("pa", 1.0, "1000 Pa", "hpa"),       # hPa given as Pa
    ("hpa", 100.0, "1e+05 hPa = 1e+07 Pa", "pa"),      # Pa given as hPa
])
def test_a_pressure_in_the_wrong_unit_is_refused_naming_column_and_option(tmp_path, unit, scale,
                                                                         read, fix):
    path = pressure_log(tmp_path / "p.csv", scale)
    with pytest.raises(InputError) as refused:
        import_csv(path, replace(PRESSURE_FMT, pressure_unit=unit))
    message = str(refused.value)
    assert message.startswith(f"{path}: column p: median pressure {read}")
    assert f"(--pressure-unit {unit}); expected 300-1100 hPa, 30-110 kPa" in message
    assert message.endswith(f"pass --pressure-unit {fix} (or --force to accept them as read)")
    with pytest.warns(InputWarning, match="accepted as read"):
        import_csv(path, replace(PRESSURE_FMT, pressure_unit=unit, accept_implausible=True))


def test_an_empty_pressure_cell_is_no_barometer_reading_at_that_row(tmp_path):
    """The barometer is a sensor of its own: a row without its reading is an IMU row."""
    path = pressure_log(tmp_path / "p.csv", nan_row=4)
    kept = import_csv(path, PRESSURE_FMT)
    assert len(kept.imu) == 20 and len(kept.pressure) == 19 and kept.rows_invalid == 0
    np.testing.assert_array_equal(kept.pressure.stamp_ns,
                                  np.delete(kept.imu.stamp_ns, 4))


def test_a_constant_pressure_column_is_imported_with_a_warning(tmp_path):
    body = [[0.01 * i, 0.01 * (i % 2), 0.01 * (i % 3), 9.8 + 0.01 * (i % 5), 1013.25]
            for i in range(MIN_ROWS_CONSTANT_AXIS)]
    path = write_csv(tmp_path / "still.csv", body, header="t,ax,ay,az,p\n")
    with pytest.warns(InputWarning, match=r"column p \(--pressure-col\) is 1013.25 in all 1000 "
                                          "rows: constant over the whole recording"):
        result = import_csv(path, PRESSURE_FMT)
    assert len(result.pressure) == MIN_ROWS_CONSTANT_AXIS
    short = write_csv(tmp_path / "short.csv", body[:-1], header="t,ax,ay,az,p\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        import_csv(short, PRESSURE_FMT)


SPARSE_HEADER = "t,ax,ay,az,gx,gy,gz,mx,my,mz,p\n"
SPARSE_FMT = CsvImuFormat(time_col="t", acc_cols=("ax", "ay", "az"),
                          gyro_cols=("gx", "gy", "gz"), mag_cols=("mx", "my", "mz"),
                          pressure_col="p")


def sparse_log(path, extra=()):
    """A logger's one row per sensor event: the IMU at 100 Hz (rows 2-21), the
    magnetometer every 0.05 s 3 ms after an IMU row, the barometer in the IMU's rows
    every 0.1 s; ``extra`` rows appended."""
    lines = []
    for i in range(20):
        p = f"{1000.0 + 0.01 * i:g}" if i % 10 == 0 else ""
        lines.append(f"{0.01 * i:.3f},0.1,0.2,9.8,0.01,0.02,{0.01 * i},,,,{p}")
        if i % 5 == 0:
            lines.append(f"{0.01 * i + 0.003:.3f},,,,,,,20,{i},-40,")
    path.write_text(SPARSE_HEADER + "\n".join(lines + list(extra)) + "\n")
    return path


def test_sparse_sensors_are_each_written_at_their_own_rows(tmp_path):
    result = import_csv(sparse_log(tmp_path / "s.csv"), SPARSE_FMT)
    assert (len(result.imu), len(result.mag), len(result.pressure)) == (20, 4, 2)
    assert result.rows_read == 24 and result.rows_invalid == 0
    np.testing.assert_array_equal(result.imu.stamp_ns, np.arange(20) * 10_000_000)
    np.testing.assert_array_equal(result.mag.stamp_ns, np.arange(4) * 50_000_000 + 3_000_000)
    np.testing.assert_array_equal(result.pressure.stamp_ns, [0, 100_000_000])
    np.testing.assert_allclose(result.mag["magnetic_field"][:, 1], [0, 5e-6, 10e-6, 15e-6])
    np.testing.assert_array_equal(result.pressure["fluid_pressure"], [100_000.0, 100_010.0])


@pytest.mark.parametrize("row, problem", [
    ("0.2,0.1,0.2,9.8,,,,,,,", "row 26, column gx: empty or NaN, while other columns of the "
                               "IMU (ax,ay,az,gx,gy,gz) hold values (a sensor not yet started, "
                               "or a value lost?)"),
    ("0.2,0.1,0.2,9.8,0,0,0,20,,-40,", "row 26, column my: empty or NaN, while other columns "
                                       "of the magnetometer (mx,my,mz) hold values"),
    ("0.2,,,,,,,,,,", "row 26: no reading of any sensor (every cell of ax,ay,az,gx,gy,gz,mx,my,"
                      "mz,p is empty)"),
    ("0.2,0.1,0.2,inf,0,0,0,,,,", "row 26, column az: inf"),
    ("0.1,,,,,,,,,,1000.5", "row 26, column t: time 0.100000000 does not increase over the "
                            "barometer's previous reading"),
])
def test_a_sensor_partly_empty_or_no_sensor_at_all_is_an_invalid_row(tmp_path, row, problem):
    path = sparse_log(tmp_path / "s.csv", [row, "0.3,0.1,0.2,9.8,0,0,0,,,,"])
    with pytest.raises(InputError) as refused:
        import_csv(path, SPARSE_FMT)
    assert str(refused.value).startswith(f"{path}: {problem}")
    assert str(refused.value).endswith("(1 such rows; --drop-invalid drops them)")
    kept = import_csv(path, replace(SPARSE_FMT, drop_invalid=True))
    assert kept.rows_invalid == 1 and len(kept.imu) == 21 and len(kept.mag) == 4
    assert len(kept.pressure) == 2


def test_blank_lines_are_rows_numbered_as_the_files_lines(tmp_path):
    fast = import_csv(write_csv(tmp_path / "fast.csv", rows()), FMT)
    path = tmp_path / "blank.csv"
    path.write_text((tmp_path / "fast.csv").read_text().replace("\n", "\n\n", 2) + "\n\n")
    with pytest.raises(InputError, match=r"blank\.csv: row 2, column time: empty or NaN \(no "
                                         r"time\) \(2 such rows"):
        import_csv(path, FMT)
    slow = import_csv(path, replace(FMT, drop_invalid=True))
    assert slow.rows_invalid == 2 and slow.rows_read == 7
    for name in ("linear_acceleration", "angular_velocity"):
        np.testing.assert_array_equal(slow.imu[name], fast.imu[name])
