"""The words the packages share, defined once: activities, landmark types, floor height.

- :class:`Activity`: what a person does during a step, the ``pdr_msgs/Step`` constants
  (``STANDING`` … ``SITTING``); ``Activity.WALKING.label`` is the name reports use and
  ``.colour`` the one every plot draws it in, :data:`ACTIVITY_NAMES` all the names by
  value, :data:`STAIRS_ACTIVITIES` those on a flight, :data:`ACTIVITY_VALUES` the numbers
  that are one.
- :class:`LandmarkType`: the ``pdr_msgs/Landmark`` types (``CORNER``, ``STAIRS``);
  ``LandmarkType.CORNER.label`` is the name logs use, ``.marker`` the plots'.

Nothing else counts them: a new activity or landmark type needs its colour or marker
here and nothing in the reports, plots or checks (test_code_shape.py fails on a literal
count or value).
- :data:`FLOOR_HEIGHT_M`: the default height of one floor [m], from which a height becomes
  a floor index, round(z / FLOOR_HEIGHT_M).

A test checks the enums against the message definitions, so adding an activity starts in
``Step.msg`` and here (docs/extending.md).
"""
from __future__ import annotations

from enum import IntEnum


class _Labelled(IntEnum):
    @property
    def label(self) -> str:
        """The lower-case name reports, plots and logs use ("upstairs")."""
        return self.name.lower()


class Activity(_Labelled):
    """pdr_msgs/Step activities."""

    STANDING = 0
    WALKING = 1
    UPSTAIRS = 2
    DOWNSTAIRS = 3
    SITTING = 4

    @property
    def colour(self) -> str:
        """The Matplotlib colour every plot draws this activity in."""
        return _ACTIVITY_COLOURS[self]


ACTIVITY_NAMES = tuple(a.label for a in Activity)
ACTIVITY_VALUES = frozenset(a.value for a in Activity)
STAIRS_ACTIVITIES = (Activity.UPSTAIRS, Activity.DOWNSTAIRS)


class Ride(_Labelled):
    """pdr_msgs/Step rides (its ``RIDE_`` constants): how the floor changed since the
    step before without a stairs step, found by the barometer (issue 41)."""

    NONE = 0
    LIFT = 1
    ESCALATOR = 2


_ACTIVITY_COLOURS = {Activity.STANDING: "tab:gray", Activity.WALKING: "tab:blue",
                     Activity.UPSTAIRS: "tab:green", Activity.DOWNSTAIRS: "tab:orange",
                     Activity.SITTING: "tab:purple"}


class LandmarkType(_Labelled):
    """pdr_msgs/Landmark types."""

    CORNER = 0
    STAIRS = 1

    @property
    def marker(self) -> str:
        """The Matplotlib format string the plots mark this type with."""
        return _LANDMARK_MARKERS[self]


_LANDMARK_MARKERS = {LandmarkType.CORNER: "k^", LandmarkType.STAIRS: "gs"}

FLOOR_HEIGHT_M = 3.5
