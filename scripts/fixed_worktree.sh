# Source this file (bash) with REPO and TREE set: TREE becomes a worktree of REPO at a fixed
# commit if it is missing (then FIXED_WORKTREE_NEW=1), is built on its own with REPO's .venv, and
# is entered with its environment. Long runs go there, so that work on the library in REPO cannot
# change or break a run in progress (they import the workspace's build).
# The commit: the one PIN_FILE names (a file committed beside the run's kept progress: every
# session resumes the run with the code that started it, also on a new machine), written with
# REPO's HEAD at the first start; without PIN_FILE, REPO's HEAD. A worktree at another commit
# than the pin is refused (exit 1).
FIXED_WORKTREE_NEW=0
FIXED_COMMIT="$(git -C "$REPO" rev-parse HEAD)"
if [ -n "${PIN_FILE:-}" ]; then
  if [ -f "$PIN_FILE" ]; then
    FIXED_COMMIT="$(cat "$PIN_FILE")"
  else
    mkdir -p "$(dirname "$PIN_FILE")"
    echo "$FIXED_COMMIT" > "$PIN_FILE"
  fi
fi
if [ ! -d "$TREE" ]; then
  git -C "$REPO" worktree add --detach "$TREE" "$FIXED_COMMIT"
  FIXED_WORKTREE_NEW=1
fi
if [ -n "${PIN_FILE:-}" ] && [ "$(git -C "$TREE" rev-parse HEAD)" != "$FIXED_COMMIT" ]; then
  echo "$TREE is at $(git -C "$TREE" rev-parse HEAD), not the run's $FIXED_COMMIT ($PIN_FILE):" \
    "remove it (git worktree remove) and run this again" >&2
  exit 1
fi
export HEXAPOD_VENV="$REPO/.venv"
# One BLAS kernel on every x86-64 machine: OpenBLAS picks its kernels by processor, and their
# rounding steers CMA-ES and the GPs, so a run resumed on a machine that picked others goes on
# differently (measured: a 1,500-evaluation cma_mae map of 200 niches filled 23 niches with the
# Haswell kernels and with Zen's, 27 with SkylakeX's). Haswell's run on any AVX2 processor.
if [ "$(uname -m)" = x86_64 ]; then
  export OPENBLAS_CORETYPE=Haswell OPENBLAS_L2_SIZE=512
fi
# numpy's kernels too (a worktree pinned before this file existed has an env.sh without it)
# shellcheck disable=SC1091
source "$REPO/scripts/same_floats.sh"
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
