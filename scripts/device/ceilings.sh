#!/usr/bin/env bash
# The default map's ceilings on the lent 16-core machine (the `device` tool), with the library
# at the commit the ceilings are pinned to (hexapod_adapt/maps/in_progress/ceilings/COMMIT,
# written by resume_ceilings.sh when a new map's ceilings start; the shipped ones were made at
# 2031cb7: hexapod_adapt/maps/ceilings/README.md).
#   bash scripts/device/pack.sh && bash scripts/device/ceilings.sh pack     # here
#   BUDGET=430 KINDS='shortened no_tibia' bash scripts/device/ceilings.sh run   # there, as the
#     command of a `run` that carries .whl and .devrun (the working tree must be under 64 MiB:
#     move studies/out/map_study out of the checkout for the call, then back)
# 'pack' archives the pinned library into .devrun/ceilsrc and copies the cases kept so far into
# .devrun/done, so the machine skips them. 'run' first recomputes one case kept here (leg 4
# locked, CHECK) to compare, then the KINDS' missing cases until BUDGET seconds, and leaves
# everything in one $OUT/res.tar (a call returns at most 8 files). Unpack it here and copy the
# new ceil/*.npz into in_progress/ceilings and ../ceilgen's cache.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
keep=hexapod_adapt/maps/in_progress/ceilings
case "${1:-}" in
  pack)
    rm -rf .devrun/ceilsrc .devrun/done
    mkdir -p .devrun/ceilsrc .devrun/done
    git archive "$(cat "$keep/COMMIT")" hexapod_adapt hexapod_sim hexapod_description \
      hexapod_gait | tar x -C .devrun/ceilsrc --exclude='hexapod_adapt/maps/*'
    cp "$keep"/*.npz .devrun/done/
    du -sh .devrun .whl
    ;;
  run)
    # shellcheck disable=SC1091
    SRC="$PWD/.devrun/ceilsrc" source scripts/device/setup.sh
    python3 -c "import numpy, mujoco; print('numpy', numpy.__version__, 'mujoco', mujoco.__version__)"
    map="$PWD/hexapod_adapt/maps/default_map.npz"
    mkdir -p /tmp/check /tmp/ceil
    cp .devrun/done/*.npz /tmp/ceil/
    trap 'tar cf "$OUT/res.tar" -C /tmp check ceil' EXIT
    cd /tmp
    python3 -m hexapod_adapt.online.ceilings_cli --archive "$map" --engine mujoco \
      --damage "${CHECK:-4:locked}" --cache-dir /tmp/check --workers 16
    # shellcheck disable=SC2086  # KINDS is a list
    timeout --signal=INT "${BUDGET:-400}" python3 -m hexapod_adapt.online.ceilings_cli \
      --archive "$map" --engine mujoco --scenarios S1 S2 S3 S4 --damage-kind ${KINDS:-shortened} \
      --cache-dir /tmp/ceil --workers 16 || true
    ;;
  *) echo "usage: $0 pack|run" >&2; exit 2 ;;
esac
