"""tf2_msgs (issue 42): src/tf2_msgs builds TFMessage only where no tf2_msgs is installed.

A tf2_msgs elsewhere (a ROS install, a wheel) is found by tools/tf2_msgs_elsewhere.py, and
tools/bootstrap.sh then skips ours; src/tf2_msgs itself builds nothing when one is on
AMENT_PREFIX_PATH, for a plain ``colcon build`` on a ROS install. Both are tested here by
hiding a fake tf2_msgs on the path; the workspace's own tf2_msgs is checked as built.
"""
from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

from wstest import ROOT

SCRIPT = ROOT / "tools" / "tf2_msgs_elsewhere.py"
PACKAGE = ROOT / "src" / "tf2_msgs"
SITE = Path("lib", f"python{sys.version_info.major}.{sys.version_info.minor}", "site-packages")


def load_script():
    spec = importlib.util.spec_from_file_location("tf2_msgs_elsewhere", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


elsewhere = load_script().elsewhere


def fake_tf2_msgs(prefix: Path, index: bool = True, python: bool = True) -> Path:
    """A minimal installed tf2_msgs under ``prefix``: its ament index entry and a Python
    package with a TFMessage, as a ROS install or a wheel lays them out."""
    if index:
        marker = prefix / "share" / "ament_index" / "resource_index" / "packages"
        marker.mkdir(parents=True)
        (marker / "tf2_msgs").touch()
    if python:
        msg = prefix / SITE / "tf2_msgs" / "msg"
        msg.mkdir(parents=True)
        (msg.parent / "__init__.py").touch()
        (msg / "__init__.py").write_text("class TFMessage:\n    transforms = ()\n")
    return prefix


def test_a_tf2_msgs_elsewhere_is_found_by_its_index_entry_or_its_python_package(tmp_path):
    workspace = tmp_path / "ws"
    both = fake_tf2_msgs(tmp_path / "ros")
    index_only = fake_tf2_msgs(tmp_path / "index_only", python=False)
    python_only = fake_tf2_msgs(tmp_path / "python_only", index=False)
    empty = tmp_path / "empty"
    empty.mkdir()
    assert elsewhere([str(empty), str(both)], [str(empty), str(both / SITE)],
                     workspace) == both
    assert elsewhere([str(index_only)], [], workspace) == index_only
    assert elsewhere([str(empty)], [str(python_only / SITE)],
                     workspace) == python_only / SITE / "tf2_msgs"
    assert elsewhere(["", str(empty)], ["", str(empty)], workspace) is None


def test_a_previous_build_of_ours_is_not_elsewhere(tmp_path):
    """install/tf2_msgs of the workspace is on both paths once tools/env.sh is sourced:
    taking it for another one would skip ours, and the next bootstrap would build it
    again."""
    workspace = tmp_path / "ws"
    ours = fake_tf2_msgs(workspace / "install" / "tf2_msgs")
    built = fake_tf2_msgs(workspace / "build" / "tf2_msgs", index=False)
    linked = tmp_path / "linked"                          # --symlink-install's layout
    linked.mkdir()
    (linked / "tf2_msgs").symlink_to(built / SITE / "tf2_msgs")
    assert elsewhere([str(ours)], [str(ours / SITE), str(built / SITE), str(linked)],
                     workspace) is None
    theirs = fake_tf2_msgs(tmp_path / "ros")
    assert elsewhere([str(ours), str(theirs)], [str(ours / SITE)], workspace) == theirs


def run_script(env: dict, *options: str) -> str:
    result = subprocess.run([sys.executable, *options, str(SCRIPT), str(ROOT)], env=env,
                            capture_output=True, text=True, timeout=30, check=True)
    return result.stdout.strip()


def test_the_bootstrap_decision_with_and_without_one_on_the_path(tmp_path):
    """The script as tools/bootstrap.sh runs it: it prints the fake prefix hidden first on
    AMENT_PREFIX_PATH (skip ours), and nothing with only our own build on the paths
    (build ours; -S leaves the venv's site-packages out, to compare with ours alone)."""
    theirs = fake_tf2_msgs(tmp_path / "ros")
    ours = ROOT / "install" / "tf2_msgs"
    prefixes = os.environ.get("AMENT_PREFIX_PATH", "")
    env = {**os.environ, "AMENT_PREFIX_PATH": f"{theirs}:{prefixes}"}
    assert run_script(env) == str(theirs)
    env = {**os.environ, "PYTHONPATH": f"{theirs / SITE}:{ours / SITE}", "AMENT_PREFIX_PATH": ""}
    assert run_script(env) == str(theirs / SITE / "tf2_msgs")
    env = {**os.environ, "PYTHONPATH": str(ours / SITE), "AMENT_PREFIX_PATH": str(ours)}
    assert run_script(env, "-S") == ""


def test_the_package_builds_nothing_with_a_tf2_msgs_on_the_path(tmp_path):
    """A plain colcon build of src/tf2_msgs, as on a ROS install, with a fake tf2_msgs
    hidden on AMENT_PREFIX_PATH: it configures, and installs neither an index entry nor
    a Python package that would shadow the other one."""
    venv = ROOT / ".venv"
    theirs = fake_tf2_msgs(tmp_path / "ros")
    env = {**os.environ, "AMENT_PREFIX_PATH": f"{theirs}:{venv}", "CMAKE_PREFIX_PATH": str(venv),
           "PATH": f"{venv / 'bin'}:{os.environ['PATH']}"}
    result = subprocess.run(
        ["colcon", "--log-base", str(tmp_path / "log"), "build", "--base-paths", str(PACKAGE),
         "--build-base", str(tmp_path / "build"), "--install-base", str(tmp_path / "install"),
         "--event-handlers", "console_direct+", "--cmake-args",
         f"-DPython3_EXECUTABLE={venv / 'bin' / 'python'}", "-DBUILD_TESTING=OFF"],
        cwd=tmp_path, env=env, capture_output=True, text=True, timeout=120)
    out = result.stdout + result.stderr
    assert result.returncode == 0, out
    assert f"tf2_msgs: using the one in {theirs}; building nothing here" in out
    installed = tmp_path / "install" / "tf2_msgs"
    assert not (installed / "share" / "ament_index").exists()
    assert not (installed / SITE).exists()
    assert not list((tmp_path / "build" / "tf2_msgs").glob("rosidl_generator_*"))


def test_the_workspace_has_tf2_msgs_from_where_the_bootstrap_chose():
    """Ours, built by the bootstrap (with the type hash of ROS 2 Jazzy's TFMessage), or
    the one elsewhere when there is one; either way a TFMessage serializes and reads back
    as ROS 2 Jazzy's."""
    from geometry_msgs.msg import TransformStamped
    from rclpy.serialization import serialize_message
    from rosbags.typesys import Stores, get_typestore

    import tf2_msgs
    from tf2_msgs.msg import TFMessage

    jazzy = get_typestore(Stores.ROS2_JAZZY)
    theirs = elsewhere(os.environ.get("AMENT_PREFIX_PATH", "").split(":"), sys.path, ROOT)
    ours = ROOT / "install" / "tf2_msgs"
    if theirs is None:
        assert Path(tf2_msgs.__file__).is_relative_to(ours / SITE)
        described = json.loads((ours / "share" / "tf2_msgs" / "msg" / "TFMessage.json")
                               .read_text())
        hashes = {h["type_name"]: h["hash_string"] for h in described["type_hashes"]}
        assert hashes["tf2_msgs/msg/TFMessage"] == jazzy.hash_rihs01("tf2_msgs/msg/TFMessage")
    else:
        assert not ours.exists()
        assert not Path(tf2_msgs.__file__).resolve().is_relative_to(ROOT / "install")
    pose = TransformStamped(child_frame_id="base_link")
    pose.header.frame_id = "map"
    pose.header.stamp.sec = 7
    pose.transform.translation.x = 1.5
    pose.transform.rotation.w = 1.0
    raw = serialize_message(TFMessage(transforms=[pose, TransformStamped()]))
    read = jazzy.deserialize_cdr(bytes(raw), "tf2_msgs/msg/TFMessage")
    assert [t.child_frame_id for t in read.transforms] == ["base_link", ""]
    assert read.transforms[0].header.frame_id == "map"
    assert read.transforms[0].header.stamp.sec == 7
    assert read.transforms[0].transform.translation.x == 1.5
