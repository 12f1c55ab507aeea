"""The workspace's ``ros2`` (pdr_ros2, issue 58, acceptance 1 in part): ``pocket_pdr``
started with ``ros2 run`` on the sample bag (played by ``ros2 bag play``), its topics seen
with ``ros2 topic list -t`` and one odometry message with ``ros2 topic echo --once`` in
ros2cli's YAML (and CSV); ``topic hz`` of a second playback at real time, ``topic info
-v`` of the odometry, ``service list -t`` and ``service call`` of the correction service;
its parameters listed, read, set and dumped with ``ros2 param``, an output recorded by
``ros2 bag record``; the help says it is not ros2cli, and a real ``ros2`` earlier on the
PATH runs instead. One graph for the module (tests/conftest.py ``module_procs``): a node
start and a bag played once."""
from __future__ import annotations

import itertools
import os
import re
import select
import signal
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest
import yaml
from geometry_msgs.msg import Point

from pdr_core.io.bag import BagReader
from pdr_msgs.srv import ApplyCorrection
from wstest import ROOT, command, wait_for_log

pytestmark = pytest.mark.ros
BAG = ROOT / "bags" / "pocket_walk"
DISCOVERY_WAIT_S = 10.0     # a ros2 call retried until the graph shows what it asks
ODOMETRY_FIELDS = ["header", "child_frame_id", "pose", "twist"]
ODOMETRY_LEAVES = 3 + 1 + 7 + 36 + 6 + 36   # stamp, frame, child, pose, twist, covariances
HZ_NAMESPACE = "/hz"        # of the IMU played at real time for ros2 topic hz
HZ_WAIT_S = 25.0            # ros2 topic hz's third block: at most a playback's start and 3 s
HZ_BLOCKS = 3               # the block whose rate is checked: the start's transient is over
HZ_WINDOW = 50              # --window: the rate over the last second of a 50 Hz topic
HZ_BLOCK = re.compile(r"average rate: (\d+\.\d{3})\n\tmin: (\d+\.\d{3})s max: (\d+\.\d{3})s "
                      r"std dev: (\d+\.\d{5})s window: (\d+)")


@pytest.fixture(scope="module")
def pocket_graph(module_procs):
    """``ros2 run pdr_pocket pocket_pdr`` while ``ros2 bag play`` (pdr_sim's bag_play)
    feeds it the sample bag's IMU and magnetometer (as fast as it acknowledges; not
    waited for: an ``echo --once`` of a kept output waits for the first message). Its
    outputs are kept (transient local, depth 1000)."""
    node = module_procs.start("ros2", "run", "pdr_pocket", "pocket_pdr", "--ros-args", "-p",
                              "imu_durability:=transient_local", name="pocket_pdr")
    wait_for_log(node, "publishes")
    module_procs.start("ros2", "bag", "play", str(BAG), "--topics", "/imu/data", "/imu/mag",
                       "-r", "0", "--ros-args", "-p", "wait_for_subscribers:=1",
                       name="bag_play")
    return module_procs, node


def ros2_until(procs, shows, *args: str) -> subprocess.CompletedProcess:
    """``ros2 ARGS`` run again until its stdout ``shows`` what is asked (discovery is not
    instant); the last run."""
    deadline = time.monotonic() + DISCOVERY_WAIT_S
    while True:
        result = procs.run("ros2", *args, timeout=30)
        if shows(result.stdout) or time.monotonic() > deadline:
            return result


def test_ros2_run_execs_the_node_in_its_own_process(pocket_graph):
    """The process ``ros2 run`` started is the node (executed in place: a SIGINT to it
    reaches the node)."""
    procs, node = pocket_graph
    listed = ros2_until(procs, lambda out: "/pocket_pdr" in out, "node", "list")
    lines = listed.stdout.splitlines()
    assert "/pocket_pdr" in lines and lines == sorted(lines), listed.stderr
    executable = ROOT / "install" / "pdr_pocket" / "lib" / "pdr_pocket" / "pocket_pdr"
    assert str(executable) in Path(f"/proc/{node.pid}/cmdline").read_text().split("\0")


