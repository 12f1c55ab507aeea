"""The navigators' health on ``/diagnostics``, read live (issue 42, acceptance 2): a real
``pocket_pdr`` (and ``zupt_ekf``) fed IMU samples from this process at 100 Hz, one of them
poisoned (NaN), and a correction refused (a negative variance). An
rclpy subscriber reads ``/diagnostics``: the node's status goes WARN naming the counter
and how many, and back to OK after a clean report period (pdr_core.ros.diagnostics). The
pocket node's key-values name the inputs fused (issue 54): the barometer absent, then, once
``imu/pressure`` comes at 1 Hz, waiting for a step (a person at rest takes none), its
offset jumps, and the magnetometer fused."""
from __future__ import annotations

import math
import signal
import time

import numpy as np
import pytest

from pdr_core import topics
from pdr_core.frames import SENSOR_FRAME
from pdr_core.ros.diagnostics import Level
from pdr_core.topics import DIAGNOSTICS as DIAGNOSTICS_TOPIC
from wstest import log_text, wait_for_log

pytestmark = pytest.mark.ros
RATE_HZ = 100.0
FIRST_STAMP_NS = 1_700_000_000_000_000_000
FIELD_T = (20e-6, 0.0, -40e-6)      # the Earth's field in the sensor frame [T]
REPORT_WAIT_S = 5.0                 # a report comes every second; this is ample
START_WAIT_S = 30.0                 # the first clean report, the node's kernels loaded


class Feed:
    """A sensor at rest published from the test's node: ``imu/data`` (and ``imu/mag``) at
    :data:`RATE_HZ` of wall-clock time, stamped 1/RATE_HZ apart from
    :data:`FIRST_STAMP_NS` however late the test's loop runs (no gap in the stamps), and
    the statuses named ``name`` read from ``/diagnostics``."""

    def __init__(self, ros, name: str, mag: bool) -> None:
        from diagnostic_msgs.msg import DiagnosticArray
        from rclpy.qos import QoSProfile, ReliabilityPolicy
        from sensor_msgs.msg import FluidPressure, Imu, MagneticField

        self.node, self.executor = ros
        qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
        self.imu_pub = self.node.create_publisher(Imu, topics.graph_name(topics.IMU_DATA), qos)
        self.mag_pub = self.node.create_publisher(
            MagneticField, topics.graph_name(topics.IMU_MAG), qos) if mag else None
        self.pressure_pub = self.node.create_publisher(
            FluidPressure, topics.graph_name(topics.IMU_PRESSURE), qos)
        self.pressure = False       # imu/pressure at 1 Hz with the IMU's stamps
        self.statuses: list = []        # (the array's stamp [ns], the status)
        self.node.create_subscription(DiagnosticArray, DIAGNOSTICS_TOPIC, lambda array: (
            self.statuses.extend((array.header.stamp.sec * 1_000_000_000
                                  + array.header.stamp.nanosec, s)
                                 for s in array.status if s.name == name)), 10)
        self.rng = np.random.default_rng(0)
        self.sent = 0
        self.start = time.monotonic()
        self.poison_next = False

    def wait_for_node(self, proc) -> None:
        deadline = time.monotonic() + 30
        while self.imu_pub.get_subscription_count() < 1:
            assert time.monotonic() < deadline and proc.poll() is None, log_text(proc)
            self.executor.spin_once(timeout_sec=0.05)
        self.start = time.monotonic()

    def publish_due(self) -> None:
        """The samples due by now (at most a second's worth at once)."""
        from sensor_msgs.msg import FluidPressure, Imu, MagneticField

        due = int((time.monotonic() - self.start) * RATE_HZ) - self.sent
        for _ in range(min(due, int(RATE_HZ))):
            stamp_ns = FIRST_STAMP_NS + round(self.sent * 1e9 / RATE_HZ)
            imu = Imu()
            imu.header.stamp.sec, imu.header.stamp.nanosec = divmod(stamp_ns, 1_000_000_000)
            imu.header.frame_id = SENSOR_FRAME
            f = self.rng.normal(0.0, 0.01, 3) + [0.0, 0.0, 9.81]
            w = self.rng.normal(0.0, 0.001, 3)
            if self.poison_next:
                f[0], self.poison_next = math.nan, False
            imu.linear_acceleration.x, imu.linear_acceleration.y, \
                imu.linear_acceleration.z = map(float, f)
            imu.angular_velocity.x, imu.angular_velocity.y, imu.angular_velocity.z = \
                map(float, w)
            self.imu_pub.publish(imu)
            if self.mag_pub is not None:
                mag = MagneticField()
                mag.header = imu.header
                mag.magnetic_field.x, mag.magnetic_field.y, mag.magnetic_field.z = FIELD_T
                self.mag_pub.publish(mag)
            if self.pressure and self.sent % int(RATE_HZ) == 0:
                self.pressure_pub.publish(FluidPressure(header=imu.header,
                                                        fluid_pressure=101_325.0))
            self.sent += 1

    def spin(self) -> None:
        self.publish_due()
        self.executor.spin_once(timeout_sec=0.02)

    def next_status(self, level: Level, proc, text: str, wait_s: float = REPORT_WAIT_S):
        """The first status from now on at ``level`` whose message holds ``text``, fed
        meanwhile, and its array's stamp [ns]; within ``wait_s`` [s]."""
        seen = len(self.statuses)
        deadline = time.monotonic() + wait_s
        while time.monotonic() < deadline:
            self.spin()
            for stamp_ns, status in self.statuses[seen:]:
                if status.level == bytes([level]) and text in status.message:
                    return status, stamp_ns
        got = [(s.level, s.message) for _, s in self.statuses[seen:]]
        raise AssertionError(f"no {level.name} status with {text!r} within {wait_s} s; "
                             f"got {got}\n{log_text(proc)}")

    def call(self, client, request):
        """A service call, fed while it is answered."""
        assert client.wait_for_service(timeout_sec=30)
        future = client.call_async(request)
        deadline = time.monotonic() + 30
        while not future.done() and time.monotonic() < deadline:
            self.spin()
        return future.result()


