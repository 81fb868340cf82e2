#!/usr/bin/env bash
# Keep the long runs' progress in the repository before a session ends: a machine may be new
# next session, and a checkpoint left outside git is lost with it (2026-11-25: 851,002 evaluations
# of the default map were).
#   bash scripts/save_progress.sh [MAP_WORKTREE] [CEILING_WORKTREE] [CHECKPOINTS]
# then commit what it lists.
# - The default map running in MAP_WORKTREE (default ../mapgen, resume_default_map.sh) is stopped
#   right after its next checkpoint (within --checkpoint-every, 300 s), so that the saved
#   checkpoint and the saved log end together: the log loses at most the time since its last
#   row (--log-every, 30 s), and no work past the checkpoint is thrown away. Its checkpoint and
#   log go to CHECKPOINTS (default hexapod_adapt/maps/in_progress), where
#   resume_default_map.sh resumes from. Once the map is written, it goes there instead
#   (default_map.npz and its log), to ship with its ceilings.
# - The ceilings' finished cases in CEILING_WORKTREE (default ../ceilgen, resume_ceilings.sh) go
#   to CHECKPOINTS/ceilings; the run goes on (a case in progress is recomputed on resume).
# - The navigation rounds' finished units in NAV_TREE (worktrees, separated by spaces; default
#   ../navtune and every ../navtune-GRID, tuning/tune_all_kinds.sh) go to NAV_KEEP (default
#   tuning/navigation_all_kinds); the rounds go on (a unit in progress is walked again).
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
map_tree="${1:-$repo/../mapgen}"
ceil_tree="${2:-$repo/../ceilgen}"
keep="${3:-$repo/hexapod_adapt/maps/in_progress}"
if [ -n "${NAV_TREE:-}" ]; then
  read -ra nav_trees <<< "$NAV_TREE"  # one or more, separated by spaces
else
  nav_trees=("$repo/../navtune" "$repo"/../navtune-*)
fi
nav_keep="${NAV_KEEP:-$repo/tuning/navigation_all_kinds}"
set +u  # the setup scripts read unset variables
# shellcheck disable=SC1091
source "$repo/scripts/env.sh" >/dev/null
set -u
# shellcheck disable=SC1091
source "$repo/scripts/map_progress.sh"

copy_atomic() {  # copy_atomic SRC DEST: DEST is never seen half written
  cp "$1" "$2.tmp.$$" && mv -f "$2.tmp.$$" "$2"
}

copy_whole_rows() {  # copy_whole_rows LOG DEST: LOG up to its last whole row (a row being
  # written is torn), written atomically
  python3 - "$1" "$2" <<'EOF'
import os, sys
data = open(sys.argv[1], 'rb').read()
tmp = sys.argv[2] + '.tmp'
with open(tmp, 'wb') as out:
    out.write(data[: data.rfind(b'\n') + 1])
os.replace(tmp, sys.argv[2])
EOF
}

maps="$map_tree/hexapod_adapt/maps"
ckpt="$maps/default_map.npz.ckpt.npz"
pidfile="$map_tree/out/default_map.pid"
if [ "$(cd "$repo" && map_finished "$maps/default_map.npz")" = yes ] \
  && cmp -s "$maps/default_map.npz" "$repo/hexapod_adapt/maps/default_map.npz"; then
  echo "the finished map is the one this checkout ships: nothing to save"
elif [ "$(cd "$repo" && map_finished "$maps/default_map.npz")" = yes ]; then
  # written: kept beside the checkpoint until it ships with its ceilings (resume_ceilings.sh
  # computes them from this copy on a new machine)
  mkdir -p "$keep"
  copy_atomic "$maps/default_map.npz" "$keep/default_map.npz"
  copy_atomic "$maps/default_map.npz.log.jsonl" "$keep/default_map.npz.log.jsonl"
  echo "saved the finished map and its log to $keep"