def test_topic_list_shows_the_nodes_topics_with_their_types(pocket_graph):
    procs, _ = pocket_graph
    want = ["/pdr/pocket/odometry [nav_msgs/msg/Odometry]",
            "/pdr/pocket/step [pdr_msgs/msg/Step]", "/imu/data [sensor_msgs/msg/Imu]",
            "/rosout [rcl_interfaces/msg/Log]"]
    assert_sorted_lines_include(procs, want, "topic", "list", "-t")


def assert_sorted_lines_include(procs, want: list[str], *args: str) -> None:
    """``ros2 ARGS`` (a list verb), run until it shows every line of ``want``, prints
    sorted lines that include them."""
    listed = ros2_until(procs, lambda out: all(w in out.splitlines() for w in want), *args)
    lines = listed.stdout.splitlines()
    assert set(want) <= set(lines) and lines == sorted(lines), listed.stdout


def test_echo_once_prints_one_odometry_message_as_ros2cli_yaml(pocket_graph):
    procs, _ = pocket_graph
    echoed = ros2_until(procs, bool, "topic", "echo", "--once", "/pdr/pocket/odometry")
    assert echoed.returncode == 0, echoed.stderr
    text = echoed.stdout
    assert text.endswith("\n---\n") and text.count("---\n") == 1, text
    message = yaml.safe_load(text.removesuffix("---\n"))
    assert list(message) == ODOMETRY_FIELDS
    assert message["header"]["frame_id"] == "map" and message["child_frame_id"] == "base_link"
    assert len(message["pose"]["covariance"]) == 36
    assert isinstance(message["pose"]["pose"]["position"]["x"], float)
    assert text.startswith("header:\n  stamp:\n    sec: ")
    assert "\n  covariance:\n  - " in text             # a list in a map is not indented


def test_echo_once_csv_is_one_line_of_every_leaf(pocket_graph):
    procs, _ = pocket_graph
    echoed = ros2_until(procs, bool, "topic", "echo", "--once", "--csv",
                        "/pdr/pocket/odometry")
    assert echoed.returncode == 0, echoed.stderr
    [line] = echoed.stdout.splitlines()
    values = line.split(",")
    assert len(values) == ODOMETRY_LEAVES and values[2:4] == ["map", "base_link"]


def test_echo_of_a_topic_the_graph_does_not_have_says_so(pocket_graph):
    procs, _ = pocket_graph
    echoed = procs.run("ros2", "topic", "echo", "--once", "/no/such/topic", timeout=30)
    assert echoed.returncode == 1
    assert echoed.stderr == "Could not determine the type for the passed topic\n"



def test_topic_hz_gives_the_rate_of_a_playback_at_real_time(pocket_graph):
    """``topic hz --window 50`` on a second playback of the bag's IMU, at real time, in a
    namespace of its own (apart from pocket_pdr's input): its third block, the last second,
    within 10 % of the bag's rate, every block in ros2cli's format; Ctrl-C ends it quietly.
    The two start at once: hz waits for the topic. Not the first block: a reader of
    ros2cli's ``sensor_data`` QoS (best effort, depth 5) that stalls at its start on a
    loaded machine loses messages (38 Hz seen once of 50 Hz beside a busy core)."""
    procs, _ = pocket_graph
    stamps = BagReader(BAG).read("/imu/data").stamp_ns
    bag_rate = 1e9 / np.mean(np.diff(stamps))
    player = procs.start("bag_play", "--ros-args", "-r", f"__ns:={HZ_NAMESPACE}", "-p",
                         f"bag:={BAG}", "-p", "topics:=[/imu/data]", "-p", "rate:=1.0",
                         name="bag_play_hz")
    topic = f"{HZ_NAMESPACE}/imu/data"
    hz = subprocess.Popen([command("ros2"), "topic", "hz", topic, "--window", str(HZ_WINDOW)],
                          env=procs.env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          text=True)
    blocks_seen = itertools.count(1)
    lines = lines_until(hz, lambda line: line.startswith("\tmin: ")
                        and next(blocks_seen) == HZ_BLOCKS, HZ_WAIT_S)
    procs.stop(player)
    stopped, said = procs.stop(hz), hz.stderr.read()
    assert (stopped, said) == (signal.SIGINT, ""), said
    before, printed = lines[:-2 * HZ_BLOCKS], lines[-2 * HZ_BLOCKS:]
    assert set(before) <= {f"WARNING: topic [{topic}] does not appear to be published yet"}
    blocks = [HZ_BLOCK.fullmatch("\n".join(printed[k:k + 2])) for k in range(0, len(printed), 2)]
    assert all(blocks), lines
    rate, shortest, longest, _, window = map(float, blocks[-1].groups())
    assert abs(rate - bag_rate) < 0.1 * bag_rate, (rate, bag_rate, lines)
    assert shortest <= round(1 / rate, 3) <= longest     # the mean, to the printed digits
    assert window == HZ_WINDOW