def values(status) -> dict[str, str]:
    return {kv.key: kv.value for kv in status.values}


def test_pocket_pdr_goes_warn_on_a_poisoned_sample_and_a_refused_correction(procs, ros):
    """WARN naming ``non_finite +1``, OK, WARN naming ``corrections_refused +1``, OK; the
    key-values carry the counts, the arrival rate and the IMU's frame as hardware id, and
    the array is stamped with the node's clock."""
    from pdr_msgs.srv import ApplyCorrection

    proc = procs.start("pocket_pdr", name="pocket_pdr")
    feed = Feed(ros, "pocket_pdr: navigator", mag=True)
    wait_for_log(proc, "configuration")
    started = next(x for x in log_text(proc).splitlines() if "configuration" in x)
    assert DIAGNOSTICS_TOPIC in started.split("publishes")[1].split(";")[0], started
    feed.wait_for_node(proc)
    clean, stamp_ns = feed.next_status(Level.OK, proc, "navigating", START_WAIT_S)
    assert abs(stamp_ns * 1e-9 - time.time()) < 60      # the node's clock: ROS time
    assert clean.hardware_id == SENSOR_FRAME
    assert values(clean)["navigating"] == "true" and values(clean)["mag_paused"] == "false"
    assert values(clean)["barometer"] == f"absent: no {topics.IMU_PRESSURE} reading"
    assert values(clean)["barometer_offset_jumps"] == "0"
    assert values(clean)["magnetometer"] == "fused"
    assert values(clean)["barometer_distrusted"] == "false"

    feed.poison_next = True
    warned, _ = feed.next_status(Level.WARN, proc, "non_finite +1 since the last report")
    assert values(warned)["non_finite"] == "1", values(warned)
    feed.next_status(Level.OK, proc, "navigating")

    client = ros[0].create_client(ApplyCorrection,
                                  topics.graph_name(topics.POCKET_APPLY_CORRECTION))
    response = feed.call(client, ApplyCorrection.Request(yaw=0.01, yaw_variance=-1.0))
    assert response is not None and not response.accepted, log_text(proc)
    warned, _ = feed.next_status(Level.WARN, proc, "corrections_refused +1 since the last "
                                 "report")
    assert values(warned)["corrections_refused"] == "1"
    assert values(warned)["non_finite"] == "1"
    feed.pressure = True
    back, _ = feed.next_status(Level.OK, proc, "navigating")
    for _ in range(3):          # the report before the first reading came may say absent
        if not values(back)["barometer"].startswith("absent"):
            break
        back, _ = feed.next_status(Level.OK, proc, "navigating")
    assert values(back)["barometer"] == "not fused: its readings wait for the first step " \
        "(the height is fused at each step)", values(back)
    assert int(values(back)["samples_in"]) > int(values(clean)["samples_in"])
    # a whole period fed at 100 Hz (the loop catches up when it runs late)
    assert 30.0 < float(values(back)["input_rate_hz"]) < 300.0, values(back)
    assert procs.stop(proc, signal.SIGINT) == 0, log_text(proc)


