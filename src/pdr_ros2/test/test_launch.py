"""The launch front ends (pdr_ros2.launch_description), their substitutions, the schema
of the shipped launch files, and the runner's shutdown (pdr_ros2.launch_runner) on
plain processes: no ROS graph (test/test_ros2_launch.py runs the graphs)."""
from __future__ import annotations

import signal
import time
from pathlib import Path

import pytest
import xmlschema
import yaml

from pdr_ros2.launch_description import read_launch
from pdr_ros2.launch_runner import LaunchRunner
from pdr_ros2.launch_substitutions import LaunchError, Scope, substitute

SRC = Path(__file__).resolve().parents[2]
SCHEMA = SRC / "pdr_ros2" / "schema" / "launch.xsd"
SHIPPED = sorted(SRC.glob("*/launch/*.launch.xml"))
REPLAY_ARGS = {"package": "pdr_drift", "graph": "pocket_drift.launch.xml", "bag": "b",
               "out": "o", "record": "[pdr/drift]"}


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(text)
    return path


def test_the_project_ships_its_four_graphs_and_the_replay():
    assert [p.name for p in SHIPPED] == ["pocket_drift.launch.xml", "foot.launch.xml",
                                         "pocket.launch.xml", "two_imu.launch.xml",
                                         "replay.launch.xml"]


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.name)
def test_shipped_launch_files_follow_the_schema(path):
    xmlschema.XMLSchema(SCHEMA).validate(path)


def test_the_schema_refuses_what_launch_xml_refuses(tmp_path):
    schema = xmlschema.XMLSchema(SCHEMA)
    for text in ('<launch><node pkg="a" exec="b" package="c"/></launch>',
                 '<launch><node pkg="a"/></launch>',
                 '<launch><node pkg="a" exec="b"><param name="x" sep=","/></node></launch>',
                 '<launch><node pkg="a" exec="b" on_exit="restart"/></launch>',
                 '<launch version="0.1.1"/>'):
        assert not schema.is_valid(text), text


def test_the_reader_refuses_what_launch_xml_refuses_naming_it(tmp_path):
    path = write(tmp_path, "x.launch.xml",
                 '<launch><node pkg="pdr_pocket" exec="pocket_pdr" package="p"/></launch>')
    with pytest.raises(LaunchError, match=r"x.launch.xml: Unexpected attribute\(s\) found in "
                                          r"`node`: \['package'\]"):
        read_launch(path, {})
    path.write_text('<launch><node pkg="pdr_pocket" exec="pocket_pdr"><topic/></node></launch>')
    with pytest.raises(LaunchError, match=r"Unexpected nested tag\(s\) found in `node`"):
        read_launch(path, {})


def test_replay_of_the_drift_graph_reads_into_four_nodes_with_their_arguments():
    launch = read_launch(SRC / "pdr_sim" / "launch" / "replay.launch.xml",
                         {**REPLAY_ARGS, "config": "/c.yaml", "imu": "/phone/imu"})
    labels = [p.label for p in launch.processes]
    assert labels == ["pocket_pdr-1", "landmark_drift-2", "bag_record-3", "bag_play-4"]
    navigator, _, recorder, player = launch.processes
    assert navigator.command[0].endswith("/lib/pdr_pocket/pocket_pdr")
    assert navigator.ros_arguments == ["-r", "__node:=pocket_pdr", "-r", "imu/data:=/phone/imu",
                                       "-r", "imu/mag:=imu/mag"]
    assert navigator.parameters == [{"config": "/c.yaml", "imu_durability": "volatile",
                                     "block_s": 0.25}]
    assert recorder.shutdown_on_exit and not player.shutdown_on_exit
    assert recorder.parameters == [{"out": "o", "topics": ["pdr/drift"], "max_messages": 0}]
    assert player.parameters[0]["topics"] == ["/imu/data", "/imu/mag"]


def test_parameters_are_written_as_launch_ros_writes_them(tmp_path):
    launch = read_launch(SRC / "pdr_pocket" / "launch" / "pocket.launch.xml",
                         {"namespace": "alice"})
    [navigator] = launch.processes
    argv = navigator.argv(tmp_path)
    assert argv[1:5] == ["--ros-args", "-r", "__node:=pocket_pdr", "-r"]
    assert "__ns:=/alice" in argv
    written = yaml.safe_load(Path(argv[argv.index("--params-file") + 1]).read_text())
    assert written == {"/**": {"ros__parameters": {"config": "", "imu_durability": "volatile",
                                                   "block_s": 0.25}}}


def test_an_unknown_or_missing_argument_is_an_error_naming_it():
    replay = SRC / "pdr_sim" / "launch" / "replay.launch.xml"
    with pytest.raises(LaunchError, match="required launch argument 'out' not provided"):
        read_launch(replay, {k: v for k, v in REPLAY_ARGS.items() if k != "out"})
    with pytest.raises(LaunchError, match=r"unknown launch argument.*confg"):
        read_launch(replay, {**REPLAY_ARGS, "confg": "x"})