def lines_until(proc: subprocess.Popen, last, timeout: float) -> list[str]:
    """The lines ``proc`` prints up to the first for which ``last`` is true (without their
    newlines); AssertionError after ``timeout`` [s]."""
    deadline = time.monotonic() + timeout
    lines: list[str] = []
    while not (lines and last(lines[-1])):
        ready, _, _ = select.select([proc.stdout], [], [], max(0.0, deadline - time.monotonic()))
        assert ready, f"no line for {timeout} s; so far: {lines}"
        lines.append(proc.stdout.readline().removesuffix("\n"))
    return lines


def test_topic_info_verbose_shows_each_endpoint_of_the_odometry(pocket_graph):
    """``topic info -v``: each line followed by a blank one, the publisher's block (rclpy's
    TopicEndpointInfo) after its count, pocket_pdr's QoS (reliable, transient local)."""
    procs, _ = pocket_graph
    info = ros2_until(procs, lambda out: "Node name: pocket_pdr" in out, "topic", "info", "-v",
                      "/pdr/pocket/odometry")
    parts = info.stdout.split("\n\n")
    assert parts[:2] == ["Type: nav_msgs/msg/Odometry", "Publisher count: 1"], info.stdout
    publisher = parts[2].splitlines()
    assert publisher[:3] == ["Node name: pocket_pdr", "Node namespace: /",
                             "Topic type: nav_msgs/msg/Odometry"]
    assert publisher[3].startswith("Topic type hash: RIHS01_")
    assert publisher[4:5] == ["Endpoint type: PUBLISHER"] and publisher[5].startswith("GID: ")
    assert publisher[6:8] == ["QoS profile:", "  Reliability: RELIABLE"]
    assert "  Durability: TRANSIENT_LOCAL" in publisher
    assert parts[3].startswith("Subscription count: ")
    subscriptions, end = parts[4:-1], parts[-1]
    assert len(subscriptions) == int(parts[3].removeprefix("Subscription count: "))
    assert all("\nEndpoint type: SUBSCRIPTION\n" in p for p in subscriptions) and end == ""


def test_service_list_shows_the_correction_service_with_its_type(pocket_graph):
    procs, _ = pocket_graph
    want = ["/pdr/pocket/apply_correction [pdr_msgs/srv/ApplyCorrection]",
            "/pocket_pdr/reset [std_srvs/srv/Trigger]"]
    assert_sorted_lines_include(procs, want, "service", "list", "-t")


def test_service_call_prints_the_request_and_the_answer(pocket_graph):
    """A well-formed correction with no part: the request as filled from the YAML
    (nested, array), pocket_pdr's refusal as the response, each as its repr."""
    procs, _ = pocket_graph
    values = ("{stamp: {sec: 0}, request_id: 0, position: {x: 0.0},"
              " position_covariance: [0, 0, 0, 0, 0, 0, 0, 0, 0]}")
    called = procs.run("ros2", "service", "call", "/pdr/pocket/apply_correction",
                       "pdr_msgs/srv/ApplyCorrection", values, timeout=30)
    assert called.returncode == 0, called.stderr
    text = called.stdout.removeprefix("waiting for service to become available...\n")
    request = ApplyCorrection.Request(position=Point(x=0.0))
    assert text.startswith(f"requester: making request: {request!r}\n\nresponse:\n"
                           "pdr_msgs.srv.ApplyCorrection_Response(accepted=False, "
                           "message='nothing to apply"), text
    assert text.endswith(", revised_steps=[], revised_poses=[])\n\n")


