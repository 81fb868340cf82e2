#!/usr/bin/env bash
# The navigation repertoire's specialists: the default map's fastest 3-feet gait under each of
# the bank's damages, as more steps (hexapod_navigation.core.specialists). About 16 CPU-minutes
# (17 min of wall time on 2 cores beside a niced ceilings run, 2026-11-28).
set -eo pipefail   # (no -u: colcon's setup scripts read unset variables)
cd "$(dirname "$0")/../.."
source scripts/env.sh
exec python -m hexapod_navigation.offline.specialists_cli \
  --out hexapod_navigation/maps/navigation_specialists.npz --workers "${WORKERS:-2}" --force
