#!/usr/bin/env bash
# The ninth navigation tuning round (tune_tripod_option --grid all_kinds: tripod_after on all
# eight damage kinds, goals of seed 100), resumable across sessions, in the background at the
# lowest priority: it takes what the default map leaves of the cores.
#   bash tuning/tune_all_kinds.sh [WORKTREE]
# It runs from WORKTREE (default ../navtune), a worktree of the commit named in
# tuning/navigation_all_kinds/COMMIT (written at the first start: HEAD then), so that every unit
# of the round is walked by the same code. The units already committed in
# tuning/navigation_all_kinds/all_kinds/ are copied in and not walked again. Before a session
# ends, scripts/save_progress.sh copies the new ones back: commit them.
# Output: WORKTREE/out/tune_all_kinds.out; it ends with "winner: ...".
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
tree="${1:-$repo/../navtune}"
cache="$repo/tuning/navigation_all_kinds"
# shellcheck disable=SC1091
source "$repo/scripts/map_progress.sh"
REPO="$repo" TREE="$tree" PIN_FILE="$cache/COMMIT"
# shellcheck disable=SC1091
source "$repo/scripts/fixed_worktree.sh"
mkdir -p out tuning/navigation_all_kinds
running="$(cat out/tune_all_kinds.pid 2>/dev/null || true)"
if [ -n "$running" ] && alive "$running"; then
  echo "the round is already running in $tree (pid $running)"
  exit 0
fi
cp -rn "$cache/." tuning/navigation_all_kinds/
nohup nice -n 19 python -m tuning.tune_tripod_option --grid all_kinds \
  --cache-dir tuning/navigation_all_kinds >> out/tune_all_kinds.out 2>&1 &
echo $! > out/tune_all_kinds.pid
echo "navigation round running in $tree (pid $!): tail -f $tree/out/tune_all_kinds.out"
