#!/usr/bin/env bash
# Start or resume the default map's ceilings (make_ceilings.sh: 8 kinds x 21 cases, hours on 2
# cores) in the background, from a worktree of its own at this checkout's HEAD, so that work on
# the library under it cannot change or break the run.
#   bash hexapod_adapt/maps/resume_ceilings.sh [WORKTREE] [CHECKPOINTS]
# The ceilings are those of the map that HEAD ships: commit the finished default map first.
# WORKTREE (default ../ceilgen) is made at HEAD if missing and built with this checkout's .venv.
# Cases already cached in CHECKPOINTS (default ../persist/ceilings) are copied in, so a new
# worktree only computes what is missing (a cache file names its map, engine and damage: a file
# of another map is never used).
# Output: WORKTREE/out/ceilings.out. Before a session ends copy WORKTREE's
# hexapod_adapt/maps/ceilings/*.npz to CHECKPOINTS; when every case is cached, copy them back
# into this checkout's hexapod_adapt/maps/ceilings/ and commit them.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
tree="${1:-$repo/../ceilgen}"
keep="${2:-$repo/../persist/ceilings}"
REPO="$repo" TREE="$tree"
# shellcheck disable=SC1091
source "$repo/scripts/fixed_worktree.sh"
mkdir -p out hexapod_adapt/maps/ceilings
if [ -d "$keep" ]; then
  cp -n "$keep"/*.npz hexapod_adapt/maps/ceilings/ 2>/dev/null || true
fi
nohup nice -n 10 bash hexapod_adapt/maps/make_ceilings.sh >> out/ceilings.out 2>&1 &
echo "ceilings running in $tree (pid $!): tail -f $tree/out/ceilings.out"
