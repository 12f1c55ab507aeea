# Sourced by ./ws and the Makefile: the environment of the built workspace.
# Pitfall 5 of ../shared/ROS_JAZZY_FROM_PYPI.md: the venv prefix must be on
# AMENT_PREFIX_PATH before install/setup.bash extends it.
_pdr_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck disable=SC1091
source "$_pdr_root/.venv/bin/activate"
export AMENT_PREFIX_PATH="$_pdr_root/.venv${AMENT_PREFIX_PATH:+:$AMENT_PREFIX_PATH}"
export CMAKE_PREFIX_PATH="$_pdr_root/.venv${CMAKE_PREFIX_PATH:+:$CMAKE_PREFIX_PATH}"
export RMW_IMPLEMENTATION="${RMW_IMPLEMENTATION:-rmw_fastrtps_cpp}"
set +u
# shellcheck disable=SC1091
source "$_pdr_root/install/setup.bash"
unset _pdr_root
