"""``pdr-sim import-oxiod`` on small synthetic sequences in OxIOD's layout (issue 53): what it
writes, that import-csv with the truth-attitude options writes the same, and the
refusals (exit 2, one line naming the file and the problem, no output)."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.io.bag import BagReader
from wstest import cli

N = 200
TIME = 1.4955e11           # OxIOD's time column: 5 significant digits, the same in every row


def sequence_tables(n=N, seed=0):
    """(imu (n, 16), vicon (n, 9)) of a phone turning slowly in the hand at 100 Hz."""
    rng = np.random.default_rng(seed)
    t = 0.01 * np.arange(n)
    gravity = np.column_stack([0.1 * np.sin(t), np.full(n, -0.3),
                               -np.sqrt(0.9 - 0.01 * np.sin(t) ** 2)])
    imu = np.column_stack([np.full(n, TIME), rng.normal(0, 1, (n, 3)), rng.normal(0, 0.5, (n, 3)),
                           gravity, rng.normal(0, 0.05, (n, 3)),
                           [20.0, -5.0, -40.0] + rng.normal(0, 0.5, (n, 3))])
    attitude = Rotation.from_euler("ZYX", np.column_stack([0.5 * t, 0.2 * np.sin(t),
                                                           np.full(n, 0.1)]))
    vicon = np.column_stack([np.full(n, TIME), 5000 + np.arange(n), 0.3 * t, np.sin(t),
                             np.full(n, 1.2), attitude.as_quat()])
    return imu, vicon


def write_sequence(folder, k=3, imu=None, vicon=None):
    """imuK.csv and viK.csv in ``folder``; the tables of :func:`sequence_tables` unless
    given."""
    folder.mkdir(parents=True, exist_ok=True)
    default_imu, default_vicon = sequence_tables()
    for name, table in ((f"imu{k}.csv", default_imu if imu is None else imu),
                        (f"vi{k}.csv", default_vicon if vicon is None else vicon)):
        np.savetxt(folder / name, table, delimiter=",", fmt="%.12g")
    return folder


def written(folder, k=3):
    """The tables of the sequence as written (rounded to 12 digits)."""
    return tuple(np.loadtxt(folder / f"{kind}{k}.csv", delimiter=",") for kind in ("imu", "vi"))


def run(*args):
    return cli("pdr-sim", "import-oxiod", *map(str, args))


def test_a_sequence_becomes_the_topics_import_csv_writes(tmp_path):
    folder = write_sequence(tmp_path / "handheld_seq3")
    result = run(folder, "--out", tmp_path / "bag", "--start-s", 100)
    assert result.returncode == 0, result.stderr
    assert (f"{tmp_path / 'bag'}: OxIOD handheld_seq3 (imu3.csv + vi3.csv): 200 samples from "
            "100.000 s, 1.990 s at 100.0 Hz mean;") in result.stdout
    assert "magnetometer: yes; truth: attitude and position (200 ground_truth/pose); " \
           "0 truth glitches" in result.stdout
    reader = BagReader(tmp_path / "bag")
    imu, mag, pose = (reader.read(topic) for topic in ("/imu/data", "/imu/mag",
                                                        "/ground_truth/pose"))
    table, vicon = written(folder)
    stamps = 100_000_000_000 + 10_000_000 * np.arange(N)
    for batch in (imu, mag, pose):
        np.testing.assert_array_equal(batch.stamp_ns, stamps)
    np.testing.assert_allclose(imu["linear_acceleration"],
                               -(table[:, 7:10] + table[:, 10:13]) * STANDARD_GRAVITY_MPS2,
                               rtol=1e-10)
    np.testing.assert_allclose(imu["angular_velocity"], table[:, 4:7], rtol=1e-10)
    np.testing.assert_allclose(mag["magnetic_field"], table[:, 13:16] * 1e-6, rtol=1e-10)
    np.testing.assert_allclose(pose["pose.position"], vicon[:, 2:5], rtol=1e-10)
    phone = Rotation.from_quat(vicon[:, 5:9]) * Rotation.from_euler("z", np.pi)
    turned = (Rotation.from_quat(pose["pose.orientation"]).inv() * phone).magnitude()
    np.testing.assert_allclose(turned, 0.0, atol=1e-9)
    assert {"/tf", "/tf_static"} <= set(reader.topics)
    assert reader.custom_data("pdr.source") == str(folder)
    assert reader.custom_data("pdr.command")        # the command line (here pytest's)


def test_import_csv_writes_the_same_bag_from_the_two_files_joined(tmp_path):
    """The equivalent import-csv of docs/bags.md: the files joined row by row, with the
    time column made from the row and the two accelerations summed (what import-csv
    cannot do itself), then --quat-cols and --sensor-in-body-rpy-deg 0,0,180."""
    imu, vicon = written(write_sequence(tmp_path / "seq"))
    joined = np.column_stack([0.01 * np.arange(N), -(imu[:, 7:10] + imu[:, 10:13]),
                              imu[:, 4:7], imu[:, 13:16], vicon[:, 2:9]])
    np.savetxt(tmp_path / "joined.csv", joined, delimiter=",", fmt="%.17g")
    assert run(tmp_path / "seq", "--out", tmp_path / "oxiod").returncode == 0
    result = cli("pdr-sim", "import-csv", str(tmp_path / "joined.csv"), "--out",
                 str(tmp_path / "csv"), "--no-header", "--time-col", "0", "--acc-cols", "1,2,3",
                 "--acc-unit", "g", "--gyro-cols", "4,5,6", "--mag-cols", "7,8,9",
                 "--pos-cols", "10,11,12", "--quat-cols", "13,14,15,16",
                 "--sensor-in-body-rpy-deg", "0,0,180")
    assert result.returncode == 0, result.stderr
    assert "200 ground_truth/pose with attitude" in result.stdout
    oxiod, csv = BagReader(tmp_path / "oxiod"), BagReader(tmp_path / "csv")
    assert oxiod.topics == csv.topics
    for topic, field in (("/imu/data", "linear_acceleration"), ("/imu/data", "angular_velocity"),
                         ("/imu/mag", "magnetic_field"), ("/ground_truth/pose", "pose.position"),
                         ("/ground_truth/pose", "pose.orientation")):
        a, b = oxiod.read(topic), csv.read(topic)
        np.testing.assert_array_equal(a.stamp_ns, b.stamp_ns)
        np.testing.assert_allclose(a[field], b[field], rtol=1e-12, atol=1e-15, err_msg=topic)


def test_glitches_are_counted_and_kept(tmp_path):
    """A marker swap: the Vicon attitude turns 180° for rows 50-55 and back."""
    imu, vicon = sequence_tables()
    flipped = Rotation.from_quat(vicon[50:56, 5:9]) * Rotation.from_euler("x", np.pi)
    vicon[50:56, 5:9] = flipped.as_quat()
    vicon[80, 1] = vicon[79, 1]                       # a Vicon frame written twice
    result = run(write_sequence(tmp_path / "seq", imu=imu, vicon=vicon), "--out", tmp_path / "bag")
    assert result.returncode == 0, result.stderr
    assert "2 truth glitches (attitude jumps > 0.5 rad between rows, kept); 1 rows repeat " \
           "the previous Vicon frame; 200 rows read, 0 invalid rows dropped" in result.stdout
    assert len(BagReader(tmp_path / "bag").read("/ground_truth/pose")) == N


def test_a_file_of_a_folder_of_several_pairs_names_its_pair(tmp_path):
    write_sequence(tmp_path / "syn", k=1)
    write_sequence(tmp_path / "syn", k=2)
    result = run(tmp_path / "syn" / "vi2.csv", "--out", tmp_path / "bag")
    assert result.returncode == 0, result.stderr
    assert "(imu2.csv + vi2.csv)" in result.stdout


def nan_row(imu, vicon):
    imu[7, 9] = np.nan
    return imu, vicon


def lost_tracking(imu, vicon):
    vicon[7, 5:9] = 0.0
    return imu, vicon


def refused(tmp_path, *args):
    result = run(*args, "--out", tmp_path / "bag")
    assert result.returncode == 2, result.stdout + result.stderr
    [line] = result.stderr.splitlines()
    assert not (tmp_path / "bag").exists()
    return line.removeprefix("pdr-sim: error: ")


@pytest.mark.parametrize("spoil, file, problem", [
    (nan_row, "imu3.csv", "row 8, column 9: empty or NaN (1 such rows; --drop-invalid drops "
                          "them)"),
    (lost_tracking, "vi3.csv", "row 8: quaternion norm 0, not 1 (±0.01) (1 such rows; "
                               "--drop-invalid drops them)"),
    (lambda imu, vicon: (imu, vicon[:-1]), "vi3.csv",
     "199 rows, but imu3.csv has 200: row k of both must be one instant (OxIOD's syn/ "
     "files, not raw/)"),
    (lambda imu, vicon: (imu[:, :15], vicon), "imu3.csv",
     "15 columns, expected 16 (time, attitude roll/pitch/yaw, rotation rate x/y/z, gravity "
     "x/y/z, user acceleration x/y/z, magnetic field x/y/z)"),
    (lambda imu, vicon: (imu, vicon[:, :8]), "vi3.csv",
     "8 columns, expected 9 (time, frame counter, translation x/y/z, rotation x/y/z/w)"),
])
def test_bad_rows_and_files_are_refused_naming_the_file(tmp_path, spoil, file, problem):
    folder = write_sequence(tmp_path / "seq", 3, *spoil(*sequence_tables()))
    assert refused(tmp_path, folder) == f"{folder / file}: {problem}"


@pytest.mark.parametrize("spoil", [nan_row, lost_tracking])
def test_drop_invalid_drops_the_row_of_both_files_and_keeps_the_stamps(tmp_path, spoil):
    folder = write_sequence(tmp_path / "seq", 3, *spoil(*sequence_tables()))
    result = run(folder, "--out", tmp_path / "bag", "--drop-invalid")
    assert result.returncode == 0, result.stderr
    assert "200 rows read, 1 invalid rows dropped" in result.stdout
    reader = BagReader(tmp_path / "bag")
    for topic in ("/imu/data", "/imu/mag", "/ground_truth/pose"):
        np.testing.assert_array_equal(reader.read(topic).stamp_ns,
                                      10_000_000 * np.delete(np.arange(N), 7))


def test_a_ragged_row_is_refused_with_its_row(tmp_path):
    folder = write_sequence(tmp_path / "seq")
    lines = (folder / "imu3.csv").read_text().splitlines()
    lines[4] = lines[4].rsplit(",", 1)[0]
    (folder / "imu3.csv").write_text("\n".join(lines) + "\n")
    line = refused(tmp_path, folder)
    assert line == f"{folder / 'imu3.csv'}: row 5: 15 cells, but the first data row has 16"


def test_folders_without_exactly_one_pair_are_refused(tmp_path):
    empty = tmp_path / "empty"
    (empty / "syn").mkdir(parents=True)
    assert refused(tmp_path, empty) == (
        f"{empty}: no OxIOD pair imuK.csv + viK.csv of the same K (found no imu*.csv or "
        "vi*.csv); the synchronised files are in its syn/ folder")
    odd = write_sequence(tmp_path / "odd", k=3)
    (odd / "vi3.csv").rename(odd / "vi4.csv")
    assert refused(tmp_path, odd) == (
        f"{odd}: no OxIOD pair imuK.csv + viK.csv of the same K (found imu3.csv, vi4.csv)")
    both = write_sequence(write_sequence(tmp_path / "both", k=1), k=2)
    assert refused(tmp_path, both) == (
        f"{both}: 2 OxIOD pairs (imu1.csv/vi1.csv, imu2.csv/vi2.csv): name one of the files, "
        f"e.g. {both / 'imu1.csv'}")
    assert refused(tmp_path, odd / "imu3.csv") == (
        f"{odd / 'vi3.csv'}: no such file (the partner of imu3.csv)")
    assert refused(tmp_path, tmp_path / "none") == f"{tmp_path / 'none'}: no such directory"


def test_magnetometer_columns_of_one_value_are_no_magnetometer(tmp_path):
    imu, vicon = sequence_tables()
    imu[:, 13:16] = 0.0
    result = run(write_sequence(tmp_path / "seq", imu=imu, vicon=vicon), "--out", tmp_path / "bag")
    assert result.returncode == 0, result.stderr
    assert "magnetometer: none (constant columns)" in result.stdout
    assert "/imu/mag" not in BagReader(tmp_path / "bag").topics
