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
#   to CHECKPOINTS/ceilings, or, once their map has shipped (ship_map.sh), into the shipped cache
#   (hexapod_adapt/maps/ceilings), packed; the run goes on. A case in progress keeps the gaits it
#   has walked in a walking_*.npz file (every minute): that goes to CHECKPOINTS/ceilings, and
#   resume_ceilings.sh takes it up. The shipped cache's README gets its table of the cases held
#   (make_ceilings.sh --summary).
# - The transfer study's runs in TRANSFER_TREE (default ../transfer-study,
#   studies/transfer/transfer_study.sh): each checkpoint and log to studies/checkpoints/
#   transfer_study/ (a checkpoint only when it is further on than the one kept there); a
#   finished map and its log to studies/out/transfer_study/, and its checkpoint is then dropped
#   (TRANSFER_KEEP and TRANSFER_DONE name other folders). The runs go on.
# - The robust-speed study in ROBUST_TREE (default ../robust-study): see its block below.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
map_tree="${1:-$repo/../mapgen}"
ceil_tree="${2:-$repo/../ceilgen}"
keep="${3:-$repo/hexapod_adapt/maps/in_progress}"
set +u  # the setup scripts read unset variables
# shellcheck disable=SC1091
source "$repo/scripts/env.sh" >/dev/null
set -u
# shellcheck disable=SC1091
source "$repo/scripts/map_progress.sh"

copy_atomic() {  # copy_atomic SRC DEST: DEST is never seen half written
  cp "$1" "$2.tmp.$$" && mv -f "$2.tmp.$$" "$2"
}

copy_compressed() {  # copy_compressed NPZ DEST: the same arrays, compressed (a map's empty
  # niches are NaN rows: a 20,000-niche checkpoint keeps in a fraction of its size), atomically
  python -c 'import sys; from hexapod_util.npz import compress_npz; compress_npz(*sys.argv[1:])' \
    "$1" "$2"
}

