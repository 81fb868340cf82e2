# Source this file (bash, with the workspace environment, from the repository root): helpers for
# long map runs.
# checkpoint_evaluations FILE: the evaluations a map or checkpoint holds (0 if FILE is missing or
# unreadable), from its metadata (hexapod_adapt.mapping.archive.load_archive).
checkpoint_evaluations() {
  [ -f "$1" ] || { echo 0; return; }
  python - "$1" <<'PY' 2>/dev/null || echo 0
import sys

from hexapod_adapt.mapping.archive import load_archive

print(int(load_archive(sys.argv[1]).metadata.get('evaluations', 0)))
PY
}

# default_map_shipped: "yes" when the repository's default map holds the evaluations
# make_default_map.sh asks for (the map is finished and committed), else "no".
default_map_shipped() {
  local target
  target="$(grep -o -- '--evaluations [0-9]*' hexapod_adapt/maps/make_default_map.sh | cut -d' ' -f2)"
  if [ "$(checkpoint_evaluations hexapod_adapt/maps/default_map.npz)" -ge "$target" ]; then
    echo yes
  else
    echo no
  fi
}
