#!/usr/bin/env bash
# The default map's ceilings on the lent 16-core machine (the `device` tool), with the library
# at the commit the ceilings are pinned to (hexapod_adapt/maps/in_progress/ceilings/COMMIT,
# written by resume_ceilings.sh when a new map's ceilings start; the shipped ones were made at
# 2031cb7: hexapod_adapt/maps/ceilings/README.md). The map: in_progress/default_map.npz while
# one is kept there (a map written, not shipped yet), else the shipped one.
#   bash scripts/device/pack.sh && bash scripts/device/ceilings.sh pack     # here
#   BUDGET=500 KINDS='locked weak' bash scripts/device/ceilings.sh run   # there, as the
#     command of a `run` that carries .whl and .devrun (the working tree must be under 64 MiB)
# 'pack' archives the pinned library into .devrun/ceilsrc and copies the cases kept so far into
# .devrun/done, so the machine skips them. 'run' first walks again 160 gaits of a case kept here
# (S1 leg 1 lifted, CHECK) and compares (recheck.py: a few seconds), then computes the KINDS'
# missing cases until BUDGET seconds, and leaves them in one $OUT/res.tar (a call returns at
# most 8 files). Unpack it here (tar xf res.tar) and copy the new ceil/*.npz into
# ../ceilgen's cache, and into in_progress/ceilings (a map not shipped yet) or the shipped
# cache, packed (ceilings_cli --cache-dir hexapod_adapt/maps/ceilings --pack); name them in
# that folder's README.md.
# Seen 2026-11-28: 74-84 s a case of the 6,758-gait map at 4 steps per row, 16 workers.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
keep=hexapod_adapt/maps/in_progress/ceilings
case "${1:-}" in
  pack)
    rm -rf .devrun/ceilsrc .devrun/done
    mkdir -p .devrun/ceilsrc .devrun/done
    git archive "$(cat "$keep/COMMIT")" hexapod_adapt hexapod_sim hexapod_description \
      hexapod_gait hexapod_util | tar x -C .devrun/ceilsrc --exclude='hexapod_adapt/maps/*'
    # the cases made so far: kept loose (a map not shipped yet) or packed in the shipped cache
    cp "$keep"/*.npz .devrun/done/ 2>/dev/null || true
    for pack in hexapod_adapt/maps/ceilings/ceilings_*.zip; do
      [ -f "$pack" ] && unzip -qo "$pack" -d .devrun/done
    done
    du -sh .devrun .whl
    ;;
  run)
    # shellcheck disable=SC1091
    SRC="$PWD/.devrun/ceilsrc" source scripts/device/setup.sh
    python3 -c "import numpy, mujoco; print('numpy', numpy.__version__, 'mujoco', mujoco.__version__)"
    map="$PWD/hexapod_adapt/maps/in_progress/default_map.npz"
    [ -f "$map" ] || map="$PWD/hexapod_adapt/maps/default_map.npz"
    mkdir -p /tmp/ceil
    cp .devrun/done/*.npz /tmp/ceil/
    trap 'tar cf "$OUT/res.tar" -C /tmp ceil' EXIT
    python3 scripts/device/recheck.py "$map" "$PWD/.devrun/done" "${CHECK:-1:lifted}" 16 \
      | tee "$OUT/check.txt"
    cd /tmp
    # shellcheck disable=SC2086  # KINDS is a list
    timeout --signal=INT "${BUDGET:-400}" python3 -m hexapod_adapt.online.ceilings_cli \
      --archive "$map" --engine mujoco --scenarios S1 S2 S3 S4 --damage-kind ${KINDS:-shortened} \
      --cache-dir /tmp/ceil --workers 16 || true
    ;;
  *) echo "usage: $0 pack|run" >&2; exit 2 ;;
esac
