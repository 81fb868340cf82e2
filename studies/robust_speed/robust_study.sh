#!/usr/bin/env bash
# Start or resume the robust-speed study's seven candidate maps (studies/robust_speed/README.md)
# in the background, niced, from a worktree pinned to the commit that started them
# (studies/robust_speed/COMMIT), in two queues (one per core) that take the maps in turn. Each
# map: MuJoCo at 4 steps per row, iso+line, the default map's 10,000 niches and seed, presets
# first, WALKS simulated walks (its evaluations x its variants per gait). A finished map is skipped; a stopped one resumes
# from its checkpoint (every 300 s).
#   bash studies/robust_speed/robust_study.sh [WORKTREE]          # start or resume
#   bash studies/robust_speed/robust_study.sh stop                # stop both queues now
# The checkpoints (3.5 MB each) are in WORKTREE/tuning/robust_speed, outside git; before a
# session ends, scripts/save_progress.sh keeps them, compressed, in studies/robust_speed/progress
# (committed), and a start here restores them. The finished maps are judged with: python -m studies.robust_speed.judge_maps --maps WORKTREE/tuning/robust_speed
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
if [ "${1:-}" = stop ]; then
  pkill -f robust_study_queue || true  # the queues first: they start no next map
  pkill -f "generate_map_cli --out tuning/robust_speed/" || true  # its workers die with it
  echo "stopped; resume with: bash studies/robust_speed/robust_study.sh"
  exit 0
fi
tree="${1:-$repo/../robust-study}"
WALKS=32000
REPO="$repo" TREE="$tree" PIN_FILE="$repo/studies/robust_speed/COMMIT"
# shellcheck disable=SC1091
source "$repo/scripts/fixed_worktree.sh"
out=tuning/robust_speed
mkdir -p out "$out"
# the default map's niches (the CVT file itself is 1.2 MB: not kept in git)
[ -f "$out/centroids_10000_6.dat" ] || python - <<'PY'
from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.cvt import cvt_cache_path, save_centroids

base = load_archive('hexapod_adapt/maps/default_map.npz')
save_centroids(cvt_cache_path('tuning/robust_speed', 10000), base.centroids)
PY
run() {  # run NAME VARIANTS STATISTIC WALKS: one candidate map, resumed where it stopped
  local evaluations=$(($4 / ($2 > 0 ? $2 : 1)))
  python -m hexapod_adapt.mapping.generate_map_cli --out "tuning/robust_speed/$1.npz" \
    --engine mujoco --substeps 4 --niches 10000 --evaluations "$evaluations" --seed 1 \
    --with-presets --emitters iso_line --cvt-dir tuning/robust_speed --workers 1 \
    --variants "$2" --statistic "$3" --variant-seed 0 \
    --checkpoint-every 300 --log-every 60 --no-bar --resume
}
queue() {  # queue SPEC...: the next map no other queue has claimed, until none is left
  for spec in "$@"; do
    IFS=: read -r name variants statistic <<< "$spec"
    [ -f "tuning/robust_speed/$name.npz" ] && continue
    mkdir "tuning/robust_speed/$name.claim" 2>/dev/null || continue  # the other queue's
    run "$name" "$variants" "$statistic" "$WALKS"
  done
}
if pgrep -f robust_study_queue >/dev/null; then
  echo "running already: tail -f $tree/out/robust_study_*.out"
  exit 0
fi
rm -rf tuning/robust_speed/*.claim  # no queue runs: a claim left is a stopped run's
# what an earlier session kept in the repository (progress.py save), where further on than here
PYTHONPATH="$repo:$PYTHONPATH" python -m studies.robust_speed.progress restore --tree "$tree"
# the longest first (a nominal walk is a map proposal: more of them reach the slow 5 s walks)
mapfile -t specs < <(PYTHONPATH="$repo:$PYTHONPATH" python -m studies.robust_speed.candidates)
for q in 1 2; do
  nohup nice -n 19 bash -c "WALKS=$WALKS; $(declare -f run queue); queue ${specs[*]}" \
    robust_study_queue >> "out/robust_study_$q.out" 2>&1 &
  echo "queue $q running in $tree (pid $!): tail -f $tree/out/robust_study_$q.out"
done
