"""``recover_recording``: rewrite an MCAP recording whose writer was killed (SIGKILL, power loss)
as a valid, indexed MCAP that every reader opens, keeping every complete message (every trial
the adapt node finished before the kill).

    ros2 run hexapod_adapt recover_recording adaptation_runs/adapt_20261121_101500.mcap
    recover_recording killed.mcap --out repaired.mcap
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from hexapod_adapt.recording import recover


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``recover_recording``; exit status 2 for a missing file, 1 for an I/O error."""
    ap = argparse.ArgumentParser(prog="recover_recording", description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("recording", type=Path, help="the MCAP file to recover")
    ap.add_argument("--out", type=Path, default=None,
                    help="where to write the recovered file (default: replace the input, atomically)")
    args = ap.parse_args(argv)
    if not args.recording.is_file():
        print(f"recover_recording: {args.recording}: no such file", file=sys.stderr)
        return 2
    try:
        result = recover(args.recording, args.out)
    except OSError as exc:
        print(f"recover_recording: {exc}", file=sys.stderr)
        return 1
    print(f"wrote {result.out}: {result.messages} messages on {result.channels} topics")
    return 0


if __name__ == "__main__":
    sys.exit(main())
