"""A ``ros2`` command for a workspace whose ROS 2 comes from PyPI wheels, which carry rclpy
but not ros2cli (issue 58; docs/studies/issue58_ros2_cli.md). Not ros2cli: a few of its
verbs, with its syntax and output format; where a real ``ros2`` is on the PATH, that one
runs instead (tools/env.sh appends this package's lib/pdr_ros2 to the PATH, after any
ROS install's bin).

Modules:
    command      The ``ros2`` console script: stepping aside for a real ros2, the
                 argparse tree of the commands below.
    cli_parsers  Shared argparse shapes: a command's verbs, a graph verb's --spin-time.
    cli_run      ``ros2 run PKG EXE``: the executable's path, executed in place.
    cli_node     ``ros2 node`` verbs.
    cli_topic    ``ros2 topic`` verbs.
    cli_service  ``ros2 service`` verbs.
    graph        The CLI's hidden node after its discovery wait; ``node list``,
                 ``topic list`` and ``service list`` lines.
    topic_echo   ``ros2 topic echo``: the topic's type from the graph, ros2cli's QoS
                 choice, messages as YAML or CSV.
    topic_hz     ``ros2 topic hz``: a topic's reception rate every second of messages.
    topic_info   ``ros2 topic info [-v]``: a topic's type, publishers and subscriptions.
    service_call  ``ros2 service call``: a request filled from YAML, sent once, the
                  request and the response printed.
"""
