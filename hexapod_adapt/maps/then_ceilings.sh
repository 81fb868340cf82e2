#!/usr/bin/env bash
# Start the new default map's ceilings (resume_ceilings.sh) as soon as the map running in
# WORKTREE (default ../mapgen, resume_default_map.sh) has written it, so that the cores do not
# idle between the two:
#   nohup bash hexapod_adapt/maps/then_ceilings.sh >> out/then_ceilings.out 2>&1 &
# The map is taken as written when WORKTREE's default_map.npz is newer than the run's pid file
# (generate_map writes it once, at the end). If the run stops without writing it (the session
# ends, a kill), nothing starts.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
tree="$(realpath "${1:-$repo/../mapgen}")"
# shellcheck disable=SC1091
source "$repo/scripts/map_progress.sh"
pidfile="$tree/out/default_map.pid"
map="$tree/hexapod_adapt/maps/default_map.npz"
if [ ! -f "$pidfile" ]; then
  echo "no map run in $tree (no $pidfile): no ceilings started"
  exit 0
fi
pid="$(cat "$pidfile")"
watcher="$tree/out/then_ceilings.pid"
other="$(cat "$watcher" 2>/dev/null || true)"
if [ -n "$other" ] && [ "$other" != $$ ] && alive "$other"; then
  echo "then_ceilings.sh is already waiting for this map (pid $other)"
  exit 0
fi
echo $$ > "$watcher"
while alive "$pid"; do sleep 30; done
if [ -f "$map" ] && [ "$map" -nt "$pidfile" ]; then
  echo "$(date -u +%FT%TZ) the map is written: starting its ceilings"
  MAP="$map" bash "$repo/hexapod_adapt/maps/resume_ceilings.sh"
else
  echo "$(date -u +%FT%TZ) the map run $pid ended without writing $map: no ceilings started"
fi
