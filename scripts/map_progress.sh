# Source this file (bash, with the workspace environment): helpers for long map runs.
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
