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
# `ros2` (pdr_ros2, issue 58) appended, not prepended: a real ROS 2's ros2 comes first.
case ":$PATH:" in
  *":$_pdr_root/install/pdr_ros2/lib/pdr_ros2:"*) ;;
  *) export PATH="$PATH:$_pdr_root/install/pdr_ros2/lib/pdr_ros2" ;;
esac
unset _pdr_root
