#!/usr/bin/env bash
# Start or resume the default map (make_default_map.sh) in the background, from a worktree of its
# own at a fixed commit, so that work on the library under it cannot change a run in progress.
#   bash hexapod_adapt/maps/resume_default_map.sh [WORKTREE] [CHECKPOINTS]
# WORKTREE (default ../mapgen) is made at this checkout's HEAD if missing and built with this
# checkout's .venv. It resumes from the worktree's checkpoint, or else from the copy in
# CHECKPOINTS (default hexapod_adapt/maps/in_progress, committed: default_map.npz.ckpt.npz and
# its log). With neither, a new worktree starts the map from scratch (make_default_map.sh with
# FRESH=1: the shipped map and its log are kept there as NAME.bak).
# Output: WORKTREE/out/default_map.out (the run's pid in out/default_map.pid). When it says
# "wrote", copy WORKTREE's hexapod_adapt/maps/default_map.npz and default_map.npz.log.jsonl back;
# before a session ends, `bash hexapod_adapt/maps/save_progress.sh` stops the run at a checkpoint
# and copies it with the log to in_progress/: commit them (a new machine has no ../mapgen).
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
tree="${1:-$repo/../mapgen}"
keep="${2:-$repo/hexapod_adapt/maps/in_progress}"
REPO="$repo" TREE="$tree"
# shellcheck disable=SC1091
source "$repo/scripts/fixed_worktree.sh"
fresh="$FIXED_WORKTREE_NEW"
mkdir -p out
# the checkpoint and the progress log (its rows are the map's core-hours), kept outside git:
# a worktree without a checkpoint of its own (a new one too) resumes from CHECKPOINTS' copies
if [ ! -f hexapod_adapt/maps/default_map.npz.ckpt.npz ] \
  && [ -f "$keep/default_map.npz.ckpt.npz" ]; then
  for kept in default_map.npz.ckpt.npz default_map.npz.log.jsonl; do
    if [ -f "$keep/$kept" ]; then
      cp "$keep/$kept" "hexapod_adapt/maps/$kept"
    fi
  done
  fresh=0
fi
FRESH="$fresh" nohup nice -n 10 bash hexapod_adapt/maps/make_default_map.sh >> out/default_map.out 2>&1 &
echo $! > out/default_map.pid  # nohup, nice and bash exec: this is the map's own process
echo "default map running in $tree (pid $!): tail -f $tree/out/default_map.out"
