#!/usr/bin/env bash
# Start or resume every long background run of the project, first thing in a session (each in a
# worktree of its own, at a low priority; each resumes from what the repository keeps):
#   bash scripts/resume_long_runs.sh
# - the default map (hexapod_adapt/maps/resume_default_map.sh), while the shipped one is not
#   the one make_default_map.sh makes, and then_ceilings.sh beside it: the new map's ceilings
#   start the moment it is written; once the map is written (kept in
#   hexapod_adapt/maps/in_progress/, or shipped), its ceilings (resume_ceilings.sh: only the
#   cases not cached yet), until the shipped cache holds them all;
# - the robust-speed study's maps (studies/robust_speed/candidates.py, robust_study.sh), until
#   studies/robust_speed/progress holds them all finished;
# Before the session ends: bash scripts/save_progress.sh, then commit what it lists.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
mkdir -p out
set +u  # the setup scripts read unset variables
# shellcheck disable=SC1091
source scripts/env.sh >/dev/null
set -u
# shellcheck disable=SC1091
source scripts/map_progress.sh
shipped="$(default_map_shipped)"
if [ "$shipped" = yes ] && [ "$(bash hexapod_adapt/maps/make_ceilings.sh --missing)" = 0 ]; then
  echo "the default map and every one of its ceilings are shipped: nothing to resume"
elif [ "$shipped" = yes ] \
  || [ "$(map_finished hexapod_adapt/maps/in_progress/default_map.npz)" = yes ]; then
  bash hexapod_adapt/maps/resume_ceilings.sh  # the finished map's (resume_ceilings.sh says which)
else
  bash hexapod_adapt/maps/resume_default_map.sh
  nohup bash hexapod_adapt/maps/then_ceilings.sh >> out/then_ceilings.out 2>&1 &
  echo "then_ceilings.sh waiting for the map (pid $!): out/then_ceilings.out"
fi
finished="$(find studies/robust_speed/progress -maxdepth 1 -name '*.npz' ! -name '*.ckpt.npz' \
  2>/dev/null | wc -l)"
candidates="$(PYTHONPATH="$repo:$PYTHONPATH" python -m studies.robust_speed.candidates | wc -l)"
if [ "$finished" -lt "$candidates" ]; then
  bash studies/robust_speed/robust_study.sh
else
  echo "the robust-speed study's $candidates maps are finished (its result: studies/robust_speed/README.md)"
fi
