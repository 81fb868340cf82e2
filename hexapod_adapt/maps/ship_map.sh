#!/usr/bin/env bash
# Ship the finished default map kept in KEEP (default hexapod_adapt/maps/in_progress, where
# save_progress.sh puts it) with the ceilings made so far. Refuses, changing nothing, while any
# lifted-leg case is missing from KEEP/ceilings: the damage bank, the S1-S4 prior, the navigation
# specialists and the acceptance runs read those 21. The other kinds' cases take sessions more
# (resume_ceilings.sh); until they land, a damage without a shipped case is re-scored when it is
# asked for (the streaming prior), and save_progress.sh packs each finished case into the shipped
# cache. Then:
#   - maps/ceilings/: the old map's cases go, the new map's come in and are packed;
#   - maps/default_map.npz and its log: the new map's;
#   - config/adapt.yaml: sim_node's engine and substeps, the map's (map_substeps);
#   - hexapod_navigation's specialists, which read the map's ceilings, made again;
#   - KEEP is emptied, except KEEP/ceilings/COMMIT while cases are missing (the commit the
#     ceilings run stays pinned at).
# Everything is staged with git; what to run before committing is printed at the end.
#   bash hexapod_adapt/maps/ship_map.sh [KEEP]
set -eo pipefail   # (no -u: colcon's setup scripts read unset variables)
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
keep="$(realpath "${1:-$repo/hexapod_adapt/maps/in_progress}")"
cd "$repo"
maps=hexapod_adapt/maps
map="$keep/default_map.npz"
if [ ! -f "$map" ] || [ ! -f "$map.log.jsonl" ]; then
  echo "no finished map with its log in $keep: nothing shipped" >&2
  exit 1
fi
source scripts/env.sh >/dev/null
mkdir -p "$keep/ceilings"
# make_ceilings.sh's cases, counted in the kept cache (the last --cache-dir and --damage-kind
# given are used)
count_missing() {
  bash "$maps/make_ceilings.sh" --archive "$map" --missing --cache-dir "$keep/ceilings" "$@"
}
lifted="$(count_missing --damage-kind lifted --damage)"  # (no check cases: make_ceilings.sh's)
if [ "$lifted" != 0 ]; then
  echo "$lifted lifted-leg ceiling cases of $map are not in $keep/ceilings yet: nothing shipped" >&2
  exit 1
fi
missing="$(count_missing)"
git rm -q --ignore-unmatch "$maps"/ceilings/ceiling_*.npz "$maps"/ceilings/ceilings_*.zip
rm -f "$maps"/ceilings/ceiling_*.npz "$maps"/ceilings/ceilings_*.zip
cp "$keep"/ceilings/ceiling_*.npz "$maps/ceilings/"
for f in default_map.npz default_map.npz.log.jsonl; do
  cp "$keep/$f" "$maps/$f.tmp.$$" && mv -f "$maps/$f.tmp.$$" "$maps/$f"
done
colcon build --packages-select hexapod_adapt >/dev/null  # the installed share holds the map
bash "$maps/make_ceilings.sh" --pack | tail -1
read -r engine substeps < <(python - "$maps/default_map.npz" <<'PY'
import sys
from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.simulation import archive_engine, map_substeps
archive = load_archive(sys.argv[1])
engine = archive_engine(archive.metadata)
print(engine, map_substeps(archive, engine))
PY
)
sed -i -E "s/^(    engine: )[a-z]+( +#)/\1$engine\2/; s/^(    substeps: )[0-9]+( +#)/\1$substeps\2/" \
  hexapod_adapt/config/adapt.yaml
colcon build --packages-select hexapod_adapt >/dev/null
bash hexapod_navigation/maps/make_navigation_specialists.sh
if [ -f "$keep/ceilings/README.md" ]; then
  echo "--- $keep/ceilings/README.md (removed now; say it in $maps/ceilings/README.md):"
  cat "$keep/ceilings/README.md"
  echo "---"
fi
pin="$(cat "$keep/ceilings/COMMIT" 2>/dev/null || true)"  # (git rm removes the file)
git rm -rq --ignore-unmatch -- "$keep" 2>/dev/null || true
if [ "$missing" = 0 ]; then
  rm -rf "$keep"
else  # the pin stays: the run goes on at the commit it started with
  rm -rf "$keep"
  if [ -n "$pin" ]; then
    mkdir -p "$keep/ceilings"
    echo "$pin" > "$keep/ceilings/COMMIT"
    case "$keep" in "$repo"/*) git add "$keep/ceilings/COMMIT" ;; esac
  fi
  echo "$missing ceiling cases are still to make: bash scripts/resume_long_runs.sh each session;"\
    "save_progress.sh packs the finished ones into $maps/ceilings"
fi
git add "$maps" hexapod_adapt/config/adapt.yaml hexapod_navigation/maps/navigation_specialists.npz
echo "shipped (staged): the map, $(ls "$maps"/ceilings/ceilings_*.zip | wc -l) ceiling packs,"\
  "adapt.yaml at $engine/$substeps, the navigation specialists"
echo "before committing: name the cases made elsewhere in $maps/ceilings/README.md; then"\
  "bash $maps/regenerate_derived.sh (the check of partial ceilings, the docs' figures, what to"\
  "measure); make test"
