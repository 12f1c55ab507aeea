"""Messages as ``ros2 topic echo`` prints them, against text written from the rules of
Jazzy's rosidl_runtime_py (ros2/rosidl_runtime_py ``rosidl_runtime_py/convert.py``,
commit 06724e3c): ``message_to_yaml`` = ``yaml.dump(message_to_ordereddict(msg, ...),
allow_unicode=True, width=sys.maxsize, default_flow_style=False)`` with an OrderedDict
representer on PyYAML's default Dumper; ``_convert_value``: ``numpy.number`` ->
``.item()``, sequences -> lists cut at ``truncate_length`` with ``'...'`` as last item,
strings cut with ``...`` appended, bytes as ``chr``-joined strings; ``message_to_csv``:
``str(val)`` of every leaf, arrays flattened, ``'...'`` after ``truncate_length`` items.
ros2cli's ``ros2topic/verb/echo.py`` (``DEFAULT_TRUNCATE_LENGTH = 128``) prints the YAML
with ``end='---\\n'`` and the CSV with ``print``. Float spelling is PyYAML's
``represent_float`` (yaml/representer.py): ``repr`` lowered, ``.0`` before an exponent
without a dot, ``.nan``, ``.inf``. The real messages are rclpy's generated classes."""
from __future__ import annotations

from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu
from std_msgs.msg import Byte, Float32MultiArray, Float64MultiArray

from pdr_core.ros.message_yaml import message_csv, message_yaml
from pdr_msgs.msg import Step

ZEROS9 = "- 0.0\n" * 9

IMU_YAML = f"""\
header:
  stamp:
    sec: 1
    nanosec: 500000000
  frame_id: imu_link
orientation:
  x: 0.0
  y: 0.0
  z: 0.0
  w: 1.0
orientation_covariance:
- -1.0
- 0.0
- 0.0
- 0.0
- 0.0
- 0.0
- 0.0
- 0.0
- 0.0
angular_velocity:
  x: 1.0e-05
  y: .nan
  z: .inf
angular_velocity_covariance:
{ZEROS9}\
linear_acceleration:
  x: 9.81
  y: -0.5
  z: 1.0e+17
linear_acceleration_covariance:
{ZEROS9}"""

IMU_CSV = ("1,500000000,imu_link,0.0,0.0,0.0,1.0,-1.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,"
           "1e-05,nan,inf,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,9.81,-0.5,1e+17,"
           "0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0")


def imu() -> Imu:
    msg = Imu()
    msg.header.stamp.sec, msg.header.stamp.nanosec = 1, 500_000_000
    msg.header.frame_id = "imu_link"
    msg.orientation_covariance[0] = -1.0
    msg.angular_velocity.x, msg.angular_velocity.y = 1e-05, float("nan")
    msg.angular_velocity.z = float("inf")
    msg.linear_acceleration.x, msg.linear_acceleration.y = 9.81, -0.5
    msg.linear_acceleration.z = 1e17
    return msg


def test_an_imu_message_is_nested_maps_in_field_order_with_pyyaml_floats():
    assert message_yaml(imu()) == IMU_YAML


def test_an_imu_message_as_csv_is_its_leaves_as_python_str():
    assert message_csv(imu()) == IMU_CSV


def test_odometry_cut_short_ends_its_covariances_with_a_quoted_ellipsis():
    """truncate_length 3: strings cut with ``...``, arrays of 36 cut to 3 + ``'...'``, a
    list inside a map not indented; a string that reads as a number is quoted."""
    msg = Odometry(child_frame_id="1")
    msg.header.frame_id = "odom_frame"
    msg.pose.pose.position.x = 0.7312
    msg.twist.covariance[0] = 0.01
    assert message_yaml(msg, truncate_length=3) == """\
header:
  stamp:
    sec: 0
    nanosec: 0
  frame_id: odo...
child_frame_id: '1'
pose:
  pose:
    position:
      x: 0.7312
      y: 0.0
      z: 0.0
    orientation:
      x: 0.0
      y: 0.0
      z: 0.0
      w: 1.0
  covariance:
  - 0.0
  - 0.0
  - 0.0
  - '...'
twist:
  twist:
    linear:
      x: 0.0
      y: 0.0
      z: 0.0
    angular:
      x: 0.0
      y: 0.0
      z: 0.0
  covariance:
  - 0.01
  - 0.0
  - 0.0
  - '...'
"""
    assert message_csv(msg, truncate_length=3) == (
        "0,0,odo...,1,0.7312,0.0,0.0,0.0,0.0,0.0,1.0,0.0,0.0,0.0,...,"
        "0.0,0.0,0.0,0.0,0.0,0.0,0.01,0.0,0.0,...")


def test_odometry_in_full_has_its_36_covariance_items():
    text = message_yaml(Odometry(), truncate_length=None)
    assert text.count("  - 0.0\n") == 72 and "..." not in text


def test_a_sequence_is_cut_at_echos_default_of_128_items():
    msg = Float64MultiArray(data=[float(i) for i in range(130)])
    items = "".join(f"- {i}.0\n" for i in range(128))
    assert message_yaml(msg) == f"layout:\n  dim: []\n  data_offset: 0\ndata:\n{items}- '...'\n"
    assert message_csv(msg) == ",0," + ",".join(f"{i}.0" for i in range(128)) + ",..."


def test_a_float32_prints_as_the_double_it_is():
    msg = Float32MultiArray(data=[0.1, 2.5])
    assert message_yaml(msg) == ("layout:\n  dim: []\n  data_offset: 0\n"
                                 "data:\n- 0.10000000149011612\n- 2.5\n")
    assert message_csv(msg) == ",0,0.10000000149011612,2.5"


def test_a_byte_is_its_character_in_yaml_and_its_bytes_repr_in_csv():
    assert message_yaml(Byte(data=b"A")) == "data: A\n"
    assert message_csv(Byte(data=b"A")) == "b'A'"


def test_the_projects_step_message():
    msg = Step(index=7, length=0.72, heading=-1.5707963267948966, duration=0.5,
               activity=Step.UPSTAIRS, ride=Step.RIDE_NONE)
    msg.header.frame_id = "map"
    assert message_yaml(msg) == """\
header:
  stamp:
    sec: 0
    nanosec: 0
  frame_id: map
index: 7
length: 0.72
vertical_displacement: 0.0
heading: -1.5707963267948966
pitch_max: 0.0
pitch_min: 0.0
pitch_amplitude: 0.0
duration: 0.5
activity: 2
ride: 0
ride_height: 0.0
"""
    assert message_csv(msg) == "0,0,map,7,0.72,0.0,-1.5707963267948966,0.0,0.0,0.0,0.5,2,0,0.0"
