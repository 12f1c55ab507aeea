"""Shared core of the PDR stack: what the navigators, the simulator, the nodes and the
tools share. No module imports rclpy at import time (the node helpers import it inside
their functions or are duck-typed on it), so pdr_core is testable without ROS.

A name is imported from the module that defines it (``from pdr_core.io.bag import
BagReader``): a package's ``__init__`` only indexes its modules and hands no name on.
Each sub-package's docstring indexes its modules, one line each; src/pdr_core/test/
test_index.py fails when a module is missing from its package's index.

Modules (where to look first: errors, configuration, names and units):
    errors        InputError and the CLI error convention (one line naming file and
                  problem).
    config_files  Typed dataclasses from YAML mappings (units in key names), YAML errors
                  as InputError, a package's shipped config/.
    report_files  report.json written and printed one way.
    constants     Physical constants, in one place (SI).
    units         Conversions at the edges (°/√h, µg/√Hz, mg, ...).
    frames        Default frame names of the messages (REP-105, REP-145).
    topics        Topic and service names in bags and on the graph.
    vocabulary    Activities, landmark types and the floor height (the pdr_msgs
                  constants).

Sub-packages:
    io            Messages, bags and files: the typestore, MessageBatch, CDR and MCAP in
                  bulk, bags read, written and recorded, poses as Path, Odometry and /tf,
                  the CSV, phone and OxIOD imports.
    ros           What every node shares (duck-typed on rclpy): main(), parameters, the
                  backlog in blocks, diagnostics, /tf and the map → odom transform.
    sensors       IMU, magnetometer and barometer: the input checks, error models and
                  profiles, Allan deviation, magnetic fields and their calibration, a slow
                  sensor's readings paired with the IMU's samples.
    maths         Attitude conventions, angle wraps, compiled 3 × 3 kernels, the low-pass
                  gain, χ² gates, and numba's cache kept valid across modules.
    walking       What a person can walk: stride and speed bounds, staircases, whether an
                  input looks like a walk, and which navigator it is for.
    corrections   Drift corrections that come late: the value, requests answered once,
                  the states kept and the inputs run again.
    evaluation    Scores against a truth, figures and batch runs: trajectory metrics, NEES,
                  attitude errors, the plots' layout, Dask. No navigator imports it
                  (test/test_code_shape.py).
"""