def test_zupt_ekf_goes_warn_on_a_poisoned_sample_and_a_refused_correction(procs, ros):
    """The same for the foot navigator: a poisoned sample, then a correction refused on
    ``pdr/foot/apply_correction`` (issue 44), each a WARN and back to OK. The correction
    sent again with its request_id gets the first answer and is counted once, as resent
    (issue 55)."""
    from pdr_msgs.srv import ApplyCorrection

    proc = procs.start("zupt_ekf", name="zupt_ekf")
    feed = Feed(ros, "zupt_ekf: navigator", mag=False)
    wait_for_log(proc, "configuration")
    feed.wait_for_node(proc)
    clean, _ = feed.next_status(Level.OK, proc, "navigating", START_WAIT_S)
    assert clean.hardware_id == SENSOR_FRAME and values(clean)["gaps"] == "0"
    assert values(clean)["corrections_refused"] == values(clean)["corrections_accepted"] == "0"
    feed.poison_next = True
    warned, _ = feed.next_status(Level.WARN, proc, "non_finite +1 since the last report")
    assert values(warned)["non_finite"] == "1", values(warned)
    feed.next_status(Level.OK, proc, "navigating")
    client = ros[0].create_client(ApplyCorrection,
                                  topics.graph_name(topics.FOOT_APPLY_CORRECTION))
    request = ApplyCorrection.Request(yaw=0.01, yaw_variance=-1.0, request_id=55)
    response = feed.call(client, request)
    assert response is not None and not response.accepted, log_text(proc)
    assert response.message.startswith("nothing applied: "), response.message
    assert feed.call(client, request) == response
    warned, _ = feed.next_status(Level.WARN, proc, "corrections_refused +1 since the last "
                                 "report")
    assert values(warned)["corrections_refused"] == "1"
    clean, _ = feed.next_status(Level.OK, proc, "navigating")   # reported after both calls
    assert values(clean)["corrections_refused"] == values(clean)["corrections_resent"] == "1"
    assert procs.stop(proc, signal.SIGINT) == 0, log_text(proc)


def test_zupt_ekf_without_the_odometry_its_odom_frame_needs_goes_warn(procs, ros):
    """``odom_frame:=odom`` and no node publishing odom → base_link: the poses wait 10 s of
    pose time for it (pdr_core.ros.node_tf.ODOM_WAIT_S), then count as ``tf_no_odom`` and the
    status goes WARN naming it (docs/nodes.md, "TF and odometry")."""
    from diagnostic_msgs.msg import DiagnosticArray

    from wstest import ROOT

    statuses: list = []
    node, executor = ros
    node.create_subscription(DiagnosticArray, DIAGNOSTICS_TOPIC, lambda array: statuses.extend(
        s for s in array.status if s.name == "zupt_ekf: navigator"), 10)
    proc = procs.start("zupt_ekf", "--ros-args", "-p", "imu_durability:=transient_local",
                       "-p", "odom_frame:=odom", name="zupt_ekf")
    wait_for_log(proc, "/tf map -> odom from odom -> base_link")
    deadline = time.monotonic() + START_WAIT_S     # heard before the bag plays, so that the
    while not statuses and time.monotonic() < deadline:    # report of the rise is heard
        executor.spin_once(timeout_sec=0.1)
    assert statuses, log_text(proc)
    played = procs.run("bag_play", "--ros-args", "-p", f"bag:={ROOT / 'bags' / 'foot_walk'}",
                       "-p", "topics:=[/imu/data]", "-p", "rate:=0.0", "-p",
                       "wait_for_subscribers:=1")
    assert played.returncode == 0, played.stderr
    # 6,033 poses 10 ms apart: all but the 1,001 within 10 s of the last waited in vain
    expected = 6033 - 1001

    def counted() -> int:
        return max((int(values(s)["tf_no_odom"]) for s in statuses), default=0)

    deadline = time.monotonic() + 3 * REPORT_WAIT_S / 2   # the reports after the last pose
    while counted() < expected and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
    assert any(s.level == bytes([Level.WARN]) and "tf_no_odom +" in s.message
               for s in statuses), [(s.level, s.message) for s in statuses]
    assert counted() == expected
    assert procs.stop(proc, signal.SIGINT) == 0, log_text(proc)
