"""The activities and landmark types of pdr_core.vocabulary are the constants of
pdr_msgs/Step and pdr_msgs/Landmark, names and values: in the .msg files and in the
Python classes generated from them."""
from __future__ import annotations

import re

import pytest

from pdr_core.vocabulary import ACTIVITY_NAMES, STAIRS_ACTIVITIES, Activity, LandmarkType, Ride
from wstest import ROOT

MSG = ROOT / "src" / "pdr_msgs" / "msg"
CONSTANT = re.compile(r"^\s*uint8\s+([A-Z][A-Z0-9_]*)\s*=\s*(\d+)\s*(?:#.*)?$")
# each message's enums by the prefix of their constants' names
ENUMS = {"Step": {"": Activity, "RIDE_": Ride}, "Landmark": {"": LandmarkType}}


def members(message: str) -> dict[str, int]:
    """The constants the enums of ``message`` give, by name."""
    return {prefix + e.name: e.value for prefix, enum in ENUMS[message].items() for e in enum}


def constants(message: str) -> dict[str, int]:
    """The uint8 constants of src/pdr_msgs/msg/<message>.msg, in file order."""
    return {m[1]: int(m[2]) for line in (MSG / f"{message}.msg").read_text().splitlines()
            if (m := CONSTANT.match(line))}


@pytest.mark.parametrize("message", sorted(ENUMS))
def test_the_enum_is_the_message_definitions_constants(message):
    assert constants(message) == members(message)


@pytest.mark.parametrize("message", sorted(ENUMS))
def test_the_generated_message_class_agrees(message):
    msg = pytest.importorskip("pdr_msgs.msg")
    generated = getattr(msg, message)
    for name, value in members(message).items():
        assert getattr(generated, name) == value, name


def test_the_parser_sees_the_constants_it_is_for():
    assert CONSTANT.match("uint8 STAIRS = 1").groups() == ("STAIRS", "1")
    assert CONSTANT.match("uint8 SITTING = 4   # seated").groups() == ("SITTING", "4")
    assert not CONSTANT.match("uint8 activity                # one of the constants above")


def test_the_labels_and_the_stairs():
    assert ACTIVITY_NAMES == ("standing", "walking", "upstairs", "downstairs", "sitting")
    assert [a.label for a in STAIRS_ACTIVITIES] == ["upstairs", "downstairs"]
    assert LandmarkType.CORNER.label == "corner"
    assert all(ACTIVITY_NAMES[a] == a.label for a in Activity)
