# Source this file (bash) for the helpers of long runs; the map helpers need the workspace
# environment and the repository root as the working directory.

# alive PID: the process runs (a zombie, exited but not yet reaped by its parent, does not)
alive() {
  kill -0 "$1" 2>/dev/null && [ "$(ps -o stat= -p "$1" | cut -c1)" != Z ]
}

# checkpoint_evaluations FILE [EMITTERS]: the evaluations a map or checkpoint holds (0 if FILE is
# missing or unreadable, or, with EMITTERS, made by other emitters), from its metadata
# (hexapod_adapt.mapping.archive.load_archive).
checkpoint_evaluations() {
  [ -f "$1" ] || { echo 0; return; }
  python - "$1" "${2:-}" <<'PY' 2>/dev/null || echo 0
import sys

from hexapod_adapt.mapping.archive import load_archive

meta = load_archive(sys.argv[1]).metadata
# iso_line's maps do not record it (MapElitesConfig.identity: their identity predates emitters)
made_by = meta.get('map_elites', {}).get('emitters', 'iso_line')
same = not sys.argv[2] or made_by == sys.argv[2]
print(int(meta.get('evaluations', 0)) if same else 0)
PY
}

# map_finished FILE: "yes" when the map FILE holds the evaluations make_default_map.sh asks for,
# made by its emitters (the new default map, written), else "no".
map_finished() {
  local target emitters
  target="$(grep -o -- '--evaluations [0-9]*' hexapod_adapt/maps/make_default_map.sh | cut -d' ' -f2)"
  emitters="$(grep -o -- '--emitters [a-z_]*' hexapod_adapt/maps/make_default_map.sh | cut -d' ' -f2)"
  if [ "$(checkpoint_evaluations "$1" "$emitters")" -ge "$target" ]; then
    echo yes
  else
    echo no
  fi
}

# default_map_shipped: "yes" when the repository's default map is that map (committed).
default_map_shipped() {
  map_finished hexapod_adapt/maps/default_map.npz
}
