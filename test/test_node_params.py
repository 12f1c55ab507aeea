"""The nodes as an integrator starts them (issue 29): a parameter file that is no ROS
parameter file, an integer for a double, a choice outside its values and a removed name
each answer in one line with exit status 2, never a traceback; the shipped parameter
files start their nodes; the start-up line names the resolved topics and services; the
magnetometer's pause and resume are said once each, on the remapped topic, and nothing
is said of it when no magnetic update is configured."""
from __future__ import annotations

import signal

import numpy as np
import pytest

from pdr_core.io.bag import BagReader, write_batches
from wstest import ROOT, log_text, wait_for_log

pytestmark = pytest.mark.ros
POCKET_CONFIG = ROOT / "src" / "pdr_pocket" / "config"
BAG = ROOT / "bags" / "pocket_walk"


def refused(procs, *args: str) -> str:
    """Run a node that must refuse its parameters: exit 2, one line on its output."""
    result = procs.run(*args, timeout=60)
    assert result.returncode == 2, result.stdout + result.stderr
    output = (result.stdout + result.stderr).strip()
    assert "Traceback" not in output, output
    lines = [line for line in output.splitlines() if not line.startswith("[bootstrap]")]
    assert len(lines) == 1, output
    return lines[0]


@pytest.mark.parametrize("node", ["pocket_pdr", "landmark_drift", "zupt_ekf", "bag_play",
                                  "bag_record"])
def test_a_navigator_configuration_as_params_file_is_refused_in_one_line(procs, node):
    line = refused(procs, node, "--ros-args", "--params-file",
                   str(POCKET_CONFIG / "pocket_pdr.yaml"))
    assert line.startswith(f"{node}: error: --params-file ") and "pocket_pdr.yaml" in line
    assert "not a ROS parameter file" in line and "-p config:=" in line


@pytest.mark.parametrize(("node", "params_file"), [
    ("pocket_pdr", POCKET_CONFIG / "pocket_pdr_params.yaml"),
    ("stride_calibrator", POCKET_CONFIG / "stride_calibrator_params.yaml"),
    ("landmark_drift", ROOT / "src" / "pdr_drift" / "config" / "landmark_drift_params.yaml"),
    ("zupt_ekf", ROOT / "src" / "pdr_ins_ekf" / "config" / "zupt_ekf.yaml")])
def test_the_shipped_parameter_files_start_their_nodes(procs, node, params_file):
    proc = procs.start(node, "--ros-args", "--params-file", str(params_file), name=node)
    wait_for_log(proc, "configuration")
    assert procs.stop(proc, signal.SIGINT) == 0, log_text(proc)


def test_an_integer_for_a_double_is_taken(procs, ros):
    """``-p mag_wait_s:=2`` and ``-p wait_timeout_s:=10`` (bag_play) start, as 2.0 and
    10.0 (rclpy alone refuses them with a 20-line InvalidParameterTypeException)."""
    from rcl_interfaces.srv import GetParameters

    proc = procs.start("pocket_pdr", "--ros-args", "-p", "mag_wait_s:=2", name="pocket_pdr")
    wait_for_log(proc, "configuration")
    node, executor = ros
    client = node.create_client(GetParameters, "/pocket_pdr/get_parameters")
    assert client.wait_for_service(timeout_sec=30)
    future = client.call_async(GetParameters.Request(names=["mag_wait_s"]))
    executor.spin_until_future_complete(future, timeout_sec=30)
    assert future.result().values[0].double_value == 2.0
    assert procs.stop(proc, signal.SIGINT) == 0, log_text(proc)
    player = procs.run("bag_play", "--ros-args", "-p", f"bag:={BAG}", "-p",
                       "topics:=[/imu/data]", "-p", "wait_timeout_s:=1", "-p",
                       "wait_for_subscribers:=1", timeout=60)
    assert player.returncode == 1 and "Traceback" not in player.stderr, player.stderr


@pytest.mark.parametrize(("node", "args", "says"), [
    ("pocket_pdr", ["-p", "imu_durability:=reliable"],
     "parameter imu_durability: 'reliable' is not one of volatile, transient_local"),
    ("zupt_ekf", ["-p", "imu_durability:=transient-local"],
     "parameter imu_durability: 'transient-local' is not one of volatile, transient_local"),
    ("pocket_pdr", ["-p", "mag_wait_s:=soon"], "parameter mag_wait_s: 'soon' is not a number"),
    ("pocket_pdr", ["-p", "frame_id:=alice"],
     "parameter frame_id: is gone: use map_frame (steps, poses, path) or sensor_frame"),
    ("landmark_drift", ["-p", "frame_id:=alice"], "parameter frame_id: is gone: use map_frame"),
    ("zupt_ekf", ["-p", "frame_id:=alice"], "parameter frame_id: is gone: use map_frame"),
    ("imu_sim", ["-p", "imu:=xsens"], "parameter imu: 'xsens' is not one of ideal"),
    ("pocket_pdr", ["-p", "stairs.a_u_cm_per_deg:=-0.8"],
     "parameter stairs.a_u_cm_per_deg: a slope must be above 0, got -0.8"),
    ("pocket_pdr", ["-p", "step_length.b_h_m:=.nan"],
     "parameter step_length.b_h_m: nan is not finite"),
    ("pocket_pdr", ["-p", "step_calibration:=/nonexistent/fit.yaml"],
     "/nonexistent/fit.yaml: cannot read the saved fit"),
    ("stride_calibrator", ["-p", "forgetting:=1.5"],
     "parameter forgetting: forgetting must be within (0, 1], got 1.5"),
    ("stride_calibrator", ["-p", "every_pairs:=0"],
     "parameter every_pairs: must be at least 1, got 0")])
