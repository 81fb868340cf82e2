#!/usr/bin/env bash
# The shipped repertoire's damage bank (hexapod_navigation.core.step_bank; docs/navigation.md, "The
# navigator"): every repertoire gait played for one 2 s step from rest under each one- and two-leg
# failure of S1-S4, lifted, locked and with a dead femur servo (step_bank.NAVIGATION_BANK_KINDS),
# MuJoCo. The exact command; it writes the file only when every case is done.
#   nohup nice -n 10 bash hexapod_navigation/maps/make_navigation_bank.sh > out/navigation_bank.out 2>&1 &
set -eo pipefail   # (no -u: colcon's setup scripts read unset variables)
cd "$(dirname "$0")/../.."
source scripts/env.sh
exec python -m hexapod_navigation.offline.step_bank_cli --engine mujoco \
  --out hexapod_navigation/maps/navigation_bank.npz --workers "${WORKERS:-2}" --force
