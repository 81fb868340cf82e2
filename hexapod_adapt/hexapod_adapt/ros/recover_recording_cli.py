# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``recover_recording``.

Rewrite an MCAP recording whose writer was killed (SIGKILL, power loss) as a valid, indexed MCAP
that every reader opens, keeping every complete message (every trial the adapt node finished before
the kill). The input is never changed unless ``--in-place`` says so.

    ros2 run hexapod_adapt recover_recording adaptation_runs/adapt_20261121_101500.mcap
        # -> adaptation_runs/adapt_20261121_101500.recovered.mcap
    recover_recording killed.mcap --out repaired.mcap
    recover_recording killed.mcap --in-place   # the original is kept as killed.mcap.orig

A file that is not an MCAP recording, or one a process still has open for writing (a run in
progress), is refused and left as it is. An output that exists is refused unless ``--force``
(which keeps the old file as NAME.bak); ``--in-place`` replaces the input only if the recovered
file holds every message that could be read from it.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path
import sys

from hexapod_util.cli import (
    claim_outputs,
    input_file,
    open_for_writing_by,
    output_file,
    run_command,
)
from hexapod_util.recording import readable_messages, recording_problem, recover

#: What --in-place keeps the original as: NAME + this.
ORIGINAL_SUFFIX = '.orig'


def default_output(recording: Path) -> Path:
    """Return where the recovered copy goes by default: ``NAME.recovered.mcap`` beside it."""
    stem = recording.name[: -len('.mcap')] if recording.name.endswith('.mcap') else recording.name
    return recording.with_name(f'{stem}.recovered.mcap')


def build_parser() -> argparse.ArgumentParser:
    """Return the command-line options of ``recover_recording``."""
    ap = argparse.ArgumentParser(
        prog='recover_recording',
        description=__doc__.split('\n\n')[1].strip(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument('recording', type=input_file, help='the MCAP file to recover')
    where = ap.add_mutually_exclusive_group()
    where.add_argument(
        '--out',
        type=output_file,
        default=None,
        help='where to write the recovered file (default: NAME.recovered.mcap beside the input)',
    )
    where.add_argument(
        '--in-place',
        action='store_true',
        help='replace the input (kept as NAME.mcap.orig), only if no message is lost',
    )
    ap.add_argument(
        '--force',
        action='store_true',
        help='replace an existing output (the old file is kept as NAME.bak)',
    )
    return ap


def _check_input(recording: Path) -> None:
    """Refuse a recording still being written, or a file that is not one."""
    writers = open_for_writing_by(recording)
    if writers:
        raise ValueError(
            f'{recording} is still open for writing by process {", ".join(map(str, writers))}'
            ' (a recording in progress?): stop it first; nothing was written'
        )
    problem = recording_problem(recording)
    if problem:
        raise ValueError(f'{problem}; nothing was written')


def _in_place(recording: Path, force: bool) -> int:
    original = recording.with_name(recording.name + ORIGINAL_SUFFIX)
    claim_outputs([original], force, '--force to replace it (kept as NAME.bak)')
    readable = readable_messages(recording)
    temporary = recording.with_name(f'.{recording.name}.recovering')
    result = recover(recording, temporary)
    if result.messages < readable:
        temporary.unlink()
        raise ValueError(
            f'recovered {result.messages} of the {readable} messages {recording} holds: it is'
            ' left as it is (write a copy with --out)'
        )
    os.replace(recording, original)
    os.replace(temporary, recording)
    print(
        f'wrote {recording}: {result.messages} messages on {result.channels} topics;'
        f' the original is {original}'
    )
    return 0


def main(argv: list[str] | None = None) -> int:
    """Run ``recover_recording``; exit status 2 for bad options, 1 for a refusal or I/O error."""
    args = build_parser().parse_args(argv)

    def recover_file() -> int:
        _check_input(args.recording)
        if args.in_place:
            return _in_place(args.recording, args.force)
        out = args.out or default_output(args.recording)
        if out.resolve() == args.recording.resolve():
            raise ValueError(f'--out is the input {out}: use --in-place to replace it')
        claim_outputs(
            [out], args.force, '--force to replace it (the old file is kept as NAME.bak)'
        )
        result = recover(args.recording, out)
        print(f'wrote {result.out}: {result.messages} messages on {result.channels} topics')
        return 0

    return run_command('recover_recording', recover_file)


if __name__ == '__main__':
    sys.exit(main())
