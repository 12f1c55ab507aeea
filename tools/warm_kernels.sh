#!/usr/bin/env bash
# Compile the numba kernels into their caches (beside the sources) before pytest starts
# its workers, so that two workers never compile the same kernel at once. It runs the
# offline tools on the sample bags, which reach every compiled module, in two processes
# at once: the foot's and the simulator's kernels, then the pocket's without a gyroscope;
# and the pocket's two filters.
# Skipped while the packages' sources are unchanged since the last warm-up (a stamp in
# install/). Says what it compiles and about how long it takes before it starts, then each
# command as it starts ("[warm foot 1/6] ...") and each kernel compiled, with its seconds
# (pdr_core.maths.kernel_cache.CompileProgress, on through PDR_COMPILE_PROGRESS); a command's
# other output only if it fails.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
stamp="install/.numba-warm"
want="$(find src -path '*/test' -prune -o -name '*.py' -print | sort | xargs cat | sha256sum)"
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ]; then
  exit 0
fi
started=$SECONDS
echo "[warm] compiling the numba kernels to machine code once, into caches beside the" \
  "sources: the foot navigator's and the simulator's (pdr_ins_ekf, pdr_sim) and, at the" \
  "same time, the pocket navigator's (pdr_pocket); about 75 s on a fresh clone," \
  "seconds after an edit" >&2
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
export PDR_COMPILE_PROGRESS=1
ws() {  # ws GROUP K N CMD...: says "[warm GROUP K/N] CMD", runs ./ws CMD and passes on
  # the kernels it compiles; its whole output only if it fails
  local group="$1" k="$2" n="$3" log="$out/$RANDOM.log"
  shift 3
  echo "[warm $group $k/$n] $*" >&2
  local status=0
  ./ws "$@" 2>&1 | tee "$log" | { grep --line-buffered '^\[numba\]' || true; } \
    | sed -u "s/^\[numba\]/[warm $group]/" >&2 || status=$?
  [ "$status" = 0 ] || { cat "$log" >&2; return 1; }
}
foot() {
  ws foot 1 6 pdr-ekf run bags/foot_walk --out "$out/segmented" --smoother segmented
  ws foot 2 6 pdr-ekf run bags/foot_walk --out "$out/full" --smoother full
  ws foot 3 6 pdr-ekf montecarlo --source all --runs 2 --steps 3 \
    --estimator ins,ekf_original,ekf_limited,ekf_retarded --out "$out/montecarlo"
  # the simulator's kernels (pdr_sim) and the pocket's without a gyroscope here, where
  # the foot's end before the pocket's: the pocket's kernels these reach were compiled
  # by the pocket's first command meanwhile
  ws foot 4 6 pdr-sim generate --placement pocket --scenario sit_stand --out "$out/sit_stand"
  ws foot 5 6 pdr-sim import-csv bags/pyshoe_vicon_2018-02-22-10-10-29.csv \
    --out "$out/no_gyro" --time-col t_s --acc-cols acc_x_mps2,acc_y_mps2,acc_z_mps2
  ws foot 6 6 pdr-pocket run "$out/no_gyro" --out "$out/no_gyro_run"
}
pocket() {
  ws pocket 1 2 pdr-pocket run bags/pocket_walk --out "$out/pocket" --drift online
  # the thesis' unscented filter (filter: thesis), which the tests of its tables run
  ws pocket 2 2 pdr-pocket run bags/pocket_walk --out "$out/thesis" --drift online \
    --config src/pdr_pocket/config/pocket_pdr_no_mag.yaml
}
foot & foot_pid=$!
pocket & pocket_pid=$!
failed=0
wait "$foot_pid" || failed=1
wait "$pocket_pid" || failed=1
[ "$failed" = 0 ] || exit 1
echo "$want" > "$stamp"
echo "[warm] done in $((SECONDS - started)) s" >&2
