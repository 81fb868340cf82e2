#!/usr/bin/env bash
# The default map: the exact command, resumable. Its method is the transfer study's winner
# (studies/transfer/README.md, issue 49: iso+line, whose gaits walk on the engines that did not
# make the map), stored by the gait's own speed (the robust-speed study's winner, 2026-12-04:
# studies/robust_speed/README.md), on MuJoCo at 4 physics steps per 240 Hz row: at 1, MuJoCo has
# not converged on fast gaits (studies/engines/README.md, "Where the engines differ", item 6).
# Issue 66's size: 20,000 niches and 1,000,000 evaluations, about 39 core-hours at the 200,000-
# evaluation map's 139 ms each (issue 66 asks 16: no cheaper converged physics was found), made
# over sessions (resume_long_runs.sh). Run it from the repository root; run it again after any
# interruption (it resumes from default_map.npz.ckpt.npz) until it prints "wrote". FRESH=1 starts
# from scratch: the map, its checkpoint and log already there are kept as NAME.bak (without it, a
# finished map made with other settings is refused, not continued).
#   FRESH=1 nohup nice -n 10 bash hexapod_adapt/maps/make_default_map.sh > out/default_map.out 2>&1 &
# resume_default_map.sh runs it from a worktree of its own. On a bigger machine set WORKERS (the
# map does not depend on the worker count).
set -eo pipefail   # (no -u: colcon's setup scripts read unset variables)
cd "$(dirname "$0")/../.."
source scripts/env.sh
# the BLAS kernels the map was made with (scripts/fixed_worktree.sh says why)
if [ "$(uname -m)" = x86_64 ]; then export OPENBLAS_CORETYPE=Haswell OPENBLAS_L2_SIZE=512; fi
if [ "${FRESH:-0}" = 1 ]; then how=--force; else how=--resume; fi
exec python -m hexapod_adapt.mapping.generate_map_cli \
  --out hexapod_adapt/maps/default_map.npz --engine mujoco --substeps 4 --niches 20000 \
  --evaluations 1000000 --seed 1 --with-presets --emitters iso_line --workers "${WORKERS:-2}" \
  --checkpoint-every 300 --log-every 30 --no-bar "$how"
