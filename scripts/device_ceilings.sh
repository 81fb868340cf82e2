#!/usr/bin/env bash
# Ceiling cases on a lent many-core machine (this workplace's `device` tool; nothing depends on
# it): the same ceilings_cli as hexapod_adapt/maps/make_ceilings.sh, on the map in progress, with
# one worker per core. The machine's Python lacks MuJoCo and pyribs: they travel as a packed
# site folder (.devcarry/site312.tar.xz, ignored; wheels for its Python, MuJoCo's viewer and
# headers left out). Finished cases are tarred into $OUT/ceilings.tar as they come, so a run cut
# off at its limit still returns them; unpack them into the ceilings cache and check them with
# `make_ceilings.sh --missing` (a case made for another map or engine setting is not read).
#   DEVICE_LIMIT=540 bash scripts/device_ceilings.sh locked unpowered_tibia
# Seen 2026-11-28 on a 16-core H200 machine: 74-84 s a case with 16 workers (about 440 s on this
# workplace's 2 cores); the check re-walked 160 gaits of a case made here to within 1.4e-10 m/s.
set -eo pipefail
cd "$(dirname "$0")/.."
: "${OUT:?set OUT to a folder for the results}"
PY=${PYTHON:-python3}
if [ -f .devcarry/site312.tar.xz ]; then
  mkdir -p /tmp/site && tar -xJf .devcarry/site312.tar.xz -C /tmp/site
  export PYTHONPATH=/tmp/site
fi
for pkg in hexapod_adapt hexapod_sim hexapod_util hexapod_description hexapod_gait; do
  PYTHONPATH=$PYTHONPATH:$PWD/$pkg
done
# (before OMP_NUM_THREADS=1 below: GNU nproc reports that instead of the cores)
WORKERS=${WORKERS:-$(nproc)}
export PYTHONPATH MUJOCO_GL=disable PYTHONUNBUFFERED=1
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1 NUMBA_NUM_THREADS=1
MAP=hexapod_adapt/maps/in_progress/default_map.npz
CACHE=/tmp/device_ceilings && mkdir -p "$CACHE"
echo "$WORKERS workers"; "$PY" -V
# Same physics here as where the kept cases were made: re-walk some gaits of a kept case.
"$PY" - "$MAP" "$WORKERS" <<'PY' | tee "$OUT/check.txt"
import sys
import numpy as np
from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.online.ceiling import cached_ceiling, compute_ceiling
from hexapod_sim.damage import Damage
archive = load_archive(sys.argv[1])
kept = cached_ceiling(archive, Damage.lifted([1]), 'mujoco', ['hexapod_adapt/maps/in_progress/ceilings'])
assert kept is not None, 'the kept case S1 leg 1 lifted was not read'
niches = kept.niches[:: max(1, len(kept.niches) // 160)][:160]
again = compute_ceiling(archive, Damage.lifted([1]), 'mujoco', int(sys.argv[2]), chunk=8, niches=niches)
diff = np.abs(again.speeds - kept.speeds[np.searchsorted(kept.niches, niches)])
print(f'check: {len(niches)} gaits of S1 leg 1 lifted re-walked, max |speed diff| {diff.max():.3g} m/s,'
      f' {int((diff > 0).sum())} differ')
PY
(while sleep 10; do tar -cf "$OUT/part.tar" -C "$CACHE" . && mv "$OUT/part.tar" "$OUT/ceilings.tar"; done) &
SAVER=$!
set +e
timeout "${DEVICE_LIMIT:-540}" "$PY" -m hexapod_adapt.online.ceilings_cli --archive "$MAP" \
  --engine mujoco --scenarios S1 S2 S3 S4 --damage-kind "${@:-locked}" --cache-dir "$CACHE" \
  --workers "$WORKERS"
echo "ceilings_cli exit $?"
kill $SAVER
tar -cf "$OUT/part.tar" -C "$CACHE" . && mv "$OUT/part.tar" "$OUT/ceilings.tar"
ls "$CACHE"
