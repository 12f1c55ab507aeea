#!/usr/bin/env bash
# Run any node or CLI of the workspace from a plain shell:
#   ./ws <executable> [args]     e.g. ./ws pdr-sim import-csv ..., ./ws bag_play --ros-args ...
# Bootstraps if needed (tools/bootstrap.sh) and sets up the environment (tools/env.sh).
# Node executables are looked up in install/<pkg>/lib/<pkg>/, as `ros2 run` does.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if [ $# -eq 0 ]; then
  echo "usage: ./ws <executable> [args]" >&2
  exit 2
fi
"$root/tools/bootstrap.sh"
# shellcheck disable=SC1091
source "$root/tools/env.sh"
exe="$1"; shift
for dir in "$root"/install/*/lib/*/; do
  if [ -x "$dir$exe" ] && [ -f "$dir$exe" ]; then
    exec "$dir$exe" "$@"
  fi
done
exec "$exe" "$@"
