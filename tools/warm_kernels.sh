#!/usr/bin/env bash
# Compile the numba kernels into their caches (beside the sources) before pytest starts
# its workers, so that two workers never compile the same kernel at once. It runs the
# offline tools on the sample bags, which reach every compiled module: the foot kernels
# and the pocket and simulator kernels in two processes at once (they share none).
# Skipped while the packages' sources are unchanged since the last warm-up (a stamp in
# install/).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
stamp="install/.numba-warm"
want="$(find src -path '*/test' -prune -o -name '*.py' -print | sort | xargs cat | sha256sum)"
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ]; then
  exit 0
fi
echo "[warm] compiling the numba kernels once (about a minute on a fresh clone)" >&2
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
ws() {  # ./ws quietly; its output only if it fails
  local log="$out/$1-$2-$RANDOM.log"
  ./ws "$@" > "$log" 2>&1 || { cat "$log" >&2; return 1; }
}
foot() {
  ws pdr-ekf run bags/foot_walk --out "$out/segmented" --smoother segmented
  ws pdr-ekf run bags/foot_walk --out "$out/full" --smoother full
  ws pdr-ekf montecarlo --source all --runs 2 --steps 3 \
    --estimator ins,ekf_original,ekf_limited,ekf_retarded --out "$out/montecarlo"
}
pocket() {
  ws pdr-pocket run bags/pocket_walk --out "$out/pocket" --drift online
  # the thesis' unscented filter (filter: thesis), which the tests of its tables run
  ws pdr-pocket run bags/pocket_walk --out "$out/thesis" --drift online \
    --config src/pdr_pocket/config/pocket_pdr_no_mag.yaml
  ws pdr-sim import-csv bags/pyshoe_vicon_2018-02-22-10-10-29.csv --out "$out/no_gyro" \
    --time-col t_s --acc-cols acc_x_mps2,acc_y_mps2,acc_z_mps2
  ws pdr-pocket run "$out/no_gyro" --out "$out/no_gyro_run"
  ws pdr-sim generate --placement pocket --scenario sit_stand --out "$out/sit_stand"
}
foot & foot_pid=$!
pocket & pocket_pid=$!
failed=0
wait "$foot_pid" || failed=1
wait "$pocket_pid" || failed=1
[ "$failed" = 0 ] || exit 1
echo "$want" > "$stamp"
