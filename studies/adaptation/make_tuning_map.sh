#!/usr/bin/env bash
# The tuning map of issue 19: another seed (2), 2 000 niches and 200 000 MuJoCo evaluations (the
# default map's 100 evaluations per niche). M-BOA's settings are chosen on it and on damage types
# other than S1-S4's lifted legs, never on the default map's S1-S4 experiment.
# Resumable: run it again after an interruption.
set -eo pipefail   # (no -u: colcon's setup scripts read unset variables)
cd "$(dirname "$0")/../.."
source scripts/env.sh
exec nice -n 10 python -m hexapod_adapt.mapping.generate_map_cli \
  --out studies/out/tuning_map_s2.npz --engine mujoco --niches 2000 --evaluations 200000 \
  --seed 2 --with-presets --workers "${WORKERS:-2}" --checkpoint-every 300 --log-every 30 --no-bar --resume
