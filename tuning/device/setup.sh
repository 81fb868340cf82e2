# shellcheck shell=bash
# Source on the lent machine, from the repository root, after tuning/device/pack.sh here:
# installs the carried packages into /tmp/site and puts the workspace's Python packages on the
# path (the map tools need no ROS). Then e.g.
#   python3 -m tuning.map_study run --workers 16
# A CVT of a new niche count takes minutes to compute there: carry its centroids_*.dat.
mkdir -p /tmp/site
if [ ! -d /tmp/site/mujoco ]; then
  tar xJf .devrun/mujoco_slim.tar.xz -C /tmp/site
  python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade \
    --target /tmp/site .whl/*.whl
fi
export PYTHONPATH="/tmp/site:$PWD/hexapod_adapt:$PWD/hexapod_sim:$PWD/hexapod_description:$PWD/hexapod_gait:$PWD"
export PYTHONUNBUFFERED=1 OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1
