#!/usr/bin/env bash
# The default map: the exact command, resumable. Run it from the repository root; run it again
# after any interruption (it resumes from default_map.npz.ckpt.npz) until it prints "wrote".
#   nohup nice -n 10 bash hexapod_adapt/maps/make_default_map.sh > out/default_map.out 2>&1 &
# On a bigger machine set WORKERS (the map does not depend on the worker count).
set -eo pipefail   # (no -u: colcon's setup scripts read unset variables)
cd "$(dirname "$0")/../.."
source scripts/env.sh
exec python -m hexapod_adapt.mapping.generate_map_cli \
  --out hexapod_adapt/maps/default_map.npz --engine mujoco --niches 10000 --evaluations 1000000 \
  --seed 1 --with-presets --workers "${WORKERS:-2}" --checkpoint-every 300 --log-every 30 --no-bar --resume
