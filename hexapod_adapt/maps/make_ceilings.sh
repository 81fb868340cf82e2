#!/usr/bin/env bash
# The default map's ceilings (every gait under each S1-S4 damage, of every damage kind: issue 19's
# regret figures, issue 31's per-kind ratios and priors): the exact command, resumable; the
# lifted legs first. Each damage case is cached in its own file in maps/ceilings/ as it
# finishes; run it again after an interruption until every case prints (cached ones in ~0 s).
#   nohup nice -n 10 bash hexapod_adapt/maps/make_ceilings.sh > out/ceilings.out 2>&1 &
# Options are passed on: `bash hexapod_adapt/maps/make_ceilings.sh --missing` prints how many
# cases the cache lacks and computes nothing (ship_map.sh counts a kept map's cases in another
# folder by passing its own cache option after this one's: the last one given is used).
# (PyBullet approximations, --engine pybullet --top 1000 --guide-engine mujoco, are not shipped:
# studies/adaptation/README.md says why.)
set -eo pipefail   # (no -u: colcon's setup scripts read unset variables)
cd "$(dirname "$0")/../.."
source scripts/env.sh
# Lifted legs in full (the bank, the S1-S4 prior, the navigation specialists and the acceptance
# runs read them), then, in full too, the three cases whose fastest gait lay deepest in the
# intact order on the map of 2026-11-28 (the check of the share); then the other kinds' cases not
# cached yet, partial: the intact-fastest share of the map (ceiling.TOP_FRACTION;
# maps/ceilings/README.md, "Partial ceilings").
full=(lifted)
check=(3:no_tibia,4:no_tibia 5:locked,6:locked 4:unpowered:tibia,6:unpowered:tibia)
partial=(unpowered_coxa unpowered_femur unpowered_tibia locked weak no_tibia shortened)
exec python -m hexapod_adapt.online.ceilings_cli --engine mujoco --scenarios S1 S2 S3 S4 \
  --damage-kind "${full[@]}" "${partial[@]}" --partial "${partial[@]}" --damage "${check[@]}" \
  --cache-dir hexapod_adapt/maps/ceilings --workers "${WORKERS:-2}" "$@"