@pytest.mark.parametrize(("service_type", "values", "error"), [
    ("pdr_msgs/srv/ApplyCorrection", "{yawn: 0.1}",
     "Failed to populate field: 'ApplyCorrection_Request' object has no attribute 'yawn'"),
    ("pdr_msgs/msg/Step", "{}", "The passed type is not a service"),
    ("no_such_pkg/srv/Call", "{}", "The passed service type is invalid"),
])
def test_service_call_of_a_bad_type_or_field_fails_with_ros2clis_words(service_type, values,
                                                                        error):
    """Before any node starts: no graph needed."""
    called = subprocess.run([command("ros2"), "service", "call", "/pdr/pocket/apply_correction",
                             service_type, values], capture_output=True, text=True, timeout=30)
    assert (called.returncode, called.stdout, called.stderr) == (1, "", error + "\n")


def test_help_names_the_verbs_and_says_it_is_not_ros2cli():
    result = subprocess.run([command("ros2"), "-h"], capture_output=True, text=True,
                            timeout=30, env={**os.environ, "PATH": "/usr/bin:/bin"})
    assert result.returncode == 0, result.stderr
    assert "NOT ros2cli" in result.stdout
    for verb in ("ros2 run PKG EXE", "ros2 node list", "ros2 topic list [-t]",
                 "ros2 topic echo TOPIC [--once] [--csv]", "ros2 topic hz TOPIC [--window N]",
                 "ros2 topic info TOPIC [-v]", "ros2 service list [-t]",
                 "ros2 service call SERVICE TYPE [VALUES]",
                 "ros2 launch PKG FILE [name:=value ...]",
                 "ros2 param list [NODE] [--param-type]", "ros2 param get NODE PARAM",
                 "ros2 param set NODE PARAM VALUE", "ros2 param dump NODE",
                 "ros2 bag info BAG", "ros2 bag play BAG [--topics T ...] [-r RATE] [--clock]",
                 "ros2 bag record [-o OUT] TOPIC ..."):
        assert verb in result.stdout


def test_run_of_a_missing_package_or_executable_fails_with_ros2runs_words():
    missing_package = subprocess.run([command("ros2"), "run", "no_such_pkg", "x"],
                                     capture_output=True, text=True, timeout=30)
    missing_exe = subprocess.run([command("ros2"), "run", "pdr_pocket", "no_such_exe"],
                                 capture_output=True, text=True, timeout=30)
    assert (missing_package.returncode, missing_package.stderr) == \
        (1, "Package 'no_such_pkg' not found\n")
    assert (missing_exe.returncode, missing_exe.stderr) == (1, "No executable found\n")


def test_a_real_ros2_on_the_path_runs_instead(tmp_path):
    real = tmp_path / "ros2"
    real.write_text('#!/bin/sh\necho "real ros2: $*"\n')
    real.chmod(0o755)
    result = subprocess.run([command("ros2"), "topic", "list", "-t"], capture_output=True,
                            text=True, timeout=30,
                            env={**os.environ, "PATH": f"{os.environ['PATH']}:{tmp_path}"})
    assert result.stdout == "real ros2: topic list -t\n", result.stderr


def test_env_sh_appends_the_stand_in_to_the_path(tmp_path):
    """After ``source tools/env.sh`` ``ros2`` is ours, unless a real one is on the PATH."""
    real = tmp_path / "ros2"
    real.write_text("#!/bin/sh\n")
    real.chmod(0o755)
    found = [subprocess.run(["bash", "-c", f"source {ROOT}/tools/env.sh && command -v ros2"],
                            capture_output=True, text=True, timeout=30,
                            env={**os.environ, "PATH": path}).stdout
             for path in ("/usr/bin:/bin", f"/usr/bin:/bin:{tmp_path}")]
    assert found == [command("ros2") + "\n", f"{real}\n"]



