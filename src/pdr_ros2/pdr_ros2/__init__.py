"""A ``ros2`` command for a workspace whose ROS 2 comes from PyPI wheels, which carry rclpy
but not ros2cli (issue 58; docs/ros2.md). Not ros2cli: a few of its
verbs, with its syntax and output format; where a real ``ros2`` is on the PATH, that one
runs instead (tools/env.sh appends this package's lib/pdr_ros2 to the PATH, after any
ROS install's bin).

Modules:
    command      The ``ros2`` console script: stepping aside for a real ros2, the
                 argparse tree of the commands below.
    cli_parsers  Shared argparse shapes: the parser whose errors name this stand-in, a
                 command's verbs, a graph verb's --spin-time.
    cli_run      ``ros2 run PKG EXE``: the executable's path, executed in place.
    cli_node     ``ros2 node`` verbs.
    cli_topic    ``ros2 topic`` verbs.
    cli_service  ``ros2 service`` verbs.
    cli_param    ``ros2 param`` verbs.
    cli_bag      ``ros2 bag`` verbs.
    cli_launch   ``ros2 launch PKG FILE [name:=value ...]``: the file in the package's
                 share folder, its arguments, ``-s``.
    graph        The CLI's hidden node after its discovery wait; the graph's node
                 names; ``node list``, ``topic list`` and ``service list`` lines.
    topic_echo   ``ros2 topic echo``: the topic's type from the graph, ros2cli's QoS
                 choice, messages as YAML or CSV.
    topic_hz     ``ros2 topic hz``: a topic's reception rate every second of messages.
    topic_info   ``ros2 topic info [-v]``: a topic's type, publishers and subscriptions.
    service_call  ``ros2 service call``: a request filled from YAML, sent once, the
                  request and the response printed.
    param_verbs  ``ros2 param list/get/set/dump``: rclpy's parameter client on the
                 hidden node, ros2param's errors.
    param_text   What they print: ``param get``'s labels, ``list`` lines, ``dump``'s
                 YAML (pure).
    bag_verbs    ``ros2 bag info`` from a bag's metadata.yaml (pdr_core.io.bag);
                 ``play``/``record`` execute pdr_sim's bag_play/bag_record in place.
    bag_info_text  rosbag2's ``bag info`` text from a bag's metadata (pure).
    bag_nodes    bag_play's and bag_record's ``--ros-args -p`` for the bag verbs'
                 options, the default name of a recorded bag (pure).
    launch_description  A launch file of the XML or YAML front end read, as launch_xml
                 reads it, into the processes it starts (pure).
    launch_substitutions  ``$(var)``, ``$(find-pkg-share)``, ``$(env)``, ... (pure).
    launch_runner  Starting, watching and stopping a launch's processes, with ros2
                 launch's lines and its SIGINT, SIGTERM, SIGKILL escalation.
"""
