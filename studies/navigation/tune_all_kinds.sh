#!/usr/bin/env bash
# A navigation tuning round walked on all eight damage kinds (tune_tripod_option --grid GRID,
# goals of seed 100), resumable across sessions, in the background at the lowest priority: it
# takes what the default map leaves of the cores.
#   [GRID=evidence] bash studies/navigation/tune_all_kinds.sh [WORKTREE]
# GRID: all_kinds (default: the ninth round, tripod_after), evidence (the tenth, tripod_bank),
# reported_tripod (the eleventh, tripod_reported, on two kinds, into a folder of its own) or a
# later round's grid (tune_tripod_option.ALL_KINDS_GRIDS).
# It runs from WORKTREE (default ../navtune for all_kinds, ../navtune-GRID for another), a
# worktree of the commit named in studies/out/navigation_all_kinds/COMMIT (all_kinds) or COMMIT.GRID
# (written at the first start: HEAD then), so that every unit of a round is walked by the same
# code. The units already committed in studies/out/navigation_all_kinds/ (every such grid's)
# are copied in and not walked again. Before a session ends, scripts/save_progress.sh copies the
# new ones back: commit them.
# Output: WORKTREE/out/tune_GRID.out; it ends with "winner: ...".
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
grid="${GRID:-all_kinds}"
cache="$repo/studies/out/navigation_all_kinds"
if [ "$grid" = all_kinds ]; then
  tree="${1:-$repo/../navtune}" pin="$cache/COMMIT"
else
  tree="${1:-$repo/../navtune-$grid}" pin="$cache/COMMIT.$grid"
fi
# shellcheck disable=SC1091
source "$repo/scripts/map_progress.sh"
REPO="$repo" TREE="$tree" PIN_FILE="$pin"
# shellcheck disable=SC1091
source "$repo/scripts/fixed_worktree.sh"
mkdir -p out studies/out/navigation_all_kinds
running="$(cat "out/tune_$grid.pid" 2>/dev/null || true)"
if [ -n "$running" ] && alive "$running"; then
  echo "the round is already running in $tree (pid $running)"
  exit 0
fi
cp -rn "$cache/." studies/out/navigation_all_kinds/
nohup nice -n 19 python -m studies.navigation.tune_tripod_option --grid "$grid" \
  --cache-dir studies/out/navigation_all_kinds >> "out/tune_$grid.out" 2>&1 &
echo $! > "out/tune_$grid.pid"
echo "navigation round $grid running in $tree (pid $!): tail -f $tree/out/tune_$grid.out"
