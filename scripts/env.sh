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
# MuJoCo renders headless through OSMesa (installed by the bootstrap) unless a backend was chosen
# (MUJOCO_GL=egl on a GPU machine, glfw with a display).
if [ -z "${MUJOCO_GL:-}" ] && [ -z "${DISPLAY:-}" ]; then
  export MUJOCO_GL=osmesa PYOPENGL_PLATFORM=osmesa
fi
# shellcheck disable=SC1091
source "$_ws/scripts/same_floats.sh"
# Package directories at the repository root (hexapod_gait/, ...) would shadow the installed
# Python packages of the same name when Python puts the current directory on sys.path.
export PYTHONSAFEPATH=1
# Fast DDS profile: services wait up to 2 s for a new client to be discovered before they answer
# (hexapod_util/config/fastdds.xml says why). A profile file you chose stays.
export FASTRTPS_DEFAULT_PROFILES_FILE="${FASTRTPS_DEFAULT_PROFILES_FILE:-$_ws/hexapod_util/config/fastdds.xml}"
if [ -f "$_ws/install/local_setup.bash" ]; then
  # shellcheck disable=SC1091
  source "$_ws/install/local_setup.bash"
fi
# The studies (studies/: `python -m studies.STUDY.NAME`) import the library as a package of their own. The
# root goes last, so an installed package always wins over a source directory of the same name.
case ":${PYTHONPATH:-}:" in *":$_ws:"*) ;; *) export PYTHONPATH="${PYTHONPATH:+$PYTHONPATH:}$_ws" ;; esac
unset _ws
# Every executable by its name (generate_map, sim_node, adapt_client, ...): the install space's
# lib/<pkg> directories, where `ros2 run` finds them on a full install.
for _lib in "$HEXAPOD_WS"/install/*/lib/*/; do
  case ":$PATH:" in *":${_lib%/}:"*) ;; *) PATH="${_lib%/}:$PATH" ;; esac
done
unset _lib
export PATH
# Without the ros2 CLI, a `ros2 run <pkg> <exe> [args]` shim with the same layout.
if ! command -v ros2 >/dev/null 2>&1; then
  ros2() {
    if [ "$1" = "run" ] && [ $# -ge 3 ]; then
      local exe="$HEXAPOD_WS/install/$2/lib/$2/$3"
      shift 3
      if [ -x "$exe" ]; then "$exe" "$@"; else echo "ros2 run: no executable $exe" >&2; return 1; fi
    else
      echo "this environment has no ros2 CLI; this shim runs 'ros2 run <package> <executable> [args]'" >&2
      return 2
    fi
  }
fi
