#!/usr/bin/env bash
# The default map (make_default_map.sh) continued on the lent 16-core machine (the `device` tool),
# from the checkpoint kept here, with the library at the map's pinned commit
# (hexapod_adapt/maps/in_progress/COMMIT). First stop the map here at a checkpoint
# (scripts/save_progress.sh), then:
#   bash scripts/device/pack.sh && bash scripts/device/map.sh pack        # here
#   bash scripts/device/map.sh run 480    # there: the command of a `run` carrying .whl, .devrun
#   bash scripts/device/map.sh unpack /work/.device/N                      # here, then resume
# The working tree must be under 64 MiB for the call: move hexapod_adapt/maps,
# hexapod_navigation/maps and docs/navigation out of the checkout for it, then back.
# 'run' works SECONDS seconds and keeps what its last checkpoint holds (--checkpoint-every 60 there):
# --lag 64 --chunk 8 are the map's identity, so 8 chunks are in flight and 8 workers are all it
# can use. 'unpack' drops the log's rows past the checkpoint (work the stop threw away) and
# puts the checkpoint and log in in_progress/, which resume_default_map.sh takes as further on.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
keep=hexapod_adapt/maps/in_progress
src=.devrun/mapsrc
case "${1:-}" in
  pack)
    rm -rf "$src"
    mkdir -p "$src"
    git archive "$(cat "$keep/COMMIT")" hexapod_adapt hexapod_sim hexapod_description \
      hexapod_gait hexapod_util | tar x -C "$src" --exclude='hexapod_adapt/maps/*'
    mkdir -p "$src/hexapod_adapt/maps"
    cp hexapod_adapt/maps/centroids_20000_6.dat "$keep/default_map.npz.ckpt.npz" \
      "$keep/default_map.npz.log.jsonl" "$src/hexapod_adapt/maps/"
    du -sh .devrun .whl
    ;;
  run)
    # shellcheck disable=SC1091
    SRC="$PWD/$src" source scripts/device/setup.sh
    export OPENBLAS_CORETYPE=Haswell OPENBLAS_L2_SIZE=512  # as make_default_map.sh
    python3 -c "import numpy, mujoco; print('numpy', numpy.__version__, 'mujoco', mujoco.__version__)"
    cd "$src"
    trap 'cp hexapod_adapt/maps/default_map.npz* "$OUT/"' EXIT
    timeout --signal=TERM "${2:-480}" python3 -m hexapod_adapt.mapping.generate_map_cli \
      --out hexapod_adapt/maps/default_map.npz --engine mujoco --niches 20000 \
      --evaluations 1000000 --seed 1 --with-presets --emitters iso_line --workers 8 --lag 64 \
      --chunk 8 --checkpoint-every 60 --log-every 30 --no-bar --resume || true
    ;;
  unpack)
    from="${2:?usage: map.sh unpack FILES_AT, the folder the run call returned}"
    set +u  # the setup scripts read unset variables
    # shellcheck disable=SC1091
    source scripts/env.sh >/dev/null  # checkpoint_evaluations reads the file with numpy
    set -u
    # shellcheck disable=SC1091
    source scripts/map_progress.sh
    n="$(checkpoint_evaluations "$from/default_map.npz.ckpt.npz")"
    kept="$(checkpoint_evaluations "$keep/default_map.npz.ckpt.npz")"
    if [ "$n" -le "$kept" ]; then  # never replace a checkpoint further on
      echo "not unpacked: $keep holds $kept evaluations, $from only $n" >&2
      exit 1
    fi
    python3 - "$from/default_map.npz.log.jsonl" "$n" "$keep/default_map.npz.log.jsonl" <<'PY'
import json, os, sys
rows = [r for r in open(sys.argv[1]).read().splitlines()
        if r and json.loads(r)['evaluations'] <= int(sys.argv[2])]
with open(sys.argv[3] + '.tmp', 'w') as out:
    out.write('\n'.join(rows) + '\n')
os.replace(sys.argv[3] + '.tmp', sys.argv[3])
PY
    cp "$from/default_map.npz.ckpt.npz" "$keep/default_map.npz.ckpt.npz.tmp"
    mv -f "$keep/default_map.npz.ckpt.npz.tmp" "$keep/default_map.npz.ckpt.npz"
    chmod u+w "$keep"/default_map.npz*
    echo "checkpoint at $n evaluations in $keep: bash hexapod_adapt/maps/resume_default_map.sh"
    ;;
  *) echo "usage: $0 pack|run [SECONDS]|unpack FILES_AT" >&2; exit 2 ;;
esac