def test_a_wrong_parameter_is_refused_in_one_line(procs, node, args, says):
    line = refused(procs, node, "--ros-args", *args)
    assert line.startswith(f"{node}: error: {says}"), line


def test_the_start_up_line_names_the_resolved_topics_and_services(procs):
    proc = procs.start("pocket_pdr", "--ros-args", "-r", "__ns:=/alice", "-r",
                       "imu/mag:=sensors/mag", "-p", "map_frame:=alice_map", name="pocket_pdr")
    wait_for_log(proc, "configuration")
    line = next(x for x in log_text(proc).splitlines() if "configuration" in x)
    for text in ("map frame alice_map", "sensor frame imu_link",
                 "subscribes /alice/imu/data, /alice/imu/pressure, /alice/sensors/mag",
                 "/alice/pdr/pocket/attitude", "/alice/pdr/pocket/step",
                 "serves /alice/pdr/pocket/apply_correction, /alice/pocket_pdr/reset"):
        assert text in line, line
    assert procs.stop(proc, signal.SIGINT) == 0, log_text(proc)
    estimator = procs.start("landmark_drift", "--ros-args", "-r", "__ns:=/alice",
                            name="landmark_drift")
    wait_for_log(estimator, "calls /alice/pdr/pocket/apply_correction",
                 "subscribes /alice/pdr/pocket/pose, /alice/pdr/pocket/step")
    assert procs.stop(estimator, signal.SIGINT) == 0, log_text(estimator)


def mag_gap_bag(folder):
    """The first minute of the sample pocket walk, its magnetometer silent from 30 s to
    50 s (the rest of the walk would only be played through, 3 minutes of it)."""
    reader = BagReader(BAG)
    batches = reader.read_batches(["/imu/data", "/imu/mag"])
    start = batches["/imu/data"].stamp_ns[0]
    for topic, batch in batches.items():
        t = (batch.stamp_ns - start) * 1e-9
        keep = t <= 60.0
        if topic == "/imu/mag":
            keep &= (t < 30.0) | (t > 50.0)
        batches[topic] = batch.take(np.flatnonzero(keep))
    write_batches(folder / "gap", batches)
    return folder / "gap"


@pytest.mark.parametrize("config", ["pocket_pdr.yaml", "pocket_pdr_no_mag.yaml"])
def test_the_magnetometer_pausing_and_resuming_is_said_once_each(procs, tmp_path, config):
    """With magnetic updates: one warning when the remapped magnetometer goes quiet, one
    line when it comes back, and none at the start. Without them (pocket_pdr_no_mag.yaml):
    nothing about it."""
    bag = mag_gap_bag(tmp_path)
    ns = ["-r", "__ns:=/alice"]
    node = procs.start("pocket_pdr", "--ros-args", *ns, "-r", "imu/mag:=sensors/mag", "-p",
                       "imu_durability:=transient_local", "-p",
                       f"config:={POCKET_CONFIG / config}", name="pocket_pdr")
    wait_for_log(node, "configuration")
    played = procs.run("bag_play", "--ros-args", *ns, "-r", "imu/mag:=sensors/mag", "-p",
                       f"bag:={bag}", "-p", "topics:=[/imu/data, /imu/mag]", "-p",
                       "rate:=0.0", "-p", "wait_for_subscribers:=1", timeout=120)
    assert played.returncode == 0, played.stderr
    if config == "pocket_pdr.yaml":
        wait_for_log(node, "readings again, magnetic updates resumed")
    assert procs.stop(node, signal.SIGINT) == 0, log_text(node)
    log = log_text(node)
    paused = "/alice/sensors/mag: no reading for 1 s of IMU data, magnetic updates paused"
    if config == "pocket_pdr.yaml":
        assert log.count(paused) == 1 and log.count("magnetic updates resumed") == 1, log
        assert "/alice/sensors/mag: magnetic updates" in log       # the start-up line
    else:
        assert "paused" not in log and "resumed" not in log, log
        assert "the first reading's heading only" in log
