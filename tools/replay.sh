# Sourced by the demo scripts: a graph's launch file on a bag, over ROS 2.
#   replay LOG NAME:=VALUE ...
# Runs `ros2 launch pdr_sim replay.launch.xml NAME:=VALUE ...` (bag_play, the graph's
# launch file, bag_record; docs/ros2.md) with its lines in LOG, and prints the
# recorder's last words; on a failure, the whole log.
replay() {
  local log="$1"
  shift
  if ! "$root/ws" ros2 launch pdr_sim replay.launch.xml "$@" > "$log" 2>&1; then
    cat "$log"
    return 1
  fi
  grep -o "recorded [0-9]* messages.*" "$log"
}
