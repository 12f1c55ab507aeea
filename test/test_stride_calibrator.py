"""The live hand-over of issue 57: ``stride_calibrator`` and ``pocket_pdr`` as processes, a
walk's pocket steps and foot strides published on ``pdr/pocket/step`` and
``pdr/foot/step`` (level walking, the foot's stride a line of the pocket's pitch swing
plus noise, 80 steps of which about 65 pair). The node's last ``pdr/pocket/stride_lines``
holds the fit ``calibrated()`` gives offline on the same messages (to 1e-9), pocket_pdr's
parameters then hold the fitted level line and its log says it took them, and the fit
saved at shutdown (``save_to``) is the same. A NaN stride and one stamped back are
dropped and counted, and change nothing. A saved fit given to pocket_pdr
(``step_calibration``) gives its line parameters from the start."""
from __future__ import annotations

import signal
import time

import numpy as np
import pytest

from pdr_core import topics
from pdr_core.io import cdr
from pdr_core.io.batch import MessageBatch
from pdr_core.io.msgtypes import STEP
from pdr_core.vocabulary import Activity
from pdr_pocket.config import load_pocket_config
from pdr_pocket.line_calibration import (
    LEVEL,
    CalibrationSettings,
    StrideCalibrator,
    calibrated,
)
from pdr_pocket.saved_lines import read_fit
from wstest import log_text, wait_for_log

pytestmark = pytest.mark.ros
STEPS = 80
CYCLE_S = 1.1                   # one gait cycle [s]
LAG = 0.14                      # the footfall after the pitch maximum [cycles]
SLOPE, OFFSET = 0.021, 0.47     # the person's level line: s = a·Δθ [deg] + b [m]
T0_NS = 1_700_000_000_000_000_000


def walk(seed: int = 5) -> tuple[MessageBatch, MessageBatch]:
    """The pocket's steps and the foot's strides of a level walk at one cadence, the swing
    Δθ between 35° and 55°, the stride the person's line plus 1 cm noise."""
    rng = np.random.default_rng(seed)
    amplitude_deg = rng.uniform(35.0, 55.0, STEPS)
    stamps = T0_NS + np.round(np.arange(STEPS) * CYCLE_S * 1e9).astype(np.int64)
    zeros, ones = np.zeros(STEPS), np.ones(STEPS)
    common = {"index": np.arange(STEPS, dtype=np.uint32), "vertical_displacement": zeros,
              "heading": 0.3 * ones, "duration": CYCLE_S * ones,
              "activity": np.full(STEPS, Activity.WALKING, np.uint8),
              "ride": np.zeros(STEPS, np.uint8), "ride_height": zeros}
    swing = np.radians(amplitude_deg)
    pocket = MessageBatch(STEP, stamps, "map", {
        **common, "length": 0.42 + 0.025 * amplitude_deg, "pitch_max": 0.6 * swing,
        "pitch_min": -0.4 * swing, "pitch_amplitude": swing})
    foot = MessageBatch(STEP, stamps + round(LAG * CYCLE_S * 1e9), "map", {
        **common, "length": SLOPE * amplitude_deg + OFFSET + rng.normal(0.0, 0.01, STEPS),
        "pitch_max": zeros, "pitch_min": zeros, "pitch_amplitude": zeros})
    return pocket, foot


def offline(pocket: MessageBatch, foot: MessageBatch) -> StrideCalibrator:
    """``calibrated()`` with the node's priors: the shipped configuration's lines."""
    config = load_pocket_config()
    return calibrated(pocket, foot, StrideCalibrator(
        config.step_length, config.stairs,
        CalibrationSettings(height_m=config.person.height_m)))


def spin_until(executor, done, timeout_s: float, what: str) -> None:
    deadline = time.monotonic() + timeout_s
    while not done():
        assert time.monotonic() < deadline, what
        executor.spin_once(timeout_sec=0.05)


def parameter(node, executor, name: str) -> float:
    """``ros2 param get /pocket_pdr NAME``, through the standard service."""
    from rcl_interfaces.srv import GetParameters

    client = node.create_client(GetParameters, "/pocket_pdr/get_parameters")
    assert client.wait_for_service(timeout_sec=30)
    future = client.call_async(GetParameters.Request(names=[name]))
    executor.spin_until_future_complete(future, timeout_sec=30)
    node.destroy_client(client)
    return future.result().values[0].double_value