copy_whole_rows() {  # copy_whole_rows LOG DEST: LOG up to its last whole row, atomically
  python -c 'import sys, hexapod_util.files as f; f.copy_whole_rows(*sys.argv[1:])' "$1" "$2"
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
  # the written map supersedes the checkpoint it was resumed from: nothing resumes a finished run
  rm -f "$keep/default_map.npz.ckpt.npz"
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
  copy_compressed "$ckpt" "$keep/default_map.npz.ckpt.npz"
  # the log up to its last whole row (a row being written is torn)
  copy_whole_rows "$maps/default_map.npz.log.jsonl" "$keep/default_map.npz.log.jsonl"
  echo "saved the map's checkpoint ($here evaluations, $(du -h "$keep/default_map.npz.ckpt.npz" | cut -f1)) and log to $keep"
fi

if [ -d "$ceil_tree/hexapod_adapt/maps/ceilings" ]; then
  shipped_maps="${SHIPPED_MAPS:-$repo/hexapod_adapt/maps}"  # (another folder in the tests)
  shipped_cache="$shipped_maps/ceilings"
  if cmp -s "$ceil_tree/hexapod_adapt/maps/default_map.npz" "$shipped_maps/default_map.npz"; then
    dest="$shipped_cache"  # the shipped map's: its cache takes them, packed, as they finish
  else
    dest="$keep/ceilings"  # a map not shipped yet: kept until it ships with them
  fi
  mkdir -p "$dest"
  # the cases the shipped cache holds, loose or packed
  shipped_names="$(python -m hexapod_adapt.online.ceilings_cli --cache-dir "$shipped_cache" --list)"
  n=0
  # the case in progress: its walking file (one kept from a case since finished goes)
  rm -f "$keep"/ceilings/walking_*.npz
  for f in "$ceil_tree"/hexapod_adapt/maps/ceilings/walking_*.npz; do
    [ -f "$f" ] || continue
    finished="$(basename "$f")"
    finished="${finished#walking_}"
    if grep -qxF "$finished" <<< "$shipped_names" || [ -f "$(dirname "$f")/$finished" ]; then
      rm -f "$f"  # its case is cached: a copy taken up from here after it finished, stale
      continue
    fi
    mkdir -p "$keep/ceilings"
    copy_atomic "$f" "$keep/ceilings/$(basename "$f")"
    echo "saved the case in progress, $(basename "$f"), to $keep/ceilings"
  done
  for f in "$ceil_tree"/hexapod_adapt/maps/ceilings/ceiling_*.npz; do
    [ -f "$f" ] || continue
    grep -qxF "$(basename "$f")" <<< "$shipped_names" && continue  # shipped already
    # the worktree's own checkout (an older map's shipped cases), not computed there
    git -C "$ceil_tree" ls-files --error-unmatch "${f#"$ceil_tree"/}" >/dev/null 2>&1 && continue
    copy_atomic "$f" "$dest/$(basename "$f")"
    n=$((n + 1))
  done
  if [ "$dest" = "$shipped_cache" ] && [ "$n" != 0 ]; then
    python -m hexapod_adapt.online.ceilings_cli --cache-dir "$dest" --pack
  fi
  if [ "$dest" = "$shipped_cache" ] && [ -f "$shipped_cache/README.md" ]; then
    # the README's table of what the cache holds, kind by kind
    bash "$repo/hexapod_adapt/maps/make_ceilings.sh" --archive "$shipped_maps/default_map.npz" \
      --cache-dir "$shipped_cache" --summary "$shipped_cache/README.md"
  fi
  echo "saved $n ceiling cases to $dest"
fi

# The transfer study. Its checkpoints are several MB: git ignores them (.gitignore); they survive
# where the machine does, and a run without one starts again from its seed. A checkpoint is
# written atomically, so the copy is a whole one.
transfer_tree="${TRANSFER_TREE:-$repo/../transfer-study}"
transfer_keep="${TRANSFER_KEEP:-$repo/studies/checkpoints/transfer_study}"
transfer_done="${TRANSFER_DONE:-$repo/studies/out/transfer_study}"
if [ -d "$transfer_tree/tuning/transfer_study" ]; then  # the pinned commit's layout
  mkdir -p "$transfer_keep" "$transfer_done"
  for log in "$transfer_tree"/tuning/transfer_study/walk_*.npz.log.jsonl; do
    [ -f "$log" ] || continue
    map="${log%.log.jsonl}"
    name="$(basename "$map")"
    if [ -f "$map" ]; then  # finished: the map and its log, and no checkpoint any more
      copy_atomic "$map" "$transfer_done/$name"
      copy_whole_rows "$log" "$transfer_done/$name.log.jsonl"
      rm -f "$transfer_keep/$name.ckpt.npz" "$transfer_keep/$name.log.jsonl"
      echo "saved the finished $name and its log to $transfer_done"
      continue
    fi
    ckpt="$map.ckpt.npz"
    [ -f "$ckpt" ] || continue
    here="$(checkpoint_evaluations "$ckpt")"
    kept="$(checkpoint_evaluations "$transfer_keep/$name.ckpt.npz")"
    if [ "$here" -lt "$kept" ]; then
      echo "not saved: $transfer_keep holds $name further on ($kept evaluations) than $transfer_tree ($here)" >&2
      continue
    fi
    copy_atomic "$ckpt" "$transfer_keep/$name.ckpt.npz"
    copy_whole_rows "$log" "$transfer_keep/$name.log.jsonl"
    echo "saved $name's checkpoint ($here evaluations, $(du -h "$ckpt" | cut -f1)) and log to $transfer_keep"
  done
fi
# The robust-speed study (studies/robust_speed/robust_study.sh): its checkpoints and finished
# maps, compressed and without their centroids, to studies/robust_speed/progress (committed). The
# runs go on.
robust_tree="${ROBUST_TREE:-$repo/../robust-study}"
if [ -d "$robust_tree/tuning/robust_speed" ]; then
  (cd "$repo" && python -m studies.robust_speed.progress save --tree "$robust_tree")
fi
echo "now commit them (git add the folders above)"
