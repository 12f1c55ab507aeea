#!/usr/bin/env bash
# make demo: the foot pipeline end to end through the live ROS 2 graph.
#   1. pdr-sim generate simulates the built-in long mixed walk (Xsens MTw errors, 100 Hz)
#      with PNGs of the trajectory and the signals;
#   2. bag_play publishes its imu/data as fast as the subscribers keep up; zupt_ekf
#      navigates on it; bag_record records pdr/foot/pose and pdr/foot/stance
#      (three processes);
#   3. pdr-ekf evaluate prints the report against the ground truth and writes a PNG.
# Run through `make demo`, which bootstraps and sets up the environment first.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$root/out/demo"
config="$root/src/pdr_ins_ekf/config/foot_ekf.yaml"
export ROS_DOMAIN_ID="${ROS_DOMAIN_ID:-$((RANDOM % 100 + 1))}"
rm -rf "$out" && mkdir -p "$out"

echo "== 1. simulate the built-in long mixed walk"
"$root/ws" pdr-sim generate --scenario long_mixed_walk --imu xsens_mtw --rate 100 --seed 1 \
  --out "$out/simulated" --plot "$out"

echo "== 2. bag_play -> zupt_ekf -> bag_record over ROS 2 (domain $ROS_DOMAIN_ID)"
# zupt_ekf holds back its detector's look-ahead: that many samples stay unpublished.
expected=$(python - "$out/simulated" "$config" <<'PY'
import sys
from pdr_core.bag import BagReader
from pdr_ins_ekf.config import load_run_config
lag = load_run_config(sys.argv[2]).detector.context[1]
print(2 * (len(BagReader(sys.argv[1]).read("/imu/data")) - lag))
PY
)
"$root/ws" bag_record --ros-args -p out:="$out/estimated" \
  -p "topics:=[pdr/foot/pose, pdr/foot/stance]" -p max_messages:="$expected" \
  > "$out/bag_record.log" 2>&1 &
recorder=$!
"$root/ws" zupt_ekf --ros-args -p config:="$config" -p imu_durability:=transient_local \
  > "$out/zupt_ekf.log" 2>&1 &
node=$!
# start playing once the recorder listens to the navigator's outputs
for _ in $(seq 600); do
  grep -q "recording /pdr/foot/stance" "$out/bag_record.log" && \
    grep -q "recording /pdr/foot/pose" "$out/bag_record.log" && break
  sleep 0.1
done
"$root/ws" bag_play --ros-args -p bag:="$out/simulated" -p "topics:=[/imu/data]" \
  -p rate:=0.0 -p wait_for_subscribers:=1
wait "$recorder"
kill -INT "$node" && wait "$node" || true
tail -n 2 "$out/bag_record.log"

echo "== 3. report against the ground truth"
"$root/ws" pdr-ekf evaluate "$out/estimated" --truth "$out/simulated" --plot "$out/estimate.png"
echo "plots: $out/trajectory.png $out/signals.png $out/estimate.png"
