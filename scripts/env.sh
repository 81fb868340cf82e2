# Source this file (bash) to get the workspace environment: the virtual environment with the
# ROS 2 Jazzy wheels as underlay and the colcon install space as overlay.
#   source scripts/env.sh
_ws="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export HEXAPOD_WS="$_ws"
export HEXAPOD_VENV="${HEXAPOD_VENV:-$_ws/.venv}"
# shellcheck disable=SC1091
source "$HEXAPOD_VENV/bin/activate"
# The venv prefix is the ROS underlay: ament index, CMake packages, shared libraries.
export AMENT_PREFIX_PATH="$HEXAPOD_VENV${AMENT_PREFIX_PATH:+:$AMENT_PREFIX_PATH}"
export CMAKE_PREFIX_PATH="$HEXAPOD_VENV${CMAKE_PREFIX_PATH:+:$CMAKE_PREFIX_PATH}"
export LD_LIBRARY_PATH="$HEXAPOD_VENV/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export RMW_IMPLEMENTATION="${RMW_IMPLEMENTATION:-rmw_fastrtps_cpp}"
# Package directories at the repository root (hexapod_gait/, ...) would shadow the installed
# Python packages of the same name when Python puts the current directory on sys.path.
export PYTHONSAFEPATH=1
if [ -f "$_ws/install/local_setup.bash" ]; then
  # shellcheck disable=SC1091
  source "$_ws/install/local_setup.bash"
fi
unset _ws
