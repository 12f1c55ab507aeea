#!/usr/bin/env bash
# make figures: regenerate the PNGs of docs/img/ from the demo and the CLIs' plot options
# (built-in scenarios, fixed seeds), reduced to 64-colour palettes to keep them small.
# Run through `make figures`, which bootstraps and sets up the environment first.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
img="$root/docs/img"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$img"

echo "== the demo (README picture, simulator.md)"
"$root/tools/demo.sh" > "$work/demo.log"
demo="$root/out/demo"
cp "$demo/estimate.png" "$work/demo.png"
cp "$demo/trajectory.png" "$work/trajectory.png"
cp "$demo/pocket/corrections.png" "$work/drift.png"
"$root/tools/demo_pocket.sh" > "$work/demo_pocket.log"
cp "$root/out/demo_pocket/offline/path.png" "$work/pocket_path.png"

echo "== a pocket walk (simulator.md)"
"$root/ws" pdr-sim generate --placement pocket --scenario up_dw --out "$work/up_dw" \
  --plot "$work/up_dw_png" > /dev/null
cp "$work/up_dw_png/pocket.png" "$work/pocket.png"
"$root/ws" pdr-sim generate --placement pocket --scenario theresienhoehe \
  --imu thesis_table_6_1 --out "$work/theresienhoehe" > /dev/null
"$root/ws" pdr-pocket attitude "$work/theresienhoehe" --out "$work/attitude" --plot > /dev/null
cp "$work/attitude/attitude.png" "$work/attitude.png"

echo "== smoothing (smoothing.md) and a VICON trial (foot_ins.md)"
"$root/ws" pdr-ekf run "$demo/simulated" --out "$work/smoothed" --smoother segmented --plot > /dev/null
cp "$work/smoothed/smoothing.png" "$work/smoothing.png"
"$root/ws" pdr-sim import-csv "${PDR_SHARED_DATA:-$root/../shared/data}/foot/pyshoe_vicon/2017-11-22-11-22-03.csv" \
  --out "$work/vicon" --time-col t_s --acc-cols acc_x_mps2,acc_y_mps2,acc_z_mps2 \
  --gyro-cols gyr_x_radps,gyr_y_radps,gyr_z_radps --pos-cols gt_x_m,gt_y_m,gt_z_m \
  --pos-axes=-x,y,z > /dev/null
"$root/ws" pdr-ekf run "$work/vicon" --out "$work/vicon_ekf" --plot > /dev/null
cp "$work/vicon_ekf/path.png" "$work/vicon_path.png"

echo "== error analysis (error_analysis.md)"
"$root/ws" pdr-ekf montecarlo --source all --runs 200 --steps 83 --out "$work/mc" > /dev/null
cp "$work/mc/growth.png" "$work/growth.png"
"$root/ws" pdr-ekf study mechanization --out "$work/mech" > /dev/null
cp "$work/mech/mechanization.png" "$work/mechanization.png"

python - "$work" "$img" <<'PY'
import sys
from pathlib import Path

from PIL import Image

work, img = Path(sys.argv[1]), Path(sys.argv[2])
for name in ("demo", "trajectory", "pocket", "attitude", "smoothing", "vicon_path",
             "growth", "mechanization", "drift", "pocket_path"):
    picture = Image.open(work / f"{name}.png").convert("RGB")
    picture.convert("P", palette=Image.Palette.ADAPTIVE, colors=64).save(
        img / f"{name}.png", optimize=True)
    print(f"{img / f'{name}.png'}: {(img / f'{name}.png').stat().st_size // 1024} KiB")
PY