def test_substitutions_nest_and_unknown_ones_are_named(monkeypatch):
    scope = Scope({"pkg": "pdr_pocket", "n": "2"}, "/here")
    monkeypatch.setenv("PDR_TEST_VALUE", "v")
    share = substitute("$(find-pkg-share $(var pkg))/config", scope)
    assert share.endswith("/share/pdr_pocket/config")
    assert substitute("$(env PDR_TEST_VALUE)-$(env PDR_NO_SUCH x)-$(dirname)", scope) == \
        "v-x-/here"
    with pytest.raises(LaunchError, match="unknown substitution 'eval'"):
        substitute("$(eval 1 + 1)", scope)
    with pytest.raises(LaunchError, match="launch configuration 'nope' does not exist"):
        substitute("$(var nope)", scope)
    with pytest.raises(LaunchError, match="unclosed"):
        substitute("$(var pkg", scope)


def test_the_yaml_front_end_reads_as_the_xml_one(tmp_path):
    xml = write(tmp_path, "g.launch.xml", """<launch>
  <arg name="ns" default="bob"/>
  <group><push_ros_namespace namespace="$(var ns)"/>
    <node pkg="pdr_pocket" exec="pocket_pdr" name="p" if="true">
      <param name="topics" value="a,b" value-sep=","/><param name="rate" value="2.5"/>
      <remap from="imu/data" to="/x"/>
    </node>
  </group>
  <node pkg="pdr_drift" exec="landmark_drift" unless="1"/>
</launch>""")
    yml = write(tmp_path, "g.launch.yaml", """launch:
- arg: {name: ns, default: bob}
- group:
    children:
    - push_ros_namespace: {namespace: $(var ns)}
    - node:
        pkg: pdr_pocket
        exec: pocket_pdr
        name: p
        if: true
        param: [{name: topics, value: [a, b]}, {name: rate, value: 2.5}]
        remap: [{from: imu/data, to: /x}]
- node: {pkg: pdr_drift, exec: landmark_drift, unless: 1}
""")
    from_xml, from_yaml = read_launch(xml, {}), read_launch(yml, {})
    assert from_xml.processes == from_yaml.processes
    [node] = from_xml.processes
    assert node.parameters == [{"topics": ["a", "b"], "rate": 2.5}]
    assert node.ros_arguments[-4:] == ["-r", "__ns:=/bob", "-r", "imu/data:=/x"]


def stubborn(tmp_path: Path, name: str, traps: str) -> str:
    """An executable whose shell writes each signal it gets to NAME.signals."""
    log = tmp_path / f"{name}.signals"
    script = write(tmp_path, f"{name}.sh", f"{traps}\nwhile :; do sleep 0.02; done\n")
    return f'<executable cmd="sh {script}" name="{name}" output="screen"><env name="LOG" ' \
           f'value="{log}"/></executable>'


def test_shutdown_sends_sigint_twice_then_sigterm_then_sigkill(tmp_path, capsys):
    """A process that ignores SIGINT gets it again at half the SIGTERM timeout and then
    SIGTERM; one that ignores SIGTERM too is killed; all within the timeouts."""
    path = write(tmp_path, "s.launch.xml", "<launch>" + stubborn(
        tmp_path, "deaf", "trap 'echo INT >> $LOG' INT; trap 'echo TERM >> $LOG; exit 3' TERM")
        + stubborn(tmp_path, "deafer", "trap 'echo INT >> $LOG' INT; trap 'echo TERM >> $LOG' "
                                       "TERM")
        + '<executable cmd="sleep 0.3" on_exit="shutdown"/></launch>')
    runner = LaunchRunner(read_launch(path, {}).processes, sigterm_timeout_s=0.6,
                          sigkill_timeout_s=0.3)
    start = time.monotonic()
    assert runner.run() == 0
    assert time.monotonic() - start < 0.3 + 0.9 + 0.5
    assert (tmp_path / "deaf.signals").read_text().split() == ["INT", "INT", "TERM"]
    assert (tmp_path / "deafer.signals").read_text().split() == ["INT", "INT", "TERM"]
    out = capsys.readouterr().out
    assert "[INFO] [deaf-1]: process started with pid [" in out
    assert "[INFO] [sleep-3]: process has finished cleanly" in out
    assert "escalating to 'SIGTERM'" in out and "escalating to 'SIGKILL'" in out
    assert f"process has died [pid {runner.running[1].popen.pid}, exit code " \
           f"{-signal.SIGKILL}" in out


def test_a_process_that_dies_makes_the_launch_fail_and_its_lines_are_prefixed(tmp_path,
                                                                              capsys):
    path = write(tmp_path, "d.launch.xml", '<launch><executable cmd="sh -c \'echo hi; exit 4\'"'
                                           ' name="x" output="screen"/></launch>')
    assert LaunchRunner(read_launch(path, {}).processes).run() == 1
    out = capsys.readouterr().out
    assert "[x-1] hi\n" in out and "process has died" in out and "exit code 4" in out
