#!/usr/bin/env bash
# Issue 19's tuning protocol, the exact commands, resumable (ceilings are cached as they finish).
# 1. the tuning map (tuning/make_tuning_map.sh: seed 2, 2 000 niches, 200 000 MuJoCo evaluations);
# 2. its ceilings under the tuning damage (3 kinds x 21 leg sets, none of them S1-S4's lifted legs;
#    the 21 the trial-length study uses are in tuning/ceilings, scoring rules version 2);
# 2b. its damage bank (hexapod_adapt.online.bank): the tuning map under every one- and two-leg lifted
#    failure, in tuning/bank (none of them a tuning case: the bank is tested on damage it does not
#    hold);
# 3. why the thesis profile stops early (tuning/analyse_stops.py);
# 4. every candidate setting scored on the tuning set, with and without the bank (tuning/grid.csv);
# 5. the trial-length study on the tuning set with the chosen profile (tuning/trial_length.csv).
# The reported S1-S4 experiment on the default map is run once, afterwards (make bench-adapt).
set -eo pipefail   # (no -u: colcon's setup scripts read unset variables)
cd "$(dirname "$0")/.."
source scripts/env.sh
MAP=tuning/tuning_map_s2.npz
nice -n 10 python -m tuning.tuning_ceilings --archive "$MAP" --engine mujoco \
  --cache-dir tuning/ceilings --workers "${WORKERS:-2}"
nice -n 10 python -m hexapod_adapt.online.ceilings_cli --archive "$MAP" --engine mujoco \
  --scenarios S1 S2 S3 S4 --cache-dir tuning/bank --workers "${WORKERS:-2}"
python -m tuning.analyse_stops --archive "$MAP" --cache-dir tuning/ceilings --profile thesis \
  | tee tuning/analyse_stops_thesis.txt
python -m tuning.score_grid --archive "$MAP" --cache-dir tuning/ceilings --bank-dir tuning/bank \
  --out tuning/grid.csv \
  | tee tuning/grid_top.txt
nice -n 10 python -m tuning.trial_length --archive "$MAP" --cache-dir tuning/ceilings \
  --engine mujoco --every 3 --out tuning/trial_length.csv --plot docs/img/trial_length.png \
  | tee tuning/trial_length.txt