elif [ -f "$ckpt" ]; then
  pid="$(cat "$pidfile" 2>/dev/null || true)"
  if [ -n "$pid" ] && alive "$pid"; then
    before="$(stat -c %Y "$ckpt")"
    echo "waiting for the map's next checkpoint (pid $pid)..."
    for _ in $(seq 400); do
      [ "$(stat -c %Y "$ckpt")" != "$before" ] && break
      sleep 1
    done
    kill -TERM "$pid"
    while alive "$pid"; do sleep 1; done
    echo "map stopped after its checkpoint"
  fi
  here="$(checkpoint_evaluations "$ckpt")"
  kept="$(checkpoint_evaluations "$keep/default_map.npz.ckpt.npz")"
  if [ "$here" -lt "$kept" ]; then
    echo "not saved: $keep holds a checkpoint further on ($kept evaluations) than $map_tree ($here)" >&2
    exit 1
  fi
  mkdir -p "$keep"
  copy_atomic "$ckpt" "$keep/default_map.npz.ckpt.npz"
  # the log up to its last whole row (a row being written is torn)
  copy_whole_rows "$maps/default_map.npz.log.jsonl" "$keep/default_map.npz.log.jsonl"
  echo "saved the map's checkpoint ($here evaluations, $(du -h "$keep/default_map.npz.ckpt.npz" | cut -f1)) and log to $keep"
fi

if [ -d "$ceil_tree/hexapod_adapt/maps/ceilings" ]; then
  mkdir -p "$keep/ceilings"
  n=0
  for f in "$ceil_tree"/hexapod_adapt/maps/ceilings/*.npz; do
    [ -f "$f" ] || continue
    [ -f "$repo/hexapod_adapt/maps/ceilings/$(basename "$f")" ] && continue  # shipped already
    # the worktree's own checkout (an older map's shipped cases), not computed there
    git -C "$ceil_tree" ls-files --error-unmatch "${f#"$ceil_tree"/}" >/dev/null 2>&1 && continue
    copy_atomic "$f" "$keep/ceilings/$(basename "$f")"
    n=$((n + 1))
  done
  echo "saved $n ceiling cases to $keep/ceilings"
fi

# a unit is finished once its summary.json, written last, is there; its episodes (runs.csv) and
# summary are kept, not its paths (about 0.3 MB a unit, for plots only)
for nav_tree in "${nav_trees[@]}"; do
  [ -d "$nav_tree" ] || continue
  n=0
  for summary in "$nav_tree"/tuning/navigation_all_kinds/*/*/summary.json; do
    [ -f "$summary" ] || continue
    unit="$(dirname "$summary")"
    dest="$nav_keep/$(basename "$(dirname "$unit")")/$(basename "$unit")"
    [ -f "$dest/summary.json" ] && continue
    rm -rf "$dest.tmp"
    mkdir -p "$dest.tmp"
    cp "$unit/runs.csv" "$unit/summary.json" "$dest.tmp/" && mv "$dest.tmp" "$dest"
    n=$((n + 1))
  done
  echo "saved $n new navigation units from $nav_tree to $nav_keep"
done
# The transfer study (tuning/transfer_study.sh, worktree TRANSFER_TREE, default ../transfer-study):
# each run's checkpoint and log (the log up to its last whole row), and a finished map. The run
# goes on; a checkpoint is written atomically, so the copy is a whole one. Its checkpoints are
# several MB: git ignores them (.gitignore); they survive where the machine does, and a run
# without one starts again from its seed.
transfer_tree="${TRANSFER_TREE:-$repo/../transfer-study}"
if [ -d "$transfer_tree/tuning/transfer_study" ]; then
  mkdir -p "$repo/tuning/transfer_study"
  for f in "$transfer_tree"/tuning/transfer_study/walk_*.npz*; do
    [ -f "$f" ] || continue
    case "$f" in
      *.tmp*) continue ;;
      *.log.jsonl)
        copy_whole_rows "$f" "$repo/tuning/transfer_study/$(basename "$f")"
        ;;
      *) copy_atomic "$f" "$repo/tuning/transfer_study/$(basename "$f")" ;;
    esac
    echo "saved $(basename "$f") ($(du -h "$f" | cut -f1)) to tuning/transfer_study"
  done
fi
echo "now commit them (git add the folders above)"
