"""A phone's own export, one CSV per sensor (pdr_core.io.phone_import, issue 54): the
accelerometer paired with its gravity file and the gyroscope without inventing data, iOS's
sign turned, the magnetometer and the barometer at their own stamps, and the refusals that
name the option that fixes them."""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError
from pdr_core.io.phone_import import (
    PhoneLayout,
    SensorFile,
    import_phone,
    sensor_logger_layout,
)
from pdr_core.sensors.sample_pairing import interval_bounds, interval_means

T0_NS = 1_610_478_706_799_378_400          # a Sensor Logger stamp: ns since the epoch
YAW_RATE_RADPS = 0.4
TILT_RAD = 0.3


def attitude(t_s: np.ndarray) -> Rotation:
    """The phone's attitude, device to world (x north, z up): tilted, turning about up."""
    yaw = Rotation.from_euler("z", YAW_RATE_RADPS * np.asarray(t_s)[:, None])
    return yaw * Rotation.from_euler("x", TILT_RAD)


def motion(t_s: np.ndarray) -> np.ndarray:
    """A gravity-removed accelerometer's reading in Android's sign [m/s²], (N, 3)."""
    return 0.8 * np.column_stack([np.sin(2 * np.pi * t_s), np.cos(2 * np.pi * t_s),
                                  np.sin(4 * np.pi * t_s)])


def true_force(t_s: np.ndarray) -> np.ndarray:
    """The specific force in device axes [m/s²]: the motion plus gravity's reaction."""
    up = attitude(t_s).inv().apply([0.0, 0.0, 1.0])
    return motion(t_s) + STANDARD_GRAVITY_MPS2 * up


def write(path: Path, header: list[str], rows: np.ndarray | list) -> None:
    with path.open("w", newline="") as stream:
        out = csv.writer(stream)
        out.writerow(header)
        out.writerows(rows)


def vector_rows(stamp_ns: np.ndarray, xyz: np.ndarray) -> list:
    """Sensor Logger's vector rows: time, z, y, x."""
    return [[int(t), *(repr(float(c)) for c in v[::-1])]
            for t, v in zip(stamp_ns, xyz, strict=True)]


def sensor_logger_export(folder: Path, platform: str, orientation: bool = True,
                         metadata: bool = True, seconds: float = 6.0) -> Path:
    """A Sensor Logger folder of ``platform`` (android, ios): accelerometer and gravity at
    100 Hz, the gyroscope at 500 Hz starting 0.25 s later, the magnetometer at 100 Hz off
    the accelerometer's stamps, the barometer at 1 Hz."""
    folder.mkdir(parents=True, exist_ok=True)
    sign = 1.0 if platform == "android" else -1.0
    acc_ns = T0_NS + np.arange(int(seconds * 100)) * 10_000_000
    t = (acc_ns - T0_NS) * 1e-9
    up = attitude(t).inv().apply([0.0, 0.0, 1.0])
    write(folder / "Accelerometer.csv", ["time", "z", "y", "x"],
          vector_rows(acc_ns, sign * motion(t)))
    write(folder / "Gravity.csv", ["time", "z", "y", "x"],
          vector_rows(acc_ns, sign * STANDARD_GRAVITY_MPS2 * up))
    gyro_ns = T0_NS + 250_000_000 + np.arange(int((seconds - 0.5) * 500)) * 2_000_000
    rate = attitude((gyro_ns - T0_NS) * 1e-9).inv().apply([0.0, 0.0, YAW_RATE_RADPS])
    write(folder / "Gyroscope.csv", ["time", "z", "y", "x"], vector_rows(gyro_ns, rate))
    mag_ns = acc_ns + 3_333_333
    write(folder / "Magnetometer.csv", ["time", "z", "y", "x"],
          vector_rows(mag_ns, np.tile([20.0, 5.0, -40.0], (len(mag_ns), 1))))
    baro_ns = T0_NS - 500_000_000 + np.arange(int(seconds)) * 1_000_000_000
    write(folder / "Barometer.csv", ["time", "relativeAltitude", "pressure"],
          [[int(s), 0, 1013.25 + 0.01 * k] for k, s in enumerate(baro_ns)])
    if orientation:
        q = attitude(t).as_quat()
        write(folder / "Orientation.csv", ["time", "qz", "qy", "qx", "qw"],
              [[int(s), *(repr(float(c)) for c in (v[2], v[1], v[0], v[3]))]
               for s, v in zip(acc_ns, q, strict=True)])
    if metadata:
        write(folder / "Metadata.csv", ["version", "device name", "recording time",
                                        "platform"],
              [[2, "phone", "2021-01-12_21-11-46", platform]])
    return folder


@pytest.mark.parametrize("platform", ["android", "ios"])
def test_both_platforms_give_the_specific_force_at_the_accelerometer_stamps(tmp_path,
                                                                             platform):
    folder = sensor_logger_export(tmp_path / platform, platform)
    layout = sensor_logger_layout(folder)
    assert "Orientation.csv" in layout.sign_source
    result = import_phone(layout)
    stamps = result.imu.stamp_ns
    # the gyroscope starts 0.25 s late: the samples before it are dropped, none invented
    assert stamps[0] >= T0_NS + 250_000_000 - 5_000_000
    np.testing.assert_allclose(result.imu["linear_acceleration"],
                               true_force((stamps - T0_NS) * 1e-9), atol=1e-9)
    rate = attitude((stamps - T0_NS) * 1e-9).inv().apply([0.0, 0.0, YAW_RATE_RADPS])
    np.testing.assert_allclose(result.imu["angular_velocity"], rate, atol=2e-4)
    assert "(5 a sample)" in result.lines[0]


