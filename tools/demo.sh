#!/usr/bin/env bash
# make demo (workspace stage): a real foot-mounted IMU walk through the live ROS graph.
#   1. pdr-sim import-csv turns the x-io walk of ../shared/data into a bag;
#   2. bag_record (one process) records what bag_play (another process) publishes;
#   3. both bags are summarised, and the recording is checked to equal the input.
# Run through `make demo`, which bootstraps and sets up the environment first.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$root/out/demo"
csv="$root/../shared/data/foot/xio_gait_tracking/short_walk.csv"
export ROS_DOMAIN_ID="${ROS_DOMAIN_ID:-$((RANDOM % 100 + 1))}"
rm -rf "$out" && mkdir -p "$out"

echo "== 1. import $csv"
"$root/ws" pdr-sim import-csv "$csv" --out "$out/input" --time-col "Time (s)" \
  --acc-cols "Accelerometer X (g),Accelerometer Y (g),Accelerometer Z (g)" --acc-unit g \
  --gyro-cols "Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s)" --gyro-unit deg/s \
  --drop-duplicates

echo "== 2. bag_play -> bag_record over ROS 2 (domain $ROS_DOMAIN_ID), rate 10x"
"$root/ws" bag_record --ros-args -p out:="$out/recorded" -p "topics:=[imu/data]" \
  > "$out/bag_record.log" 2>&1 &
recorder=$!
"$root/ws" bag_play --ros-args -p bag:="$out/input" -p rate:=10.0 -p wait_for_subscribers:=1
kill -INT "$recorder" && wait "$recorder"
cat "$out/bag_record.log"

echo "== 3. result"
"$root/ws" pdr-sim info "$out/input"
"$root/ws" pdr-sim info "$out/recorded"
python - "$out/input" "$out/recorded" <<'PY'
import sys
from pdr_core.bag import BagReader
sent, got = (BagReader(p).read("/imu/data") for p in sys.argv[1:])
same = len(sent) == len(got) and (sent.stamp_ns == got.stamp_ns).all() and all(
    (sent[k] == got[k]).all() for k in sent.fields)
print(f"recorded {len(got)} of {len(sent)} messages, identical: {same}")
sys.exit(0 if same else 1)
PY