def test_the_lines_go_live_to_pocket_pdr(procs, ros, tmp_path):
    from rclpy.duration import Duration
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

    from pdr_msgs.msg import Step, StrideLines

    saved = tmp_path / "fit.yaml"
    navigator = procs.start("pocket_pdr", "--ros-args", name="pocket_pdr")
    calibrator = procs.start("stride_calibrator", "--ros-args", "-p", f"save_to:={saved}",
                             name="stride_calibrator")
    node, executor = ros
    qos = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
    received: list = []
    node.create_subscription(StrideLines, topics.graph_name(topics.POCKET_STRIDE_LINES),
                             received.append, qos)
    pocket, foot = walk()
    expected = offline(pocket, foot).fits[LEVEL]
    assert 60 <= expected.pairs < STEPS
    # the foot's strides first, then the pocket's, with garbage among them: a NaN stride
    # and one stamped back (dropped and counted)
    bad = foot.take(np.array([3, 3]))
    bad["length"][0] = np.nan
    bad.stamp_ns[1] = T0_NS
    raws = {"foot": [*cdr.encode(foot.take(slice(0, 4))), *cdr.encode(bad),
                     *cdr.encode(foot.take(slice(4, None)))], "pocket": cdr.encode(pocket)}
    publishers = {name: node.create_publisher(Step, topics.graph_name(topic), qos)
                  for name, topic in (("foot", topics.FOOT_STEP),
                                      ("pocket", topics.POCKET_STEP))}
    wait_for_log(calibrator, "configuration")
    spin_until(executor, lambda: all(p.get_subscription_count() for p in publishers.values()),
               30, "stride_calibrator subscribes")
    for name in ("foot", "pocket"):
        for raw in raws[name]:
            publishers[name].publish(raw)
        assert publishers[name].wait_for_all_acked(Duration(seconds=10))
    spin_until(executor, lambda: received and received[-1].level_pairs == expected.pairs, 30,
               f"the last lines: {received[-1:]}")
    last = received[-1]
    assert last.level_slope == pytest.approx(expected.slope, rel=0, abs=1e-9)
    assert last.level_offset == pytest.approx(expected.offset, rel=0, abs=1e-9)
    np.testing.assert_allclose(last.level_covariance, expected.covariance.ravel(), rtol=1e-9)
    assert last.up_pairs == last.down_pairs == 0 and last.refused_reasons[0] == "lag"
    assert abs(last.level_slope - SLOPE) < 0.003 and abs(last.level_offset - OFFSET) < 0.12
    # the hand-over: pocket_pdr's parameter holds the fitted offset, and its log says so
    wait_for_log(navigator, "took the person's lines from a parameter update", timeout=30)
    deadline = time.monotonic() + 30
    while parameter(node, executor, "step_length.b_h_m") != last.level_offset:
        assert time.monotonic() < deadline, log_text(navigator) + log_text(calibrator)
        time.sleep(0.1)
    assert parameter(node, executor, "step_length.a_h_m_per_deg") == last.level_slope
    assert parameter(node, executor, "stairs.b_u_cm") == load_pocket_config().stairs.b_u_cm
    assert f"{last.level_offset:.4g} m" in log_text(navigator)
    assert procs.stop(calibrator, signal.SIGINT) == 0, log_text(calibrator)
    log = log_text(calibrator)
    assert "1 messages with non_finite dropped" in log, log
    assert "1 messages with stamp_not_increasing dropped" in log, log
    fit = read_fit(saved).lines[LEVEL]
    assert (fit.slope, fit.offset, fit.fit.pairs) == (last.level_slope, last.level_offset,
                                                      last.level_pairs)
    assert procs.stop(navigator, signal.SIGINT) == 0, log_text(navigator)


def test_a_saved_fit_starts_pocket_pdr_with_the_person_s_lines(procs, ros, tmp_path):
    """``-p step_calibration:=FILE``: the walked lines of the saved fit are the line
    parameters' values from the start (a line not walked keeps the configuration's), and
    the start says so."""
    from pdr_pocket.saved_lines import saved_fit, write_fit

    fit = write_fit(tmp_path / "fit.yaml", saved_fit(offline(*walk())))
    navigator = procs.start("pocket_pdr", "--ros-args", "-p", f"step_calibration:={fit}",
                            name="pocket_pdr")
    wait_for_log(navigator, f"took the person's lines from {fit}")
    node, executor = ros
    level = read_fit(fit).lines[LEVEL]
    assert parameter(node, executor, "step_length.b_h_m") == level.offset
    assert parameter(node, executor, "step_length.a_h_m_per_deg") == level.slope
    assert parameter(node, executor, "stairs.b_d_cm") == load_pocket_config().stairs.b_d_cm
    assert procs.stop(navigator, signal.SIGINT) == 0, log_text(navigator)
