#!/usr/bin/env bash
# Start or resume the default map's ceilings (make_ceilings.sh: 8 kinds x 21 cases, hours on 2
# cores) in the background, from a worktree of its own, so that work on the library under it
# cannot change or break the run.
#   bash hexapod_adapt/maps/resume_ceilings.sh [WORKTREE] [CHECKPOINTS]
# The map: MAP (e.g. ../mapgen/hexapod_adapt/maps/default_map.npz, just written), else the
# finished map kept in hexapod_adapt/maps/in_progress/ (save_progress.sh), else the default map
# this checkout ships; it is copied into the worktree with its log. Commit a new map together
# with its ceilings: the demo, the tests and make bench-adapt read the shipped map's cache.
# WORKTREE (default ../ceilgen) is made if missing, at the commit that started the ceilings
# (CHECKPOINTS/COMMIT, committed; HEAD at the first start), and built with this checkout's .venv.
# Cases already cached in CHECKPOINTS (default hexapod_adapt/maps/in_progress/ceilings,
# committed) or shipped in this checkout's maps/ceilings are copied in, so a new worktree only computes what is missing (a cache file names
# its map, engine and damage: a file of another map is never used).
# Output: WORKTREE/out/ceilings.out. Before a session ends `bash
# scripts/save_progress.sh` copies the finished cases to in_progress/ceilings (a map not shipped
# yet; ship_map.sh ships it once its lifted-leg cases are there) or packs them into the shipped
# cache (the shipped map's): commit them.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
tree="${1:-$repo/../ceilgen}"
keep="${2:-$repo/hexapod_adapt/maps/in_progress/ceilings}"
# the map: MAP, else the finished map kept in in_progress/, else this checkout's default map (a
# worktree pinned to an older commit ships an older map). Before entering the worktree: MAP may
# be relative.
if [ -n "${MAP:-}" ]; then
  map="$(realpath "$MAP")"
elif [ -f "$repo/hexapod_adapt/maps/in_progress/default_map.npz" ]; then
  map="$repo/hexapod_adapt/maps/in_progress/default_map.npz"
else
  map="$repo/hexapod_adapt/maps/default_map.npz"
fi
# shellcheck disable=SC1091
source "$repo/scripts/map_progress.sh"
REPO="$repo" TREE="$tree" PIN_FILE="$keep/COMMIT"
# shellcheck disable=SC1091
source "$repo/scripts/fixed_worktree.sh"
# (a map made with other engine settings, generate_map --substeps, is re-scored in them:
# hexapod_adapt.mapping.simulation.map_substeps)
mkdir -p out hexapod_adapt/maps/ceilings
running="$(cat out/ceilings.pid 2>/dev/null || true)"
if [ -n "$running" ] && alive "$running"; then
  echo "the ceilings are already running in $tree (pid $running)"
  exit 0
fi
if [ "$map" != "$(realpath hexapod_adapt/maps/default_map.npz)" ]; then
  cp "$map" hexapod_adapt/maps/default_map.npz
  if [ -f "$map.log.jsonl" ]; then cp "$map.log.jsonl" hexapod_adapt/maps/default_map.npz.log.jsonl; fi
fi
# the cases kept so far (with the walking file of the case in progress: it goes on from there),
# and those this checkout ships (a worktree pinned before the map shipped holds the older map's)
for d in "$keep" "$repo/hexapod_adapt/maps/ceilings"; do
  if [ -d "$d" ]; then cp -n "$d"/*.npz hexapod_adapt/maps/ceilings/ 2>/dev/null || true; fi
done
# the shipped packs over the pinned checkout's (an older map's packs have the same names)
cp -f "$repo"/hexapod_adapt/maps/ceilings/*.zip hexapod_adapt/maps/ceilings/ 2>/dev/null || true
nohup nice -n 10 bash hexapod_adapt/maps/make_ceilings.sh >> out/ceilings.out 2>&1 &
echo $! > out/ceilings.pid
echo "ceilings running in $tree (pid $!): tail -f $tree/out/ceilings.out"
