"""``pdr-sim import-csv`` as its console script runs it (its ``main``, in the test's process:
wstest.cli): bad input gives exit 2, one line, no output."""
import pytest

from pdr_core.io.bag import BagReader
from pdr_core.io.csv_rows import MIN_ROWS_CONSTANT_AXIS
from wstest import cli

GOOD = "t,ax,ay,az\n0.00,0,0,9.8\n0.01,0,0,9.8\n0.02,0,0,9.8\n"


def run(*args):
    return cli("pdr-sim", "import-csv", *args)


def import_args(csv, out):
    return [str(csv), "--out", str(out), "--time-col", "t", "--acc-cols", "ax,ay,az"]


def test_good_file(tmp_path):
    csv = tmp_path / "good.csv"
    csv.write_text(GOOD)
    result = run(*import_args(csv, tmp_path / "bag"))
    assert result.returncode == 0, result.stderr
    assert len(BagReader(tmp_path / "bag").read("/imu/data")) == 3


@pytest.mark.parametrize("content, problem", [
    (GOOD + "0.03,0,nan,9.8\n", "row 5, column ay: empty or NaN, while other columns of "
                                "the IMU (ax,ay,az) hold values"),
    (GOOD + "0.03,0,,9.8\n", "row 5, column ay: empty or NaN, while"),
    (GOOD + "0.03,0,x,9.8\n", "row 5, column ay: 'x' is not a number"),
    (GOOD + "0.03,,,\n", "row 5: no reading of any sensor (every cell of ax,ay,az is empty)"),
    (GOOD + ",0,0,9.8\n", "row 5, column t: empty or NaN (no time)"),
    (GOOD + "0.015,0,0,9.8\n", "row 5, column t: time 0.015000000 does not increase over "
                               "the IMU's previous reading"),
    ("t,ax,ay,az\n", "no data rows"),
])
def test_bad_rows(tmp_path, content, problem):
    csv = tmp_path / "bad.csv"
    csv.write_text(content)
    result = run(*import_args(csv, tmp_path / "bag"))
    assert result.returncode == 2
    [line] = result.stderr.splitlines()
    assert line.startswith(f"pdr-sim: error: {csv}: {problem}")
    assert list(tmp_path.iterdir()) == [csv], "no half-written output"


def test_missing_file(tmp_path):
    result = run(*import_args(tmp_path / "none.csv", tmp_path / "bag"))
    assert result.returncode == 2
    assert result.stderr == f"pdr-sim: error: {tmp_path / 'none.csv'}: no such file\n"


def test_existing_output_is_kept(tmp_path):
    csv = tmp_path / "good.csv"
    csv.write_text(GOOD)
    (tmp_path / "bag").mkdir()
    result = run(*import_args(csv, tmp_path / "bag"))
    assert result.returncode == 2 and "output exists already" in result.stderr
    assert list((tmp_path / "bag").iterdir()) == []


@pytest.mark.parametrize("force", [(), ("--force",)])
def test_a_constant_accelerometer_column_is_refused(tmp_path, force):
    """A phone's accuracy column (always 3) mapped as the accelerometer's x: exit 2, one
    line naming the file and the column, --force or not."""
    csv = tmp_path / "phone.csv"
    rows = [f"{5_000_000 * i},3,{0.01 * (i % 7)},{0.02 * (i % 5)},{9.8 + 0.01 * (i % 3):.2f}\n"
            for i in range(MIN_ROWS_CONSTANT_AXIS)]
    csv.write_text("t_ns,accuracy,ax,ay,az\n" + "".join(rows))
    result = run(csv, "--out", tmp_path / "bag", "--time-col", "t_ns", "--time-unit", "ns",
                 "--acc-cols", "accuracy,ay,az", *force)
    assert result.returncode == 2
    [line] = result.stderr.splitlines()
    assert line.startswith(f"pdr-sim: error: {csv}: column accuracy, the first of --acc-cols, "
                           "is 3 in all 1000 rows: constant over the whole recording, so it "
                           "cannot be an accelerometer axis")
    assert line.endswith("(--force does not accept a constant axis)")
    assert list(tmp_path.iterdir()) == [csv], "no output"
    kept = run(csv, "--out", tmp_path / "bag", "--time-col", "t_ns", "--time-unit", "ns",
               "--acc-cols", "ax,ay,az", *force)
    assert kept.returncode == 0, kept.stderr


def pressure_log(scale: float) -> str:
    """Three rows with a barometer column p of 1013.20-1013.25 hPa, times ``scale``."""
    return "t,ax,ay,az,p\n" + "".join(f"{0.01 * i:.2f},0,0,9.8,{p * scale:.2f}\n"
                                      for i, p in enumerate((1013.20, 1013.25, 1013.22)))


@pytest.mark.parametrize("unit, scale", [("hpa", 1.0), ("pa", 100.0)])
def test_a_pressure_column_is_written_to_imu_pressure(tmp_path, unit, scale):
    csv = tmp_path / "baro.csv"
    csv.write_text(pressure_log(scale))
    result = run(*import_args(csv, tmp_path / "bag"), "--pressure-col", "p",
                 "--pressure-unit", unit)
    assert result.returncode == 0, result.stderr
    pressure = BagReader(tmp_path / "bag").read("/imu/pressure")
    assert pressure.msgtype == "sensor_msgs/msg/FluidPressure"
    assert pressure["fluid_pressure"].tolist() == pytest.approx([101320.0, 101325.0, 101322.0])


def test_a_pressure_in_pa_read_as_hpa_is_refused_naming_the_column_and_option(tmp_path):
    csv = tmp_path / "baro.csv"
    csv.write_text(pressure_log(100.0))
    result = run(*import_args(csv, tmp_path / "bag"), "--pressure-col", "p")
    assert result.returncode == 2
    [line] = result.stderr.splitlines()
    assert line.startswith(f"pdr-sim: error: {csv}: column p: median pressure 1.013e+05 hPa")
    assert "(--pressure-unit hpa)" in line and "pass --pressure-unit pa" in line
    assert list(tmp_path.iterdir()) == [csv], "no output"
