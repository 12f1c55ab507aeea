#!/usr/bin/env bash
# make demo: the foot pipeline end to end through the live ROS 2 graph.
#   1. pdr-sim generate simulates the built-in long mixed walk (Xsens MTw errors, 100 Hz)
#      with PNGs of the trajectory and the signals;
#   2. ros2 launch of the foot graph on it (pdr_sim/launch/replay.launch.xml with
#      pdr_ins_ekf/launch/foot.launch.xml): bag_play publishes its imu/data as fast as the
#      subscribers keep up; zupt_ekf navigates on it; bag_record records pdr/foot/pose and
#      pdr/foot/stance (three processes);
#   3. pdr-ekf evaluate prints the report against the ground truth and writes a PNG.
# Run through `make demo`, which bootstraps and sets up the environment first.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$root/out/demo"
config="$root/src/pdr_ins_ekf/config/foot_ekf.yaml"
export ROS_DOMAIN_ID="${ROS_DOMAIN_ID:-$((RANDOM % 100 + 1))}"
# shellcheck source=tools/replay.sh
source "$root/tools/replay.sh"
rm -rf "$out" && mkdir -p "$out"

echo "== 1. simulate the built-in long mixed walk"
"$root/ws" pdr-sim generate --scenario long_mixed_walk --imu xsens_mtw --rate 100 --seed 1 \
  --out "$out/simulated" --plot "$out"

echo "== 2. bag_play -> zupt_ekf -> bag_record over ROS 2 (domain $ROS_DOMAIN_ID)"
# zupt_ekf holds back its detector's look-ahead: that many samples stay unpublished.
expected=$(python - "$out/simulated" "$config" <<'PY'
import sys
from pdr_core.io.bag import BagReader
from pdr_ins_ekf.config import load_run_config
from pdr_ins_ekf.zero_velocity import sample_rate_hz
imu = BagReader(sys.argv[1]).read("/imu/data")
lag = load_run_config(sys.argv[2]).detector.context(sample_rate_hz(imu.stamp_ns))[1]
print(2 * (len(imu) - lag))
PY
)
replay "$out/launch.log" package:=pdr_ins_ekf graph:=foot.launch.xml bag:="$out/simulated" \
  out:="$out/live" play:="[/imu/data]" record:="[pdr/foot/pose, pdr/foot/stance]" \
  max_messages:="$expected" config:="$config" imu_durability:=transient_local

echo "== 3. report against the ground truth"
"$root/ws" pdr-ekf evaluate "$out/live" --truth "$out/simulated" --plot "$out/estimate.png"

echo "== 4. the pocket graph with the drift loop (pdr_drift/launch/pocket_drift.launch.xml):"
echo "      bag_play -> pocket_pdr <-> landmark_drift -> bag_record"
pocket="$out/pocket" && mkdir -p "$pocket"
# without magnetometer updates (the thesis' setting): the heading has no reference but
# the landmarks
no_mag="$root/src/pdr_pocket/config/pocket_pdr_no_mag.yaml"
"$root/ws" pdr-sim generate --placement pocket --scenario block_two_laps \
  --imu thesis_table_6_1 --seed 1 --out "$pocket/simulated"
"$root/ws" pdr-pocket run "$pocket/simulated" --config "$no_mag" --out "$pocket/alone" \
  > /dev/null
"$root/ws" pdr-pocket run "$pocket/simulated" --config "$no_mag" --out "$pocket/offline" \
  --drift online > "$pocket/report.json"
# a path per step and one again per accepted correction (its steps run again)
expected=$(python -c "import json,sys; r=json.load(open(sys.argv[1])); d=r['drift']
print(2 * r['steps'] + d['landmarks'] + d['associations'] + d['corrections_accepted'])" \
  "$pocket/report.json")
replay "$pocket/launch.log" package:=pdr_drift graph:=pocket_drift.launch.xml \
  bag:="$pocket/simulated" out:="$pocket/live" \
  record:="[pdr/pocket/pose, pdr/pocket/path, pdr/landmarks, pdr/drift]" \
  max_messages:="$expected" config:="$no_mag" imu_durability:=transient_local
grep -h "\[landmark_drift.*correction \(accepted\|refused\)" "$pocket/launch.log" | tail -n 3
python - "$pocket" <<'PY'
import sys
from pathlib import Path
import numpy as np
from pdr_core.io.bag import BagReader
from pdr_core.io.nav_path import last_path
from pdr_drift.plots import paths_png
folder = Path(sys.argv[1])
sim = BagReader(folder / "simulated")
steps = sim.read("/ground_truth/step")
truth = np.c_[np.cumsum(steps["length"] * np.cos(steps["heading"])),
              np.cumsum(steps["length"] * np.sin(steps["heading"]))]
alone = BagReader(folder / "alone").read("/pdr/pocket/pose")["pose.pose.position"][:, :2]
live = BagReader(folder / "live")
# the navigator's last path: the steps a correction ran again in their final place
corrected = last_path(live, "/pdr/pocket/path")["pose.position"][:, :2]
marks = live.read("/pdr/landmarks")["position"][:, :2]
drift = live.read("/pdr/drift")
start = np.zeros((1, 2))
poses = live.read("/pdr/pocket/pose").stamp_ns
applied = corrected[np.searchsorted(poses, drift.stamp_ns)]
paths_png(np.r_[start, corrected], np.r_[start, alone], marks, folder / "corrections.png",
          "block_two_laps", truth=np.r_[start, truth],
          corrected_label="with landmark_drift's corrections",
          uncorrected_label="pocket_pdr alone", corrections=applied,
          shows="a phone in the pocket, two laps of a block, the live graph")
end = lambda p: np.linalg.norm(p[-1] - truth[-1])
print(f"{len(marks)} landmarks, {len(drift)} revisit(s): drift "
      + ", ".join(f"{np.degrees(d):+.4f}" for d in drift["drift"]) + " deg/s; final error "
      f"{end(alone):.2f} m alone, {end(corrected):.2f} m with the corrections")
PY
echo "plots: $out/trajectory.png $out/signals.png $out/estimate.png $pocket/corrections.png"
