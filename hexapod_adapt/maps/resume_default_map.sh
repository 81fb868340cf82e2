#!/usr/bin/env bash
# Start or resume the default map (make_default_map.sh) in the background, from a worktree of its
# own at a fixed commit, so that work on the library under it cannot change a run in progress.
#   bash hexapod_adapt/maps/resume_default_map.sh [WORKTREE] [CHECKPOINTS]
# WORKTREE (default ../mapgen) is made if missing, at the commit that started the map
# (CHECKPOINTS/COMMIT, committed; this checkout's HEAD at the first start), and built with this
# checkout's .venv. It resumes from the worktree's checkpoint, or else from the copy in
# CHECKPOINTS (default hexapod_adapt/maps/in_progress: default_map.npz.ckpt.npz, its log and COMMIT,
# all committed: a new machine has only what git has). With neither, a
# new worktree starts the map from scratch (make_default_map.sh with
# FRESH=1: the shipped map and its log are kept there as NAME.bak).
# Output: WORKTREE/out/default_map.out (the run's pid in out/default_map.pid). When it says
# "wrote", copy WORKTREE's hexapod_adapt/maps/default_map.npz and default_map.npz.log.jsonl back;
# before a session ends, `bash scripts/save_progress.sh` stops the run at a checkpoint
# and copies it with the log to in_progress/: commit both (a new machine has no ../mapgen).
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
tree="${1:-$repo/../mapgen}"
keep="${2:-$repo/hexapod_adapt/maps/in_progress}"
set +u  # the setup scripts read unset variables
# shellcheck disable=SC1091
source "$repo/scripts/env.sh" >/dev/null
set -u
# shellcheck disable=SC1091
source "$repo/scripts/map_progress.sh"
if [ "$(cd "$repo" && default_map_shipped)" = yes ]; then
  echo "the default map $repo ships is make_default_map.sh's, finished: nothing to resume"
  exit 0
fi
if [ "$(cd "$repo" && map_finished "$keep/default_map.npz")" = yes ]; then
  echo "the map is finished ($keep/default_map.npz): its ceilings are next (resume_ceilings.sh)"
  exit 0
fi
REPO="$repo" TREE="$tree" PIN_FILE="$keep/COMMIT"
# shellcheck disable=SC1091
source "$repo/scripts/fixed_worktree.sh"
fresh="$FIXED_WORKTREE_NEW"
mkdir -p out
running="$(cat out/default_map.pid 2>/dev/null || true)"
if [ -n "$running" ] && alive "$running"; then
  echo "the default map is already running in $tree (pid $running)"
  exit 0
fi
# the checkpoint and the progress log (its rows are the map's core-hours), committed in
# CHECKPOINTS: taken when the worktree has none (a new one) or an older one (a machine handed
# back after another went further)
here="$(checkpoint_evaluations hexapod_adapt/maps/default_map.npz.ckpt.npz)"
kept="$(checkpoint_evaluations "$keep/default_map.npz.ckpt.npz")"
if [ "$kept" -gt "$here" ]; then
  echo "resuming from $keep ($kept evaluations; the worktree's checkpoint: $here)"
  for name in default_map.npz.ckpt.npz default_map.npz.log.jsonl; do
    if [ -f "$keep/$name" ]; then
      cp "$keep/$name" "hexapod_adapt/maps/$name"
    fi
  done
  fresh=0
fi
FRESH="$fresh" nohup nice -n 10 bash hexapod_adapt/maps/make_default_map.sh >> out/default_map.out 2>&1 &
echo $! > out/default_map.pid  # nohup, nice and bash exec: this is the map's own process
echo "default map running in $tree (pid $!): tail -f $tree/out/default_map.out"
