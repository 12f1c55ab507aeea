"""CSV import of a truth attitude (issue 53): quaternion columns in either order, the sensor's
frame in the tracked body's, the world remap, and invalid quaternion rows."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from pdr_core.errors import InputError
from pdr_core.io.csv_import import CsvImuFormat, import_csv, sensor_attitude
from pdr_core.io.csv_rows import QUATERNION_NORM_TOLERANCE

N = 6
BODY = Rotation.random(N, rng=np.random.default_rng(53))   # C_world_body of each row


def write_log(path, quaternions, header="t,ax,ay,az,px,py,pz,q0,q1,q2,q3\n"):
    """A 100 Hz log at rest (f = [0, 0, 9.8] m/s²) walking along x, with the quaternion
    columns ``quaternions`` (N, 4) as given."""
    rows = [[0.01 * i, 0.0, 0.0, 9.8, 0.1 * i, 0.0, 0.0, *q] for i, q in enumerate(quaternions)]
    path.write_text(header + "".join(",".join(repr(float(v)) for v in row) + "\n"
                                     for row in rows))
    return path


def fmt(**changes) -> CsvImuFormat:
    base = {"time_col": "t", "acc_cols": ("ax", "ay", "az"), "pos_cols": ("px", "py", "pz"),
            "quat_cols": ("q0", "q1", "q2", "q3")}
    return CsvImuFormat(**(base | changes))


def same_attitude(quaternions, expected: Rotation) -> bool:
    return np.allclose((Rotation.from_quat(quaternions).inv() * expected).magnitude(), 0.0,
                       atol=1e-9)


@pytest.mark.parametrize("order, columns", [("xyzw", [0, 1, 2, 3]), ("wxyz", [3, 0, 1, 2])])
def test_the_quaternion_columns_in_either_order_give_the_body_attitude(tmp_path, order, columns):
    path = write_log(tmp_path / "log.csv", BODY.as_quat()[:, columns])
    pose = import_csv(path, fmt(quat_order=order)).pose
    assert same_attitude(pose["pose.orientation"], BODY)
    np.testing.assert_allclose(np.linalg.norm(pose["pose.orientation"], axis=1), 1.0)
    assert (pose["pose.orientation"][:, 3] >= 0).all()
    np.testing.assert_array_equal(pose["pose.position"][:, 0], 0.1 * np.arange(N))


def test_the_wrong_order_gives_another_attitude(tmp_path):
    path = write_log(tmp_path / "log.csv", BODY.as_quat())
    assert not same_attitude(import_csv(path, fmt(quat_order="wxyz")).pose["pose.orientation"],
                             BODY)


def test_a_quaternion_near_unit_norm_is_normalised(tmp_path):
    scale = 1 + QUATERNION_NORM_TOLERANCE / 2                    # a tracker's rounding
    path = write_log(tmp_path / "log.csv", BODY.as_quat() * scale)
    result = import_csv(path, fmt())
    assert result.rows_invalid == 0
    np.testing.assert_allclose(np.linalg.norm(result.pose["pose.orientation"], axis=1), 1.0)
    assert same_attitude(result.pose["pose.orientation"], BODY)


def test_the_sensor_in_the_body_frame_composes_on_the_right(tmp_path):
    """C_world_sensor = C_world_body · C_body_sensor, C_body_sensor = Rz(Y)·Ry(P)·Rx(R)."""
    rpy = (10.0, -20.0, 135.0)
    path = write_log(tmp_path / "log.csv", BODY.as_quat())
    pose = import_csv(path, fmt(sensor_in_body_rpy_deg=rpy)).pose
    sensor_in_body = Rotation.from_euler("ZYX", rpy[::-1], degrees=True)
    assert same_attitude(pose["pose.orientation"], BODY * sensor_in_body)
    assert not same_attitude(pose["pose.orientation"], sensor_in_body * BODY)


def test_a_known_case_by_hand():
    """A body facing north (yaw 90°) carrying a sensor turned 180° about z faces south, and
    the sensor's x axis then points along the world's −y."""
    north = Rotation.from_euler("z", 90, degrees=True).as_quat()[None]
    [q] = sensor_attitude(north, (0.0, 0.0, 180.0))
    np.testing.assert_allclose(Rotation.from_quat(q).apply([1.0, 0.0, 0.0]), [0, -1, 0],
                               atol=1e-12)


def test_a_remap_that_turns_the_world_turns_the_attitude_too(tmp_path):
    path = write_log(tmp_path / "log.csv", BODY.as_quat())
    pose = import_csv(path, fmt(pos_axes=("-x", "-y", "z"))).pose           # 180° about z
    assert same_attitude(pose["pose.orientation"],
                         Rotation.from_euler("z", 180, degrees=True) * BODY)
    np.testing.assert_array_equal(pose["pose.position"][:, 0], -0.1 * np.arange(N))
    ned = import_csv(path, fmt(pos_axes=("y", "x", "-z"))).pose             # NED -> ENU
    assert same_attitude(ned["pose.orientation"],
                         Rotation.from_matrix([[0, 1, 0], [1, 0, 0], [0, 0, -1]]) * BODY)


def test_a_mirroring_remap_is_refused_with_quaternions(tmp_path):
    path = write_log(tmp_path / "log.csv", BODY.as_quat())
    with pytest.raises(InputError, match=r"^--pos-axes: -x,y,z mirrors the truth's frame"):
        import_csv(path, fmt(pos_axes=("-x", "y", "z")))
    assert import_csv(path, fmt(pos_axes=("-x", "y", "z"), quat_cols=())).pose is not None


@pytest.mark.parametrize("bad, problem", [
    ([np.nan, 0.0, 0.0, 1.0], "column q0: empty or NaN, while other columns of the truth "
                              "(px,py,pz,q0,q1,q2,q3) hold values (a sensor not yet started, "
                              "or a value lost?)"),
    ([0.0, 0.0, 0.0, 0.0], "quaternion norm 0, not 1 (±0.01)"),       # tracking lost
    ([0.0, 0.0, 0.0, 1.5], "quaternion norm 1.5, not 1 (±0.01)"),
])
def test_an_invalid_quaternion_is_an_invalid_row(tmp_path, bad, problem):
    quaternions = BODY.as_quat()
    quaternions[3] = bad
    path = write_log(tmp_path / "log.csv", quaternions)
    with pytest.raises(InputError) as refused:
        import_csv(path, fmt())
    where = "row 5: " if problem.startswith("quaternion") else "row 5, "
    assert str(refused.value) == \
        f"{path}: {where}{problem} (1 such rows; --drop-invalid drops them)"
    result = import_csv(path, fmt(drop_invalid=True))
    assert result.rows_invalid == 1 and len(result.pose) == N - 1
    np.testing.assert_array_equal(result.pose.stamp_ns, np.delete(np.arange(N), 3) * 10_000_000)
    assert same_attitude(result.pose["pose.orientation"], BODY[[0, 1, 2, 4, 5]])


def test_columns_by_index_without_a_header(tmp_path):
    path = write_log(tmp_path / "log.csv", BODY.as_quat()[:, [3, 0, 1, 2]], header="")
    pose = import_csv(path, fmt(header=False, time_col="0", acc_cols=("1", "2", "3"),
                                pos_cols=("4", "5", "6"), quat_cols=("7", "8", "9", "10"),
                                quat_order="wxyz")).pose
    assert same_attitude(pose["pose.orientation"], BODY)


@pytest.mark.parametrize("changes, message", [
    ({"pos_cols": ()}, "--quat-cols: needs --pos-cols too"),
    ({"quat_cols": ("q0", "q1", "q2")},
     "--quat-cols: needs 4 columns (in --quat-order xyzw), got 3"),
    ({"quat_order": "zyxw"}, "--quat-order: unknown order 'zyxw' (choose from xyzw, wxyz)"),
    ({"quat_cols": (), "sensor_in_body_rpy_deg": (0.0, 0.0, 180.0)},
     "--sensor-in-body-rpy-deg: turns a truth attitude: give its --quat-cols too"),
    ({"sensor_in_body_rpy_deg": (0.0, 180.0)},
     "--sensor-in-body-rpy-deg: needs 3 angles (roll,pitch,yaw), got 2"),
])
def test_options_that_make_no_truth_are_refused_before_reading(tmp_path, changes, message):
    with pytest.raises(InputError) as refused:
        import_csv(tmp_path / "not_read.csv", fmt(**changes))
    assert str(refused.value).startswith(message)


def test_without_quaternions_the_orientation_stays_the_identity(tmp_path):
    path = write_log(tmp_path / "log.csv", BODY.as_quat())
    pose = import_csv(path, fmt(quat_cols=())).pose
    np.testing.assert_array_equal(pose["pose.orientation"], np.tile([0, 0, 0, 1.0], (N, 1)))
