#!/usr/bin/env bash
# The default map's ceilings (every gait under each S1-S4 damage; issue 19's regret figures): the
# exact command, resumable. Each damage case is cached in its own file in maps/ceilings/ as it
# finishes; run it again after an interruption until every case prints (cached ones in ~0 s).
#   nohup nice -n 10 bash hexapod_adapt/maps/make_ceilings.sh > out/ceilings.out 2>&1 &
# Then the PyBullet approximations for the cross-engine experiment (~7x slower per gait).
set -eo pipefail   # (no -u: colcon's setup scripts read unset variables)
cd "$(dirname "$0")/../.."
source scripts/env.sh
python -m hexapod_adapt.ceiling --engine mujoco --scenarios S1 S2 S3 S4 \
  --cache-dir hexapod_adapt/maps/ceilings --workers "${WORKERS:-2}"
# across engines: PyBullet over the 1000 gaits that walk best under each damage on MuJoCo (a full
# PyBullet ceiling costs about 20 min of one core per damage case)
exec nice -n 10 python -m hexapod_adapt.ceiling --engine pybullet --top 1000 --guide-engine mujoco \
  --scenarios S1 S2 S3 S4 --cache-dir hexapod_adapt/maps/ceilings --workers "${WORKERS:-2}"
