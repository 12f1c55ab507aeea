#!/usr/bin/env bash
# make demo: a simulated foot walk through the live ROS graph.
#   1. pdr-sim generate simulates the built-in long mixed walk (Xsens MTw errors, 100 Hz)
#      and writes its bag, with PNGs of the trajectory and the signals;
#   2. bag_play (one process) publishes it over ROS 2 as fast as the subscriber keeps up,
#      and bag_record (another process) records imu/data, imu/mag and ground_truth/pose;
#   3. the recording is summarised and checked to equal the simulation, message for message.
# (The foot EKF, zupt_ekf, joins this pipeline with its issue.)
# Run through `make demo`, which bootstraps and sets up the environment first.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$root/out/demo"
export ROS_DOMAIN_ID="${ROS_DOMAIN_ID:-$((RANDOM % 100 + 1))}"
rm -rf "$out" && mkdir -p "$out"

echo "== 1. simulate the built-in long mixed walk"
"$root/ws" pdr-sim generate --scenario long_mixed_walk --imu xsens_mtw --rate 100 --seed 1 \
  --out "$out/simulated" --plot "$out"

echo "== 2. bag_play -> bag_record over ROS 2 (domain $ROS_DOMAIN_ID)"
"$root/ws" bag_record --ros-args -p out:="$out/recorded" \
  -p "topics:=[imu/data, imu/mag, ground_truth/pose]" > "$out/bag_record.log" 2>&1 &
recorder=$!
"$root/ws" bag_play --ros-args -p bag:="$out/simulated" -p rate:=0.0 -p wait_for_subscribers:=1
kill -INT "$recorder" && wait "$recorder"
cat "$out/bag_record.log"

echo "== 3. result"
"$root/ws" pdr-sim info "$out/recorded"
python - "$out/simulated" "$out/recorded" <<'PY'
import sys
from pdr_core.bag import BagReader
sent, got = (list(BagReader(p).raw_messages()) for p in sys.argv[1:])
key = lambda m: (m.log_time_ns, m.topic)
same = sorted(sent, key=key) == sorted(got, key=key)
print(f"recorded {len(got)} of {len(sent)} messages, bit for bit identical: {same}")
sys.exit(0 if same else 1)
PY
echo "plots: $out/trajectory.png $out/signals.png"
