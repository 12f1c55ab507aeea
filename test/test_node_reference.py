"""docs/nodes.md against the nodes themselves.

Each node is constructed in this process (a real rclpy node, no graph needed) and its
declared parameters, with their types and default values, are compared with the
parameter table of its section in docs/nodes.md, both ways: a parameter added to a node
without documenting it fails, and so does one documented that the node does not declare.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest
import rclpy
import yaml
from rcl_interfaces.msg import ParameterType
from rclpy.node import Node

from wstest import ROOT

REFERENCE = ROOT / "docs" / "nodes.md"
ROS_TYPE_NAMES = {ParameterType.PARAMETER_BOOL: "bool",
                  ParameterType.PARAMETER_INTEGER: "integer",
                  ParameterType.PARAMETER_DOUBLE: "double",
                  ParameterType.PARAMETER_STRING: "string",
                  ParameterType.PARAMETER_STRING_ARRAY: "string[]",
                  ParameterType.PARAMETER_DOUBLE_ARRAY: "double[]",
                  ParameterType.PARAMETER_INTEGER_ARRAY: "integer[]"}
IMPLICIT = {"use_sim_time", "start_type_description_service"}  # rclpy declares them on every node


def documented_parameters(text: str) -> dict[str, dict[str, tuple[str, str]]]:
    """Per node section (``## name``) of the reference: parameter -> (type, default cell)."""
    nodes: dict[str, dict[str, tuple[str, str]]] = {}
    current = None
    for line in text.splitlines():
        heading = re.match(r"^## (\w+)\s*$", line)
        if heading:
            current = nodes.setdefault(heading.group(1), {})
            continue
        row = re.match(r"^\| `([\w.]+)` \| ([^|]+) \| ([^|]*) \|", line)
        if row and current is not None:
            current[row.group(1)] = (row.group(2).strip(), row.group(3).strip())
    return nodes


def declared_parameters(node: Node) -> dict[str, tuple[str, object]]:
    """Parameter -> (type name, declared value) of a live node, without rclpy's own. A
    parameter declared with a type and no value (a required list) has the value None."""
    names = sorted(set(node._parameters) - IMPLICIT)
    descriptors = node.describe_parameters(names)
    return {name: (ROS_TYPE_NAMES.get(d.type, f"type {d.type}"), node._parameters[name].value)
            for name, d in zip(names, descriptors, strict=True)}


def mismatches(declared: dict[str, tuple[str, object]],
               documented: dict[str, tuple[str, str]]) -> list[str]:
    """What docs/nodes.md gets wrong about one node: undocumented, undeclared, wrong type
    or wrong default (a default cell in backquotes is read as YAML)."""
    problems = [f"{n}: declared but not documented" for n in declared.keys() - documented.keys()]
    problems += [f"{n}: documented but not declared" for n in documented.keys() - declared.keys()]
    for name in declared.keys() & documented.keys():
        (ros_type, value), (doc_type, doc_default) = declared[name], documented[name]
        if ros_type != doc_type:
            problems.append(f"{name}: declared {ros_type}, documented {doc_type}")
        quoted = re.fullmatch(r"`(.*)`", doc_default)
        if quoted and yaml.safe_load(quoted.group(1) or '""') != value:
            problems.append(f"{name}: declared default {value!r}, documented {doc_default}")
    return sorted(problems)


def node_classes(tmp_path: Path) -> dict[str, tuple[type, list[str]]]:
    """Node name -> (class, the -p arguments it needs to be constructed)."""
    from pdr_drift.nodes.landmark_drift import LandmarkDriftNode
    from pdr_ins_ekf.nodes.zupt_ekf import ZuptEkfNode
    from pdr_pocket.nodes.pocket_pdr import PocketPdrNode
    from pdr_pocket.nodes.stride_calibrator import StrideCalibratorNode
    from pdr_sim.nodes.bag_play import BagPlayer
    from pdr_sim.nodes.bag_record import BagRecorder
    from pdr_sim.nodes.imu_sim import ImuSim
    return {"imu_sim": (ImuSim, []), "bag_play": (BagPlayer, []),
            "bag_record": (BagRecorder, [f"out:={tmp_path / 'bag'}", "topics:=[imu/data]"]),
            "zupt_ekf": (ZuptEkfNode, []), "pocket_pdr": (PocketPdrNode, []),
            "landmark_drift": (LandmarkDriftNode, []),
            "stride_calibrator": (StrideCalibratorNode, [])}


def construct(cls: type, parameters: list[str]) -> Node:
    args = ["node", "--ros-args"] + [a for p in parameters for a in ("-p", p)]
    rclpy.init(args=args)
    return cls()


@pytest.fixture
def ros():
    yield
    rclpy.try_shutdown()


NODES = ["imu_sim", "bag_play", "bag_record", "zupt_ekf", "pocket_pdr", "landmark_drift",
         "stride_calibrator"]


def test_every_node_has_a_section():
    assert set(NODES) <= set(documented_parameters(REFERENCE.read_text()))


@pytest.mark.parametrize("name", NODES)
def test_reference_matches_declared_parameters(name, tmp_path, ros):
    cls, parameters = node_classes(tmp_path)[name]
    node = construct(cls, parameters)
    declared = declared_parameters(node)
    node.destroy_node()
    assert declared, "the node declares parameters"
    assert mismatches(declared, documented_parameters(REFERENCE.read_text())[name]) == []


def test_an_undocumented_parameter_fails(tmp_path, ros):
    """The check can fail: a parameter declared on top of zupt_ekf's, not in the page."""
    cls, parameters = node_classes(tmp_path)["zupt_ekf"]
    node = construct(cls, parameters)
    node.declare_parameter("new_gain", 0.5)
    declared = declared_parameters(node)
    node.destroy_node()
    documented = documented_parameters(REFERENCE.read_text())["zupt_ekf"]
    assert mismatches(declared, documented) == ["new_gain: declared but not documented"]


def test_a_stale_or_wrong_row_fails():
    declared = {"rate": ("double", 1.0)}
    assert mismatches(declared, {"rate": ("double", "`2.0`")}) == [
        "rate: declared default 1.0, documented `2.0`"]
    assert mismatches(declared, {"rate": ("integer", "`1.0`")}) == [
        "rate: declared double, documented integer"]
    assert mismatches(declared, {"rate": ("double", "`1.0`"), "gone": ("bool", "`false`")}) == [
        "gone: documented but not declared"]
