# shellcheck shell=bash
# Source on the lent machine, from the repository root, after scripts/device/pack.sh here:
# installs the carried packages into /tmp/site and puts the workspace's Python packages on the
# path (the map tools need no ROS). Then e.g.
#   python3 -m studies.map_methods.map_study run --workers 16
# A CVT of a new niche count takes minutes to compute there: carry its centroids_*.dat.
mkdir -p /tmp/site
if [ ! -d /tmp/site/mujoco ]; then
  tar xJf .devrun/mujoco_slim.tar.xz -C /tmp/site
  python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade \
    --target /tmp/site .whl/*.whl
fi
src="${SRC:-$PWD}"  # the workspace's packages: this checkout, or SRC (e.g. an archived commit)
export PYTHONPATH="/tmp/site:$src/hexapod_adapt:$src/hexapod_sim:$src/hexapod_description:$src/hexapod_gait:$src/hexapod_util:$src"
# shellcheck disable=SC1091
source scripts/same_floats.sh  # numpy's AVX2 kernels, as on the project's machines
export PYTHONUNBUFFERED=1 OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1
