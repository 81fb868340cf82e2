#!/usr/bin/env bash
# Issue 19's tuning protocol, the exact commands, resumable (ceilings are cached as they finish).
# 1. the tuning map (studies/adaptation/make_tuning_map.sh: seed 2, 2 000 niches, 200 000 MuJoCo evaluations);
# 2. its ceilings under the tuning damage (3 kinds x 21 leg sets, none of them S1-S4's lifted legs;
#    the 21 the trial-length study uses are in studies/out/ceilings, scoring rules version 2);
# 2b. its damage bank (hexapod_adapt.online.bank): the tuning map under every one- and two-leg lifted
#    failure, in studies/out/bank (none of them a tuning case: the bank is tested on damage it does not
#    hold);
# 3. why the thesis profile stops early (studies/adaptation/analyse_stops.py);
# 4. every candidate setting scored on the tuning set, with and without the bank (studies/out/grid.csv);
# 5. the trial-length study on the tuning set with the chosen profile (studies/trial_length/results/trial_length.csv).
# The reported S1-S4 experiment on the default map is run once, afterwards (make bench-adapt).
set -eo pipefail   # (no -u: colcon's setup scripts read unset variables)
cd "$(dirname "$0")/../.."
source scripts/env.sh
MAP=studies/out/tuning_map_s2.npz
nice -n 10 python -m studies.adaptation.tuning_ceilings --archive "$MAP" --engine mujoco \
  --cache-dir studies/out/ceilings --workers "${WORKERS:-2}"
nice -n 10 python -m hexapod_adapt.online.ceilings_cli --archive "$MAP" --engine mujoco \
  --scenarios S1 S2 S3 S4 --cache-dir studies/out/bank --workers "${WORKERS:-2}"
python -m studies.adaptation.analyse_stops --archive "$MAP" --cache-dir studies/out/ceilings --profile thesis \
  | tee studies/adaptation/results/analyses.txt
python -m studies.adaptation.score_grid --archive "$MAP" --cache-dir studies/out/ceilings --bank-dir studies/out/bank \
  --out studies/out/grid.csv \
  | tee studies/adaptation/results/grids.txt
nice -n 10 python -m studies.trial_length.trial_length --archive "$MAP" --cache-dir studies/out/ceilings \
  --engine mujoco --every 3 --out studies/trial_length/results/trial_length.csv --plot studies/trial_length/results/trial_length.png \
  | tee studies/trial_length/results/trial_length.txt
