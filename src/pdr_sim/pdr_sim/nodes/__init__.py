"""rclpy nodes of pdr_sim: thin adapters over pdr_core and the simulator core."""
