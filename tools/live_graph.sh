# Sourced by the demo scripts: play a bag through nodes into bag_record, over ROS 2.
#   live_graph OUT_DIR BAG TOPICS_TO_PLAY TOPICS_TO_RECORD MAX_MESSAGES RATE NODE [NODE ...]
# Starts bag_record (OUT_DIR/live) and every NODE ("name --ros-args ..."), waits until
# the recorder listens to every recorded topic, plays BAG at RATE times real time (0: as
# fast as the subscribers keep up), waits for MAX_MESSAGES to be recorded and stops the
# nodes. Logs go to OUT_DIR.
# SIGINT a node and wait for it; a node that is still running 10 s later gets SIGINT again
# (seen once in the tests: zupt_ekf kept spinning after its first SIGINT, and exited at
# once on the second; the cause is open).
stop_node() {
  kill -INT "$1" 2>/dev/null || return 0
  for _ in $(seq 100); do
    kill -0 "$1" 2>/dev/null || break
    sleep 0.1
  done
  if kill -0 "$1" 2>/dev/null; then kill -INT "$1"; fi
  wait "$1" || true
}

live_graph() {
  local out="$1" bag="$2" play="$3" record="$4" max="$5" rate="$6"
  shift 6
  "$root/ws" bag_record --ros-args -p out:="$out/live" -p "topics:=$record" \
    -p max_messages:="$max" > "$out/bag_record.log" 2>&1 &
  local recorder=$! nodes=() spec
  for spec in "$@"; do
    # shellcheck disable=SC2086
    "$root/ws" $spec > "$out/${spec%% *}.log" 2>&1 &
    nodes+=($!)
  done
  local topic
  for topic in $(echo "$record" | tr -d '[],'); do
    for _ in $(seq 600); do
      grep -q "recording /$topic" "$out/bag_record.log" && break
      sleep 0.1
    done
  done
  "$root/ws" bag_play --ros-args -p bag:="$bag" -p "topics:=$play" -p rate:="$rate" \
    -p wait_for_subscribers:=1
  wait "$recorder"
  local node
  for node in "${nodes[@]}"; do
    stop_node "$node"
  done
  tail -n 1 "$out/bag_record.log"
}
