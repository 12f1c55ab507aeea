"""A second ROS process for the pdr_msgs tests.

    python pdr_msgs_peer.py publish   publish one sample of each pdr_msgs message, then exit
    python pdr_msgs_peer.py serve     serve pdr/pocket/apply_correction until SIGINT
    python pdr_msgs_peer.py serve-late  the same, each correction's first answer LATE_S late,
                                        a call sent again answered from memory
                                        (pdr_core.corrections.answered_requests)

The samples are defined here (:func:`samples`) and imported by the test to compare.
"""
from __future__ import annotations

import sys
import time

import rclpy
from geometry_msgs.msg import Point
from rclpy.duration import Duration
from rclpy.executors import ExternalShutdownException
from rclpy.qos import QoSProfile, ReliabilityPolicy

from pdr_core.corrections.answered_requests import AnsweredRequests
from pdr_msgs.msg import DriftEstimate, Landmark, Stance, Step, StrideLines
from pdr_msgs.srv import ApplyCorrection

QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
LATE_S = 2.0     # how late serve-late answers a correction first [s]


def samples() -> dict:
    """Topic -> message with every field set to a distinctive value."""
    stance = Stance(stationary=True, statistic=1.25e7, detector=Stance.DETECTOR_SHOE)
    stance.header.stamp.sec, stance.header.stamp.nanosec = 12, 345
    stance.header.frame_id = "imu_link"
    step = Step(index=7, length=0.71, vertical_displacement=0.17, heading=-1.2,
                pitch_max=0.5, pitch_min=-0.3, pitch_amplitude=0.8, duration=1.1,
                activity=Step.UPSTAIRS)
    step.header.frame_id = "map"
    landmark = Landmark(id=3, type=Landmark.STAIRS, position=Point(x=1.0, y=-2.0, z=3.0),
                        position_covariance=[float(i) for i in range(9)], yaw_before=0.1,
                        yaw_after=1.6, floor=-1)
    drift = DriftEstimate(landmark_first=3, landmark_revisit=9, deviation=0.05, elapsed=120.0,
                          drift=0.05 / 120.0, drift_variance=1e-9)
    lines = StrideLines(level_slope=0.0251, level_offset=0.371,
                        level_covariance=[1.1e-7, -3.6e-6, -3.6e-6, 1.3e-4], level_pairs=412,
                        level_residual_sigma=0.036, up_slope=0.81, up_offset=-8.9,
                        up_covariance=[0.004, -0.1, -0.1, 4.0], up_pairs=38,
                        up_residual_sigma=1.2, down_slope=2.0, down_offset=-19.24,
                        down_covariance=[0.04, 0.0, 0.0, 16.0], down_pairs=0,
                        down_residual_sigma=0.0, refused_reasons=["lag", "turn"],
                        refused_counts=[10, 31], forgetting=0.999)
    lines.header.frame_id = "map"
    return {"test/stance": stance, "test/step": step, "test/landmark": landmark,
            "test/drift": drift, "test/stride_lines": lines}


def publish() -> None:
    node = rclpy.create_node("pdr_msgs_publisher")
    pubs = {topic: (node.create_publisher(type(msg), topic, QOS), msg)
            for topic, msg in samples().items()}
    deadline = time.monotonic() + 30
    while any(p.get_subscription_count() == 0 for p, _ in pubs.values()):
        if time.monotonic() > deadline:
            sys.exit("no subscribers")
        time.sleep(0.01)
    for pub, msg in pubs.values():
        pub.publish(msg)
    for pub, _ in pubs.values():
        pub.wait_for_all_acked(Duration(seconds=10))


def serve() -> None:
    node = rclpy.create_node("apply_correction_server")

    def handle(request, response):
        response.accepted = request.yaw_variance > 0 and request.has_position
        response.message = (f"yaw {request.yaw:.3f} bias {request.gyro_bias_z:.2e} "
                            f"at {request.position.x:.1f},{request.position.y:.1f} "
                            f"cov {sum(request.position_covariance):.1f}")
        return response

    node.create_service(ApplyCorrection, "pdr/pocket/apply_correction", handle)
    print("serving", flush=True)
    rclpy.spin(node)


def serve_late() -> None:
    """Serve pdr/pocket/apply_correction as a navigator slower than its client's timeout:
    a correction is accepted :data:`LATE_S` after it comes, and a call with a request id
    answered before gets that answer at once. Prints ``request <id>`` for every call and
    ``applied <id>`` for every correction applied."""
    node = rclpy.create_node("late_apply_correction_server")
    answered = AnsweredRequests()

    def apply(request, response):
        time.sleep(LATE_S)
        print(f"applied {request.request_id}", flush=True)
        response.accepted, response.message = True, f"applied {request.request_id}"
        return response

    def handle(request, response):
        print(f"request {request.request_id}", flush=True)
        return answered.answer(request.request_id, lambda: apply(request, response))

    node.create_service(ApplyCorrection, "pdr/pocket/apply_correction", handle)
    print("serving", flush=True)
    rclpy.spin(node)


if __name__ == "__main__":
    rclpy.init()
    try:
        {"publish": publish, "serve": serve, "serve-late": serve_late}[sys.argv[1]]()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        rclpy.try_shutdown()
