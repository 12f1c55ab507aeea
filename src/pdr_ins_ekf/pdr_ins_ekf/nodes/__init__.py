"""rclpy nodes of pdr_ins_ekf: thin adapters over the streaming navigator."""
