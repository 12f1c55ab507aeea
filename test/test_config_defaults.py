"""One source of defaults per configuration (issue 31).

- Each navigator's configuration dataclass holds, by default, what its shipped default
  file sets (``foot_ekf.yaml``, ``pocket_pdr.yaml``, ``landmark_drift.yaml``), field by
  field; a field that differs is named with both values. The profile and variant files
  (``foot_ekf_<profile>.yaml``, ``pocket_pdr_no_mag.yaml``) override them and are not
  compared.
- The nodes' parameter files (``*_params.yaml``, ``zupt_ekf.yaml``, ``imu_sim.yaml``,
  ``bag_play.yaml``) give each parameter the default its node declares, but the bag or
  scenario they play, which has to be named; and every floor height is
  ``pdr_core.vocabulary.FLOOR_HEIGHT_M``.
"""
from __future__ import annotations

import ast
import importlib
from dataclasses import fields, is_dataclass, replace
from pathlib import Path

import pytest
import yaml

from pdr_core.config_files import read_config_file
from pdr_core.vocabulary import FLOOR_HEIGHT_M
from pdr_drift.config import DriftConfig, load_drift_config
from pdr_ins_ekf.config import RunConfig, run_config
from pdr_pocket.config import PocketConfig, pocket_config
from wstest import ROOT

SRC = ROOT / "src"


def read_foot(path: Path) -> RunConfig:
    return run_config(read_config_file(path), str(path))


def read_pocket(path: Path) -> PocketConfig:
    return pocket_config(read_config_file(path), str(path))


# (shipped default file, its reader, the dataclass whose defaults it must hold)
DEFAULT_FILES = [
    (SRC / "pdr_ins_ekf" / "config" / "foot_ekf.yaml", read_foot, RunConfig),
    (SRC / "pdr_pocket" / "config" / "pocket_pdr.yaml", read_pocket, PocketConfig),
    (SRC / "pdr_drift" / "config" / "landmark_drift.yaml", load_drift_config, DriftConfig)]



def differences(default, shipped, path: str = "") -> list[str]:
    """The dotted fields where ``shipped`` differs from ``default``, descending into nested
    dataclasses of the same type; a dataclass of another type differs as a whole."""
    if is_dataclass(default) and type(default) is type(shipped):
        return [name for f in fields(default) for name in differences(
            getattr(default, f.name), getattr(shipped, f.name), f"{path}{f.name}.")]
    return [] if default == shipped else [path.removesuffix(".")]


def described(default, shipped, names: list[str]) -> str:
    def value(config, name):
        for part in name.split("."):
            config = getattr(config, part)
        return config
    return "; ".join(f"{name}: dataclass {value(default, name)!r}, shipped "
                     f"{value(shipped, name)!r}" for name in names)


@pytest.mark.parametrize(("path", "read", "cls"), DEFAULT_FILES,
                         ids=[p.name for p, _, _ in DEFAULT_FILES])
def test_the_dataclass_defaults_are_the_shipped_default_file(path, read, cls):
    default, shipped = cls(), read(path)
    found = differences(default, shipped)
    assert found == [], described(default, shipped, found)


def unlisted(default, mapping, path: str = "") -> list[str]:
    """The dotted fields of the dataclass ``default`` that ``mapping`` leaves out."""
    missing = []
    for f in fields(default):
        if f.name not in mapping:
            missing.append(path + f.name)
        elif is_dataclass(getattr(default, f.name)):
            missing += unlisted(getattr(default, f.name), mapping[f.name] or {},
                                f"{path}{f.name}.")
    return missing


@pytest.mark.parametrize(("path", "section", "cls"), [
    (SRC / "pdr_pocket" / "config" / "pocket_pdr.yaml", None, PocketConfig),
    (SRC / "pdr_drift" / "config" / "landmark_drift.yaml", "drift", DriftConfig)],
    ids=["pocket_pdr.yaml", "landmark_drift.yaml"])
def test_the_default_file_lists_every_setting(path, section, cls):
    """A user reading pocket_pdr.yaml or landmark_drift.yaml sees every setting there is.
    (foot_ekf.yaml lists the 9-state filter's; the 15-state ones are in the profile
    files.)"""
    mapping = read_config_file(path)
    assert unlisted(cls(), mapping[section] if section else mapping) == []