def ros2_at_once(procs, *calls: tuple[str, ...]) -> list[subprocess.CompletedProcess]:
    """Each ``ros2 ARGS`` of ``calls`` started at the same time (each waits for discovery
    on its own, up to 4.5 s with the param verbs); their results in order."""
    started = [subprocess.Popen([command("ros2"), *args], env=procs.env, cwd=ROOT, text=True,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE)
               for args in calls]
    outputs = [p.communicate(timeout=30) for p in started]
    return [subprocess.CompletedProcess(p.args, p.returncode, *output)
            for p, output in zip(started, outputs, strict=True)]


def test_param_list_get_and_dump_show_the_nodes_parameters(pocket_graph):
    procs, _ = pocket_graph
    listed, got, missing, dumped = ros2_at_once(
        procs, ("param", "list", "/pocket_pdr"), ("param", "get", "/pocket_pdr", "block_s"),
        ("param", "get", "/pocket_pdr", "no_such_param"), ("param", "dump", "/pocket_pdr"))
    lines = listed.stdout.splitlines()
    assert {"  block_s", "  imu_durability", "  use_sim_time"} <= set(lines), listed.stderr
    assert lines == sorted(lines) and all(line.startswith("  ") for line in lines)
    assert (got.returncode, got.stdout) == (0, "Double value is: 0.25\n"), got.stderr
    assert (missing.returncode, missing.stderr) == (1, "Parameter not set\n")
    assert dumped.stdout.startswith("/pocket_pdr:\n  ros__parameters:\n    "), dumped.stderr
    assert dumped.stdout.endswith("\n\n")                 # print of yaml.dump's text
    tree = yaml.safe_load(dumped.stdout)["/pocket_pdr"]["ros__parameters"]
    parameters = dotted(tree)           # ros2cli nests a dotted name: stairs: {b_u_cm: ...}
    assert sorted(parameters) == [line.strip() for line in lines]
    assert parameters["imu_durability"] == "transient_local"
    assert parameters["block_s"] == 0.25 and parameters["use_sim_time"] is False
    assert tree["step_length"]["b_h_m"] == parameters["step_length.b_h_m"]


def dotted(tree: dict, prefix: str = "") -> dict:
    """A dump's nested parameters by their dotted names."""
    flat = {}
    for key, value in tree.items():
        if isinstance(value, dict):
            flat |= dotted(value, f"{prefix}{key}.")
        else:
            flat[f"{prefix}{key}"] = value
    return flat


def test_param_set_changes_the_value_or_says_why_not(pocket_graph):
    procs, _ = pocket_graph
    done, refused = ros2_at_once(procs, ("param", "set", "/pocket_pdr", "mag_wait_s", "2.5"),
                                 ("param", "set", "/pocket_pdr", "mag_wait_s", "soon"))
    assert (done.returncode, done.stdout) == (0, "Set parameter successful\n"), done.stderr
    assert (refused.returncode, refused.stderr) == (
        1, "Setting parameter failed: Wrong parameter type, expected 'Type.DOUBLE' got "
           "'Type.STRING'\n")
    got = procs.run("ros2", "param", "get", "/pocket_pdr", "mag_wait_s", timeout=30)
    assert got.stdout == "Double value is: 2.5\n", got.stderr


def test_bag_record_writes_the_topics_it_is_given(pocket_graph, tmp_path):
    """``ros2 bag record -o OUT TOPIC`` of a kept output (transient local: the recorder
    gets what was published before it subscribed), stopped after 5 messages by a
    parameter of bag_record passed through ``--ros-args``."""
    from pdr_core.io.bag import BagReader

    procs, _ = pocket_graph
    out = tmp_path / "odometry"
    recorder = procs.start("ros2", "bag", "record", "-o", str(out), "/pdr/pocket/odometry",
                           "--ros-args", "-p", "max_messages:=5", name="bag_record")
    assert recorder.wait(timeout=30) == 0, recorder.log_path.read_text()
    reader = BagReader(out)
    assert reader.topics == {"/pdr/pocket/odometry": "nav_msgs/msg/Odometry"}
    assert len(reader.read_messages("/pdr/pocket/odometry")) == 5
