"""rclpy nodes of pdr_sim: thin adapters over pdr_core and the simulator core.

- :mod:`bag_play`: publishes a bag's messages with their recorded timing;
- :mod:`imu_sim`: publishes a simulated walk live, as ``pdr-sim generate`` writes it;
- :mod:`playback`: the timed publishing both share (and ``/clock``);
- :mod:`bag_record`: writes graph topics to an MCAP bag as they arrive;
"""
