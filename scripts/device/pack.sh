#!/usr/bin/env bash
# Pack what the lent 16-core machine (the `device` tool) lacks to run the map tools: MuJoCo
# (trimmed of its viewer and experimental parts, to fit the 64 MiB a call may carry), pyribs and
# their small dependencies, as cp312 wheels in .whl/ and .devrun/. Both folders are ignored
# through .git/info/exclude; name them in the call's `carry`. There, start the command with
#   source scripts/device/setup.sh
# The machine has numpy 2.5.2 (here 2.4.6): a map made there is a run of the same settings, not
# a bit-identical reproduction of one made here.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
exclude="$(git rev-parse --git-common-dir)/info/exclude"
mkdir -p "$(dirname "$exclude")" .whl .devrun
grep -qx '/.whl/' "$exclude" 2>/dev/null || echo '/.whl/' >> "$exclude"
grep -qx '/.devrun/' "$exclude" || echo '/.devrun/' >> "$exclude"
get() {
  python3 -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 \
    --implementation cp --platform manylinux_2_28_x86_64 --platform manylinux_2_27_x86_64 \
    --platform manylinux_2_17_x86_64 --platform manylinux2014_x86_64 -d "$1" "$2"
}
# the versions are requirements.txt's (case and - or _ as written there)
pin() { grep -ixE "$1==[^ ]+" requirements.txt; }
for name in glfw ribs pyopengl websockets 'array[-_]api[-_]compat' 'numpy[-_]groupies'; do
  get .whl "$(pin "$name")"
done
tmp="$(mktemp -d)"
get "$tmp" "$(pin mujoco)"
(cd "$tmp" && unzip -q mujoco-*.whl && rm -rf mujoco/experimental mujoco/_simulate*.so \
  mujoco/_render_filament*.so mujoco/include mujoco/testdata mujoco/*_test.py mujoco/viewer.py \
  && tar cJf mujoco_slim.tar.xz mujoco mujoco-*.dist-info)
mv "$tmp/mujoco_slim.tar.xz" .devrun/
rm -rf "$tmp"
du -sh .whl .devrun
