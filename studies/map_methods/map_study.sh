#!/usr/bin/env bash
# Resume the map study (studies/map_methods/README.md) in the background, from a worktree of its own, so
# that work on the library under it cannot change or break a run in progress.
#   bash studies/map_methods/map_study.sh [WORKTREE] [CHECKPOINTS]
# WORKTREE (default ../study) is made at this checkout's HEAD if missing and built with this
# checkout's .venv; the study's outputs so far (studies/out/map_study) and the checkpoints kept
# outside git (CHECKPOINTS, default ../persist: *.ckpt.npz) are copied in (existing files kept).
# Output: WORKTREE/out/map_study.out. Copy WORKTREE/studies/out/map_study/*.log.jsonl, finished maps
# and ceilings back, and the checkpoints to CHECKPOINTS, before the session ends.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
tree="${1:-$repo/../study}"
keep="${2:-$repo/../persist}"
REPO="$repo" TREE="$tree"
# shellcheck disable=SC1091
source "$repo/scripts/fixed_worktree.sh"
mkdir -p out studies/out/map_study/ceilings
cp -rn "$repo/studies/out/map_study/." studies/out/map_study/ 2>/dev/null || true
if [ -d "$keep" ]; then
  cp -n "$keep"/*.ckpt.npz studies/out/map_study/ 2>/dev/null || true
fi
nohup nice -n 19 python -m studies.map_methods.map_study run >> out/map_study.out 2>&1 &
echo "map study running in $tree (pid $!): tail -f $tree/out/map_study.out"
