#!/usr/bin/env bash
# After ship_map.sh: everything the docs show that is derived from the default map, made again
# from the shipped map and its ceilings (issue 66, deliverable 5), then the measurements to take.
# ship_map.sh itself makes the ceilings' packs, adapt.yaml's engine and step and the navigation
# specialists; the damage bank and the S1-S4 prior are the shipped lifted-leg ceilings, read as
# they are. Each step writes its files atomically and may be run again.
#   bash hexapod_adapt/maps/regenerate_derived.sh [--no-navigation]
# - the check of partial ceilings on the new map (maps/ceilings/README.md, "Partial ceilings"):
#   its full cases' fastest gaits against the intact order; stops here if one lies outside;
# - docs/img/default_map_progress.png and _projections.png (plot_map);
# - docs/experiment: the blind experiment's runs and pictures, with ratios (run_experiment);
# - docs/navigation: the navigation experiment (run_navigation; long: --no-navigation skips it),
#   and docs/navigation/locked: the same with locked legs.
set -eo pipefail   # (no -u: colcon's setup scripts read unset variables)
cd "$(dirname "$0")/../.."
source scripts/env.sh >/dev/null
maps=hexapod_adapt/maps
navigation=yes
[ "${1:-}" = --no-navigation ] && navigation=no
# exits non-zero when a full case's fastest gait lies outside TOP_FRACTION of the intact order
python -m studies.adaptation.partial_share --ceilings "$maps/ceilings" --check
python -m hexapod_adapt.mapping.plot_map_cli --archive "$maps/default_map.npz" --out-dir docs/img \
  --force
python -m hexapod_adapt.online.run_experiment_cli --ceilings "$maps/ceilings" \
  --out-dir docs/experiment --force
if [ "$navigation" = yes ]; then
  python -m hexapod_navigation.offline.run_navigation_cli --out-dir docs/navigation --force
  python -m hexapod_navigation.offline.run_navigation_cli --out-dir docs/navigation/locked \
    --damage-kind locked --force
fi
echo "regenerated: docs/img (the map's pictures), docs/experiment$( [ "$navigation" = yes ] \
  && echo ', docs/navigation, docs/navigation/locked')." \
  "Now measure and record in docs/benchmarks.md: make bench-map;"\
  "make bench-adapt; make bench-navigate; then the figures in $maps/README.md and the docs"
