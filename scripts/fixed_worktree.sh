# Source this file (bash) with REPO and TREE set: TREE becomes a worktree of REPO at COMMIT
# (default: REPO's HEAD) if it is missing (then FIXED_WORKTREE_NEW=1), is built on its own with
# REPO's .venv, and is entered with its environment. Long runs go there, so that work on the
# library in REPO cannot change or break a run in progress (they import the workspace's build).
FIXED_WORKTREE_NEW=0
if [ ! -d "$TREE" ]; then
  git -C "$REPO" worktree add --detach "$TREE" "${COMMIT:-HEAD}"
  FIXED_WORKTREE_NEW=1
fi
export HEXAPOD_VENV="$REPO/.venv"
cd "$TREE"
set +u  # the setup scripts read unset variables
# shellcheck disable=SC1091
source scripts/env.sh >/dev/null
if [ ! -d install ]; then
  colcon build --symlink-install >/dev/null 2>&1
  # shellcheck disable=SC1091
  source scripts/env.sh >/dev/null  # again: now with the install space
fi
set -u
