"""The streaming navigator (the node's core): same numbers as offline, bad input handled."""
import numpy as np
import pytest

from pdr_core.io.bag import BagReader
from pdr_ins_ekf.config import RunConfig, run_config
from pdr_ins_ekf.offline import navigate
from pdr_ins_ekf.streaming import StreamingNavigator


@pytest.fixture(scope="module")
def imu(request):
    root = request.config.rootpath
    return BagReader(root / "bags" / "foot_walk").read("/imu/data")


def stream(navigator, imu, indices=None, block=1):
    """The positions estimated live, pushing ``block`` samples at a time."""
    indices = np.arange(len(imu)) if indices is None else np.asarray(indices)
    runs = [navigator.push_many(imu.stamp_ns[part], imu["linear_acceleration"][part],
                                imu["angular_velocity"][part])
            for part in np.array_split(indices, max(1, len(indices) // block))]
    runs.append(navigator.flush())
    return np.concatenate([run.output.position for run in runs])


@pytest.mark.parametrize("detector", ["retarded", "limited", "shoe", "adaptive_shoe"])
@pytest.mark.parametrize("block", [1, 37])
def test_stream_equals_offline(imu, detector, block):
    config = run_config({"detector": {"type": detector}})
    offline = navigate(imu, config)
    live = stream(StreamingNavigator(config), imu, block=block)
    np.testing.assert_array_equal(live, offline.output.position)


def test_stream_smoother_equals_offline_segments(imu):
    config = run_config({"smoother": {"mode": "segmented", "gamma_s_m2ps2": 3.0e-4},
                         "filter": {"acc_noise_mps2_per_sqrt_hz": 0.02,
                                    "gyro_noise_radps_per_sqrt_hz": 0.002}})
    offline = navigate(imu, config).smoothed
    navigator = StreamingNavigator(config)
    stream(navigator, imu, block=50)
    segments = navigator.take_smoothed()
    ends = np.cumsum([len(s.stamp_ns) for s in segments]) - 1
    np.testing.assert_array_equal(ends, offline.segment_ends)
    np.testing.assert_array_equal(np.concatenate([s.position for s in segments]),
                                  offline.position)
    assert navigator.take_smoothed() == []


def test_full_smoothing_is_refused_live():
    from pdr_core.errors import InputError
    with pytest.raises(InputError, match="full smoothing needs the whole record"):
        StreamingNavigator(run_config({"smoother": {"mode": "full"}}))


@pytest.mark.parametrize("block", [1, 16])
def test_bad_samples_are_dropped_and_counted(imu, block):
    navigator = StreamingNavigator(RunConfig())
    bad = imu.take(np.arange(len(imu)))  # a copy
    bad["linear_acceleration"][100] = np.nan
    out = stream(navigator, bad, list(range(500)) + [450, 499] + list(range(500, len(bad))),
                 block)
    assert navigator.counts == {"non_finite": 1, "implausible": 0, "stamp_not_increasing": 2,
                                "gaps": 0}
    assert len(out) == len(bad) - 1


def test_gap_is_counted_and_propagated(imu):
    navigator = StreamingNavigator(RunConfig())
    out = stream(navigator, imu, list(range(1000)) + list(range(1050, len(imu))))
    assert navigator.counts["gaps"] == 1 and len(out) == len(imu) - 50


def test_data_in_g_is_refused_at_alignment(imu):
    navigator = StreamingNavigator(run_config({"detector": {"type": "shoe"}}))
    scaled = imu.take(np.arange(len(imu)))
    scaled.fields["linear_acceleration"] = scaled["linear_acceleration"] / 9.80665
    assert len(stream(navigator, scaled)) == 0
    assert "the accelerometer looks like it is in g" in str(navigator.failed)
    navigator.reset()
    assert navigator.failed is None and len(stream(navigator, imu)) == len(imu)


def test_memory_stays_bounded(imu):
    navigator = StreamingNavigator(RunConfig())
    stream(navigator, imu)
    left, right = RunConfig().detector.context(navigator.rate_hz)
    assert len(navigator.stamps) <= left + right + 2


def test_configuration_values_are_typed():
    from pdr_core.errors import InputError
    config = run_config({"detector": {"type": "shoe", "threshold": "1.0e6",
                                      "window_samples": 7}})
    assert config.detector.threshold == 1.0e6 and config.detector.window_samples == 7
    with pytest.raises(InputError,
                       match=r"config.detector.window_samples: expected an integer"):
        run_config({"detector": {"type": "shoe", "window_samples": 2.5}})
    with pytest.raises(InputError, match=r"config.filter.acc_noise: unknown key \(renamed "
                                         r"to acc_noise_mps2_per_sqrt_hz\)"):
        run_config({"filter": {"acc_noise": 0.02}})
    with pytest.raises(InputError, match=r"config.detector.window: unknown key \(renamed "
                                         r"to window_samples\)"):
        run_config({"detector": {"type": "shoe", "window": 7}})
    with pytest.raises(InputError, match=r"config.filter.zaru: expected true or false"):
        run_config({"filter": {"zaru": "yes"}})