def test_a_difference_is_named_with_both_values():
    default = PocketConfig()
    shipped = replace(default, steps=replace(default.steps, max_rise_s=2.0))
    found = differences(default, shipped)
    assert found == ["steps.max_rise_s"]
    assert described(default, shipped, found) == \
        "steps.max_rise_s: dataclass 1.5, shipped 2.0"


def test_a_partial_section_keeps_the_shipped_values_of_the_keys_it_does_not_give():
    """A foot configuration's ``filter:`` with one key keeps the other keys of
    foot_ekf.yaml (RunConfig's defaults), as a file without the section does."""
    config = run_config({"filter": {"zupt_sigma_mps": 0.02}})
    assert config.filter == replace(RunConfig().filter, zupt_sigma_mps=0.02)
    assert config.smoother == run_config({"smoother": {}}).smoother == RunConfig().smoother


# The nodes and the modules that declare their parameters (pdr_core.ros.node_params.declare)
NODES = {
    "zupt_ekf": ["pdr_ins_ekf.nodes.zupt_ekf"],
    "pocket_pdr": ["pdr_pocket.nodes.pocket_pdr"],
    "stride_calibrator": ["pdr_pocket.nodes.stride_calibrator"],
    "landmark_drift": ["pdr_drift.nodes.landmark_drift"],
    "imu_sim": ["pdr_sim.nodes.imu_sim", "pdr_sim.nodes.playback"],
    "bag_play": ["pdr_sim.nodes.bag_play", "pdr_sim.nodes.playback"],
    "bag_record": ["pdr_sim.nodes.bag_record"]}
PARAMS_FILES = {
    "zupt_ekf": SRC / "pdr_ins_ekf" / "config" / "zupt_ekf.yaml",
    "pocket_pdr": SRC / "pdr_pocket" / "config" / "pocket_pdr_params.yaml",
    "stride_calibrator": SRC / "pdr_pocket" / "config" / "stride_calibrator_params.yaml",
    "landmark_drift": SRC / "pdr_drift" / "config" / "landmark_drift_params.yaml",
    "imu_sim": SRC / "pdr_sim" / "config" / "imu_sim.yaml",
    "bag_play": SRC / "pdr_sim" / "config" / "bag_play.yaml"}
# What a parameter file names because the node has nothing to play without it
EXAMPLES = {"imu_sim": {"scenario"}, "bag_play": {"bag"}}


def declared_defaults(node: str) -> dict:
    """The parameters the node's modules declare with ``declare(node, NAME, DEFAULT, ...)``,
    each default evaluated in its module."""
    found = {}
    for name in NODES[node]:
        module = importlib.import_module(name)
        for call in ast.walk(ast.parse(Path(module.__file__).read_text())):
            # a computed name (pocket_pdr's lines, defaults the configuration's) is left to
            # test_node_reference, which constructs the node
            if (isinstance(call, ast.Call) and isinstance(call.func, ast.Name)
                    and call.func.id == "declare" and isinstance(call.args[1], ast.Constant)):
                key = ast.literal_eval(call.args[1])
                found[key] = eval(compile(ast.Expression(call.args[2]), name, "eval"),
                                  vars(module))
    return found


@pytest.mark.parametrize("node", sorted(PARAMS_FILES))
def test_a_parameter_file_gives_each_parameter_its_declared_default(node):
    params = yaml.safe_load(PARAMS_FILES[node].read_text())[node]["ros__parameters"]
    declared = declared_defaults(node)
    assert set(params) <= set(declared), sorted(set(params) - set(declared))
    differ = {key: (declared[key], value) for key, value in params.items()
              if key not in EXAMPLES.get(node, set())
              and (value != declared[key] or type(value) is not type(declared[key]))}
    assert differ == {}, f"{node}: declared default, parameter file: {differ}"


def test_every_floor_height_is_the_shared_one():
    from pdr_drift.cli import parser
    from pdr_drift.streaming import StreamingDrift
    from pdr_pocket.config import StairsConfig

    assert declared_defaults("landmark_drift")["floor_height_m"] == FLOOR_HEIGHT_M
    assert StairsConfig().floor_height_m == FLOOR_HEIGHT_M
    assert StreamingDrift(DriftConfig()).floor_height_m == FLOOR_HEIGHT_M
    run = parser().parse_args(["run", "in", "--out", "out"])
    assert run.floor_height_m == FLOOR_HEIGHT_M
