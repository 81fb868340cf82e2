#!/usr/bin/env bash
# A navigation repertoire of 3-feet gaits only, and its damage bank: compared with the shipped
# repertoire on the tuning goals (docs/navigation.md, "The navigator"), not adopted.
# The exact commands, resumable; run from anywhere.
#   nohup nice -n 10 bash studies/navigation/stance3.sh > out/stance3.out 2>&1 &
# Made 2026-11-23: 128 000 evaluations in 30 min (beside other work), stopped by SIGTERM, then
# resumed from its checkpoint to 150 000 in 5.4 min; the log holds both runs.
set -eo pipefail   # (no -u: colcon's setup scripts read unset variables)
cd "$(dirname "$0")/../.."
source scripts/env.sh
dir=studies/out/navigation_stance3
python -m hexapod_adapt.mapping.generate_map_cli --kind navigation \
  --out "$dir/navigation_map.npz" --cvt-dir hexapod_adapt/maps --engine mujoco --niches 1000 \
  --evaluations 150000 --min-stance-legs 3 --seed 1 --with-presets --workers "${WORKERS:-2}" \
  --checkpoint-every 300 --log-every 30 --no-bar --resume
python -m hexapod_navigation.offline.step_bank_cli --engine mujoco --repertoire "$dir/navigation_map.npz" \
  --out "$dir/navigation_bank.npz" --workers "${WORKERS:-2}"
