#!/usr/bin/env bash
# The default navigation repertoire (docs/navigation.md): the exact command, resumable. Run it
# from the repository root; run it again after any interruption (it resumes from
# navigation_map.npz.ckpt.npz) until it prints "wrote".
#   nohup nice -n 10 bash hexapod_navigation/maps/make_navigation_map.sh > out/navigation_map.out 2>&1 &
# On a bigger machine set WORKERS (the map does not depend on the worker count).
set -eo pipefail   # (no -u: colcon's setup scripts read unset variables)
cd "$(dirname "$0")/../.."
source scripts/env.sh
exec python -m hexapod_adapt.mapping.generate_map_cli --kind navigation \
  --out hexapod_navigation/maps/navigation_map.npz --engine mujoco --niches 1000 --evaluations 300000 \
  --seed 1 --with-presets --workers "${WORKERS:-2}" --checkpoint-every 300 --log-every 30 --no-bar --resume
