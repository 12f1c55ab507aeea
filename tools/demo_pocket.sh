#!/usr/bin/env bash
# make demo-pocket: the pocket pipeline end to end through the live ROS 2 graph.
#   1. pdr-sim generate simulates UP/DW of Muñoz Díaz 2016 (40 m, four floors up a
#      staircase and down again, a phone in the front pocket, Xsens MTw errors);
#   2. ros2 launch of the pocket graph on it (pdr_sim/launch/replay.launch.xml with
#      pdr_pocket/launch/pocket.launch.xml): bag_play publishes its imu/data and imu/mag as
#      fast as the subscribers keep up; pocket_pdr navigates with the filter for that
#      sensor (config/pocket_pdr_xsens_mtw.yaml); bag_record records pdr/pocket/step and
#      pdr/pocket/pose (three processes);
#   3. pdr-pocket run navigates the same bag offline for the report against the truth
#      (steps, activities, distance and riser errors, floors) and its PNG, and the live
#      poses are checked against it.
# Run through `make demo-pocket`, which bootstraps and sets up the environment first.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$root/out/demo_pocket"
export ROS_DOMAIN_ID="${ROS_DOMAIN_ID:-$((RANDOM % 100 + 1))}"
# shellcheck source=tools/replay.sh
source "$root/tools/replay.sh"
rm -rf "$out" && mkdir -p "$out"

echo "== 1. simulate UP/DW with a phone in the front pocket"
"$root/ws" pdr-sim generate --placement pocket --scenario up_dw --imu xsens_mtw --seed 1 \
  --out "$out/simulated"

echo "== 2. bag_play -> pocket_pdr -> bag_record over ROS 2 (domain $ROS_DOMAIN_ID)"
config="$root/src/pdr_pocket/config/pocket_pdr_xsens_mtw.yaml"
"$root/ws" pdr-pocket run "$out/simulated" --out "$out/offline" --config "$config" --plot \
  > "$out/report.json"
steps=$(python -c "import json,sys; print(json.load(open(sys.argv[1]))['steps'])" \
  "$out/report.json")
replay "$out/launch.log" package:=pdr_pocket graph:=pocket.launch.xml bag:="$out/simulated" \
  out:="$out/live" record:="[pdr/pocket/step, pdr/pocket/pose]" \
  max_messages:="$((2 * steps))" config:="$config" imu_durability:=transient_local

echo "== 3. report against the ground truth"
python - "$out" <<'PY'
import json, sys
from pathlib import Path
import numpy as np
from pdr_core.io.bag import BagReader
out = Path(sys.argv[1])
report = json.loads((out / "report.json").read_text())
live = BagReader(out / "live").read("/pdr/pocket/pose")["pose.pose.position"]
offline = BagReader(out / "offline").read("/pdr/pocket/pose")["pose.pose.position"]
print(f"steps {report['steps']} of {report['true_steps']} true ({report['missed_steps']} "
      f"missed, {report['false_steps']} false), activities right "
      f"{report['activity_correct_pct']:.1f} %")
print(f"distance error {report['distance_error_pct']:+.2f} %, floors: highest "
      f"{report['highest_floor']} (true {report['true_highest_floor']}), final "
      f"{report['final_floor']}, riser errors per flight "
      + ", ".join(f"{r['error_pct']:+.1f}" for r in report["staircase_riser_error_pct"]) + " %")
print(f"final error {report['final_error_m']:.2f} m; live poses equal the offline run's to "
      f"{np.abs(live - offline).max():.1e} m")
PY
echo "plot: $out/offline/path.png"
