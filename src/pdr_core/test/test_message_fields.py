"""Requests and messages filled from YAML as ``ros2 service call`` fills them, against the
rules of Jazzy's rosidl_runtime_py (``rosidl_runtime_py/set_message.py``,
``set_message_fields``): numpy arrays by ``numpy.array(value, dtype)``, ``array.array``
by its typecode, a value of the field's type as it is, others converted by the field's
type, nested messages and sequences of messages from mappings; an unknown field is the
AttributeError of ``getattr``, a value that is no mapping where one is needed the
TypeError ``Value '...' is expected to be a dictionary but is a ...``. The classes are
rclpy's generated ones (pdr_msgs/srv/ApplyCorrection: a Time, scalars, a Point, a
float64[9], sequences of Step and PoseWithCovarianceStamped)."""
from __future__ import annotations

import array

import numpy as np
import pytest
from std_msgs.msg import Float64MultiArray, String

from pdr_core.ros.message_fields import FIELD_ERRORS, set_message_fields, yaml_values
from pdr_msgs.msg import Step
from pdr_msgs.srv import ApplyCorrection


def filled(msg_class, text: str):
    """A ``msg_class`` made as ros2 service call makes its request (setters checking), its
    fields set from the YAML ``text``."""
    msg = msg_class(check_fields=True)
    set_message_fields(msg, yaml_values(text))
    return msg


def test_nested_fields_scalars_and_a_fixed_array_are_set():
    request = filled(ApplyCorrection.Request,
                     "{stamp: {sec: 3, nanosec: 5}, request_id: 7, yaw: 1, yaw_variance: 0.01,"
                     " has_position: true, position: {x: 1.5, y: -2},"
                     " position_covariance: [1, 0, 0, 0, 1, 0, 0, 0, 1]}")
    assert (request.stamp.sec, request.stamp.nanosec, request.request_id) == (3, 5, 7)
    assert request.yaw == 1.0 and isinstance(request.yaw, float)
    assert request.has_position is True
    assert (request.position.x, request.position.y, request.position.z) == (1.5, -2.0, 0.0)
    assert isinstance(request.position_covariance, np.ndarray)
    assert request.position_covariance.tolist() == [1, 0, 0, 0, 1, 0, 0, 0, 1]


def test_empty_values_leave_the_defaults():
    assert filled(ApplyCorrection.Request, "{}") == ApplyCorrection.Request()


def test_sequences_of_messages_are_filled_one_mapping_each():
    response = filled(ApplyCorrection.Response,
                      "{accepted: true, revised_steps: [{index: 4, length: 0.7}, {index: 5}],"
                      " revised_poses: [{header: {frame_id: map},"
                      " pose: {pose: {position: {z: 2.0}}}}]}")
    assert [type(s) for s in response.revised_steps] == [Step, Step]
    assert [s.index for s in response.revised_steps] == [4, 5]
    assert response.revised_steps[0].length == pytest.approx(0.7)
    [pose] = response.revised_poses
    assert pose.header.frame_id == "map" and pose.pose.pose.position.z == 2.0


def test_number_sequences_and_strings_take_the_fields_types():
    data = filled(Float64MultiArray, "{data: [1, 2.5]}")
    assert isinstance(data.data, array.array) and data.data.tolist() == [1.0, 2.5]
    assert filled(String, "{data: 5}").data == "5"


@pytest.mark.parametrize(("text", "error", "words"), [
    ("{yawn: 1.0}", AttributeError, "'ApplyCorrection_Request' object has no attribute 'yawn'"),
    ("{position: {w: 1.0}}", AttributeError, "'Point' object has no attribute 'w'"),
    ("{position: 3}", TypeError, "Value '3' is expected to be a dictionary but is a int"),
    ("[1, 2]", TypeError, "Value '[1, 2]' is expected to be a dictionary but is a list"),
    ("", TypeError, "Value 'None' is expected to be a dictionary but is a NoneType"),
    ("{yaw: abc}", ValueError, "could not convert string to float: 'abc'"),
    ("{position_covariance: [1, 2]}", AssertionError, "must have a size of 9"),
    ("{request_id: -5}", AssertionError, "must be an unsigned integer"),
])
def test_bad_values_raise_the_error_ros2cli_prints(text, error, words):
    with pytest.raises(error, match=words.replace("[", r"\[").replace("]", r"\]")) as raised:
        filled(ApplyCorrection.Request, text)
    assert isinstance(raised.value, FIELD_ERRORS)


def test_a_sequence_of_messages_given_a_number_says_it_is_not_iterable():
    with pytest.raises(TypeError, match="'int' object is not iterable"):
        filled(ApplyCorrection.Response, "{revised_steps: 5}")


def test_text_that_is_not_yaml_is_one_line_naming_the_place():
    with pytest.raises(ValueError) as raised:
        yaml_values("{yaw: [1, 2}")
    assert str(raised.value).startswith("invalid YAML: ")
    assert "(line 1, column " in str(raised.value) and "\n" not in str(raised.value)