def test_the_magnetometer_and_the_barometer_keep_their_own_stamps(tmp_path):
    folder = sensor_logger_export(tmp_path / "a", "android")
    result = import_phone(sensor_logger_layout(folder))
    mag_ns = np.loadtxt(folder / "Magnetometer.csv", delimiter=",", skiprows=1, usecols=0,
                        dtype=np.int64)
    baro = np.loadtxt(folder / "Barometer.csv", delimiter=",", skiprows=1)
    baro_ns = np.loadtxt(folder / "Barometer.csv", delimiter=",", skiprows=1, usecols=0,
                         dtype=np.int64)
    np.testing.assert_array_equal(result.mag.stamp_ns, mag_ns)
    np.testing.assert_allclose(result.mag["magnetic_field"][0], [20e-6, 5e-6, -40e-6])
    np.testing.assert_array_equal(result.pressure.stamp_ns, baro_ns)
    np.testing.assert_allclose(result.pressure["fluid_pressure"], baro[:, 2] * 100.0)
    assert [line.split(":")[0] for line in result.lines] == ["imu/data", "imu/mag",
                                                             "imu/pressure"]
    assert "at 1 Hz" in result.lines[2] and "median 1013.27 hPa" in result.lines[2]


def test_metadata_decides_the_sign_without_the_phones_attitude(tmp_path):
    folder = sensor_logger_export(tmp_path / "i", "ios", orientation=False)
    layout = sensor_logger_layout(folder)
    assert layout.acc_sign == -1.0 and "Metadata.csv" in layout.sign_source


def test_a_folder_that_cannot_tell_the_sign_names_the_option(tmp_path):
    folder = sensor_logger_export(tmp_path / "x", "ios", orientation=False, metadata=False)
    with pytest.raises(InputError, match="--convention"):
        sensor_logger_layout(folder)
    assert sensor_logger_layout(folder, convention="ios").acc_sign == -1.0


def test_a_folder_without_an_accelerometer_names_what_it_found(tmp_path):
    folder = sensor_logger_export(tmp_path / "g", "android")
    (folder / "Gravity.csv").unlink()
    with pytest.raises(InputError, match=r"found: Accelerometer.csv, Barometer.csv"):
        sensor_logger_layout(folder)


def test_a_row_that_goes_back_in_time_is_named_or_dropped(tmp_path):
    folder = sensor_logger_export(tmp_path / "b", "android")
    path = folder / "Magnetometer.csv"
    lines = path.read_text().splitlines()
    lines[5], lines[6] = lines[6], lines[5]
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError,
                       match=r"Magnetometer.csv: row 7, column time: time .* does not increase"):
        import_phone(sensor_logger_layout(folder))
    result = import_phone(sensor_logger_layout(folder, drop_invalid=True))
    assert len(result.mag) == len(lines) - 2


def test_named_files_in_seconds_with_their_own_columns(tmp_path):
    t = np.arange(300) * 0.01
    force = true_force(t)
    write(tmp_path / "acc.csv", ["t", "ax", "ay", "az"],
          [[repr(float(s)), *(repr(float(c)) for c in f)] for s, f in zip(t, force, strict=True)])
    write(tmp_path / "gyr.csv", ["t", "wx", "wy", "wz"],
          [[repr(float(s)), 0.0, 0.0, 0.1] for s in t + 0.004])
    layout = PhoneLayout(accelerometer=SensorFile(tmp_path / "acc.csv", "t", ("ax", "ay", "az")),
                         gyroscope=SensorFile(tmp_path / "gyr.csv", "t", ("wx", "wy", "wz")),
                         time_unit="s")
    result = import_phone(layout)
    assert len(result.imu) == 300 and result.mag is None and result.pressure is None
    np.testing.assert_allclose(result.imu["linear_acceleration"], force)
    np.testing.assert_allclose(result.imu["angular_velocity"][:, 2], 0.1)


def test_a_gravity_removed_accelerometer_alone_names_the_gravity_file(tmp_path):
    folder = sensor_logger_export(tmp_path / "r", "android")
    layout = PhoneLayout(accelerometer=SensorFile(folder / "Accelerometer.csv", "time",
                                                  ("x", "y", "z")))
    with pytest.raises(InputError, match=r"looks gravity-removed.*--gravity FILE") as refused:
        import_phone(layout)
    assert "--acc-unit" not in str(refused.value)
    gravity = SensorFile(folder / "Gravity.csv", "time", ("x", "y", "z"))
    assert len(import_phone(PhoneLayout(accelerometer=layout.accelerometer,
                                        gravity=gravity)).imu) == 600


def test_a_time_column_in_another_unit_is_refused_with_the_fix(tmp_path):
    folder = sensor_logger_export(tmp_path / "n", "android")
    layout = sensor_logger_layout(folder)
    with pytest.raises(InputError, match=r"--time-unit"):
        import_phone(PhoneLayout(**{**layout.__dict__, "time_unit": "us"}))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.integers(1, 40), min_size=2, max_size=30),
       st.lists(st.integers(0, 400), min_size=0, max_size=60))
def test_interval_means_are_the_means_of_the_readings_in_each_interval(gaps, readings):
    sample_ns = np.cumsum(np.asarray(gaps, np.int64)) * 10
    reading_ns = np.unique(np.asarray(readings, np.int64))
    values = np.column_stack([reading_ns * 0.5, -reading_ns * 1.0])
    means, count = interval_means(sample_ns, reading_ns, values)
    start, end = interval_bounds(sample_ns)
    assert (start[1:] == end[:-1]).all()
    for k in range(len(sample_ns)):
        inside = (reading_ns > start[k]) & (reading_ns <= end[k])
        assert count[k] == inside.sum()
        if inside.any():
            np.testing.assert_allclose(means[k], values[inside].mean(axis=0))
        else:
            assert np.isnan(means[k]).all()
