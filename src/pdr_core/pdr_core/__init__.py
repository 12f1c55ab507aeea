"""Shared core of the PDR stack: bags, messages, configuration, constants and the pieces
both navigators use. No module imports rclpy at import time (the node helpers import it
inside their functions or are duck-typed on it), so pdr_core is testable without ROS.

Modules:
  Errors, configuration, names and units
    errors                    InputError and the CLI error convention (one line naming
                              file and problem).
    config_files              Typed dataclasses from YAML mappings (units in key names),
                              YAML errors as InputError, a package's shipped config/.
    report_files              report.json written and printed one way.
    constants                 Physical constants, in one place (SI).
    units                     Conversions at the edges (°/√h, µg/√Hz, mg, ...).
    frames                    Default frame names of the messages (REP-105, REP-145).
    topics                    Topic and service names in bags and on the graph.
    vocabulary                Activities, landmark types and the floor height (the
                              pdr_msgs constants).
  Messages and bags
    msgtypes                  The rosbags typestore: ROS 2 Jazzy types plus pdr_msgs.
    batch                     MessageBatch: a topic's messages as NumPy arrays.
    cdr                       Vectorised CDR encoding and decoding of fixed-layout messages.
    mcap_bulk                 Vectorised MCAP writes and indexed reads of fixed-size messages.
    bag                       Reading and writing rosbag2 bags in MCAP storage.
    recording                 A bag written as it is recorded: a crash loses at most the
                              last second.
    headers                   std_msgs/Header stamps to and from nanoseconds.
    nav_path                  nav_msgs/Path to and from pose batches.
    csv_import                A CSV IMU log as Imu and PoseStamped batches.
    csv_export                A bag's topics as a phone-style CSV log, each at its rows.
    phone_import              A phone's own export, one CSV per sensor, as batches.
  Nodes (duck-typed on rclpy, or importing it inside a function)
    node_main                 The main() every node shares: init, spin, clean shutdown.
    node_params               Node parameters declared one way, with descriptors.
    node_wiring               The start-up log line: a node's resolved topic and service names.
    backlog                   A subscription's backlog taken in one callback, and blocks
                              published as the reliable subscribers acknowledge them.
    ros_types                 ROS type names to their rclpy message classes.
    diagnostics               A navigator's health from its counters: OK, WARN or ERROR
                              with the reason (no rclpy).
    node_diagnostics          /diagnostics at 1 Hz for a node (diagnostic_msgs).
    node_tf                   A navigator's pose on /tf (tf2_msgs, REP-105).
  IMU and magnetometer data
    imu_checks                The checks every navigator runs on IMU data, and the CSV
                              importer's unit checks.
    imu_errors                Sensor error models applied to whole signals and runs.
    imu_profiles              Named IMU profiles and their configuration keys.
    allan                     Overlapping Allan deviation and the noise parameters on it.
    magnetic_field            Homogeneous and cylinder-perturbed fields, iron distortion.
    magnetometer_calibration  Hard/soft-iron calibration by ellipsoid fitting.
    magnetometer_pairing      Each IMU sample paired with its latest magnetometer reading.
    sample_pairing            A slow sensor's readings on the IMU's samples, each once;
                              a faster sensor's mean over each sample's interval.
    walk_plausibility         Whether a navigator's input looks like a walk (the first
                              line's warnings, --strict), EXIT_REFUSED.
    navigator_choice          The foot or the pocket navigator, told from the IMU alone.
    atmosphere                Pressure and height: the standard atmosphere's formula.
    barometry                 The barometer's limits and the kinds of height change.
  Attitude and compiled kernels
    rotations                 Attitude conventions (ENU/FLU, ZYX Euler), conversions, the
                              tilt from specific force.
    angles                    The angle wrap (plain and compiled), the axial wrap, the
                              circular mean.
    small_matrix              Compiled (numba) kernels for 3 × 3 rotations and small
                              symmetric positive-definite matrices.
    kernel_cache              Keeps numba's on-disk cache valid when a kernel's callee in
                              another module changes.
    lowpass                   The first-order low-pass's gains (exact, backward and forward
                              Euler) and decay, one spelling for every kernel.
  Corrections
    correction                A drift correction as one value, sender to filter.
    answered_requests         A request sent again answered as the first time: the
                              navigators' answers by request id, the sender's new ids.
    checkpoints               A navigator's state kept at past instants with the inputs
                              since: a late correction taken there and the inputs run
                              again (robot_localization's revertTo).
  Evaluation and figures
    gait                      What a person can walk: the stride bound at a cadence, the
                              walking speed limit.
    metrics                   Trajectory error metrics: the report.json fields
                              (docs/reports.md).
    consistency               NEES of position and attitude against a truth: is the
                              covariance honest?
    plot_layout               Titles, top views and height axes shared by every PNG.
"""
