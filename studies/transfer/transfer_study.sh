#!/usr/bin/env bash
# Start or resume the transfer study's map runs (studies/transfer/README.md) in the background, from
# a worktree pinned to the commit that started them (studies/transfer/COMMIT),
# one worker each, niced. Each run: 200,000 MuJoCo evaluations, 10,000 niches (the CVT of the map study's
# baselines), seed 1, presets first: the map study's budget, so the baselines
# (studies/out/map_study/{cma_mae,iso_line}_10000_s1.npz here) compare at equal cost.
#   bash studies/transfer/transfer_study.sh [WORKTREE]
# Before the session ends: bash scripts/save_progress.sh (keeps checkpoints and logs in
# studies/checkpoints/transfer_study/, finished maps in studies/out/transfer_study/), then commit
# what it lists. Inside the worktree the pinned commit's layout holds (tuning/transfer_study/).
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
tree="${1:-$repo/../transfer-study}"
keep="$repo/studies/checkpoints/transfer_study"
REPO="$repo" TREE="$tree" PIN_FILE="$repo/studies/transfer/COMMIT"  # the code that made B1, B2
# shellcheck disable=SC1091
source "$repo/scripts/fixed_worktree.sh"
mkdir -p out tuning/transfer_study
cp -n "$keep/"* tuning/transfer_study/ 2>/dev/null || true
# the baselines' niches, from their archive (the CVT file itself is 1.2 MB: not kept in git)
[ -f tuning/transfer_study/centroids_10000_6.dat ] || python - <<'PY'
from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.cvt import cvt_cache_path, save_centroids

base = load_archive('tuning/map_study/cma_mae_10000_s1.npz')  # the pinned commit's copy
save_centroids(cvt_cache_path('tuning/transfer_study', 10000), base.centroids)
PY
run() {  # run NAME EMITTERS: one guarded map, resumed where it stopped
  python -m hexapod_adapt.mapping.generate_map_cli --out "tuning/transfer_study/$1.npz" \
    --engine mujoco --niches 10000 --evaluations 200000 --seed 1 --with-presets \
    --emitters "$2" --cvt-dir tuning/transfer_study --workers 1 \
    --min-feet 3 --max-tilt 0.5236 --checkpoint-every 300 --log-every 60 --no-bar --resume
}
# the two runs side by side (each deterministic from its seed, so order does not matter), each
# started only when it is neither finished nor running
for spec in walk_cma_mae_10000_s1:cma_mae walk_iso_line_10000_s1:iso_line; do
  name="${spec%%:*}" emitters="${spec#*:}"
  if [ -f "tuning/transfer_study/$name.npz" ]; then
    echo "$name: finished"
  elif pgrep -f "tuning/transfer_study/$name.npz" >/dev/null; then
    echo "$name: running already"
  else
    nohup nice -n 19 bash -c "$(declare -f run); run $name $emitters" \
      >> "out/transfer_study_$name.out" 2>&1 &
    echo "$name running in $tree (pid $!): tail -f $tree/out/transfer_study_$name.out"
  fi
done
