"""A gravity-removed accelerometer (a phone app's linear or user acceleration) is told from
one in g (pdr_core.sensors.imu_checks.gravity_removed): import-csv says it looks gravity-removed,
with the figures and the remedy, and never proposes --acc-unit g for it."""
import numpy as np
import pytest

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError
from pdr_core.io.csv_import import CsvImuFormat, gravity_removed_problem, import_csv
from pdr_core.sensors.imu_checks import gravity_removed, slow_part_median_norm

RATE_HZ = 100.0
T_S = np.arange(2000) / RATE_HZ
FMT = CsvImuFormat(time_col="t", acc_cols=("ax", "ay", "az"))


def linear_acceleration(seed=0) -> np.ndarray:
    """(N, 3) [m/s²] of a 20 s walk without gravity: the vertical bounce at the step
    frequency (1.8 Hz), the fore-aft surge and the sway at half of it, noise; zero mean."""
    rng = np.random.default_rng(seed)
    step = 2 * np.pi * 1.8 * T_S
    acc = np.column_stack([1.0 * np.sin(step + 0.5), 0.6 * np.sin(step / 2), 2.5 * np.sin(step)])
    return acc + rng.normal(0.0, 0.3, acc.shape)


def write_log(path, acc):
    np.savetxt(path, np.column_stack([T_S, acc]), delimiter=",", header="t,ax,ay,az",
               comments="")
    return path


def test_the_statistic_tells_gravity_removed_data_from_data_in_g():
    walk = linear_acceleration()
    with_gravity_in_g = (walk + [0.0, 0.0, STANDARD_GRAVITY_MPS2]) / STANDARD_GRAVITY_MPS2
    assert gravity_removed(T_S, walk)
    assert not gravity_removed(T_S, with_gravity_in_g)
    assert not gravity_removed(T_S, with_gravity_in_g * STANDARD_GRAVITY_MPS2)
    # the slow part of data with gravity is about g in their unit
    assert slow_part_median_norm(T_S, with_gravity_in_g) == pytest.approx(1.0, abs=0.02)
    assert slow_part_median_norm(T_S, walk) < 0.15 * np.median(np.linalg.norm(walk, axis=1))
    assert not gravity_removed(T_S[:50], walk[:50])      # shorter than a window: no call


def test_import_refuses_gravity_removed_data_naming_the_figures_and_the_remedy(tmp_path):
    path = write_log(tmp_path / "linear.csv", linear_acceleration())
    with pytest.raises(InputError) as refused:
        import_csv(path, FMT)
    message = str(refused.value)
    assert message.startswith(f"{path}: columns ax,ay,az: median |f| 1.97 m/s² (0.2 g), and "
                              "the median norm of its slow part (1 s moving mean) 0.204 m/s², "
                              "0.10 times the median |f|")
    assert "the accelerometer looks gravity-removed" in message
    assert "the median norm of its slow part (1 s moving mean)" in message
    assert "add the gravity part to it (Sensor Logger's Gravity.csv: pdr-sim import-phone " \
           "DIR)" in message
    assert "--acc-unit" not in message and "look like g" not in message
    problem = gravity_removed_problem("ax,ay,az", T_S, linear_acceleration())
    assert problem is not None and f"{path}: {problem.what}: {problem.fix}" == message


def test_the_same_walk_with_gravity_in_g_gets_the_unit_hint(tmp_path):
    in_g = (linear_acceleration() + [0.0, 0.0, STANDARD_GRAVITY_MPS2]) / STANDARD_GRAVITY_MPS2
    path = write_log(tmp_path / "g.csv", in_g)
    with pytest.raises(InputError, match="the data look like g: pass --acc-unit g"):
        import_csv(path, FMT)
    assert gravity_removed_problem("ax,ay,az", T_S, in_g) is None
    imported = import_csv(path, CsvImuFormat(time_col="t", acc_cols=("ax", "ay", "az"),
                                             acc_unit="g"))
    assert len(imported.imu) == len(T_S)


def test_read_in_g_it_is_refused_as_gravity_removed_all_the_same(tmp_path):
    """The user's path: told "the data look like g", they passed --acc-unit g and the walk
    became a plausible 2-4 g one; the slow part's ratio holds in any unit."""
    path = write_log(tmp_path / "lin.csv", linear_acceleration())
    with pytest.raises(InputError, match="looks gravity-removed") as refused:
        import_csv(path, CsvImuFormat(time_col="t", acc_cols=("ax", "ay", "az"), acc_unit="g"))
    assert "--acc-unit" not in str(refused.value)
