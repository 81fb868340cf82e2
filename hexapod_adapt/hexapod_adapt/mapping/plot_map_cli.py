# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``plot_map``: pictures of a map.

QD progress from its generation log and the 6-D map as 2-D projections (a navigation repertoire:
where its steps end, and its progress). Works on a finished map, a checkpoint, and the log of a
run still in progress.

    ros2 run hexapod_adapt plot_map --archive hexapod_adapt/maps/default_map.npz --out-dir docs/img
    plot_map --archive map.npz.ckpt.npz --log map.npz.log.jsonl --out-dir /tmp/progress
"""

from __future__ import annotations

import argparse
from pathlib import Path
import sys

from hexapod_adapt.mapping.archive import ArchiveError, load_archive
from hexapod_adapt.mapping.plots import (
    plot_progress,
    plot_projections,
    plot_repertoire,
    plot_repertoire_progress,
    read_log,
)
from hexapod_util.cli import (
    add_force,
    claim_outputs,
    FORCE_HINT,
    input_file,
    output_dir,
    run_command,
)


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``plot_map``; exit status 2 for an unreadable map or log."""
    ap = argparse.ArgumentParser(
        prog='plot_map',
        description=__doc__.split('\n\n')[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument(
        '--archive',
        type=input_file,
        required=True,
        help='map (.npz) or its checkpoint (.ckpt.npz)',
    )
    ap.add_argument(
        '--log',
        type=input_file,
        default=None,
        help='JSON-lines progress log (default: <map>.log.jsonl beside the map)',
    )
    ap.add_argument('--out-dir', type=output_dir, default=Path('.'), help='where the PNG files go')
    ap.add_argument('--name', default=None, help="file name stem (default: the map's)")
    add_force(ap)
    args = ap.parse_args(argv)
    return run_command('plot_map', lambda: _plot(args))


def _plot(args: argparse.Namespace) -> int:
    stem = args.name or args.archive.name.split('.')[0]
    base = Path(str(args.archive).replace('.ckpt.npz', ''))
    candidates = [base.with_name(base.name + '.log.jsonl'), base.with_name(stem + '.log.jsonl')]
    log = args.log or next((c for c in candidates if c.is_file()), candidates[0])
    try:
        archive = load_archive(args.archive)
        rows = read_log(log) if log.is_file() else []
        title = f'{stem}: {rows[-1]["evaluations"]} evaluations' if rows else ''
        progress = args.out_dir / f'{stem}_progress.png'
        shape = 'steps' if archive.kind.name == 'navigation' else 'projections'
        claim_outputs(
            [args.out_dir / f'{stem}_{shape}.png'] + ([progress] if rows else []),
            args.force,
            FORCE_HINT,
        )
        if archive.kind.name == 'navigation':
            written = [plot_repertoire(archive, args.out_dir / f'{stem}_steps.png')]
            if rows:
                written.append(plot_repertoire_progress(rows, progress, title=title))
        else:
            written = [plot_projections(archive, args.out_dir / f'{stem}_projections.png')]
            if rows:
                written.append(plot_progress(rows, progress, archive.trial_duration, title=title))
        if not rows:
            print(f'plot_map: no progress log at {log}; drawing the map only', file=sys.stderr)
    except (ArchiveError, ValueError) as exc:
        print(f'plot_map: {exc}', file=sys.stderr)
        return 2
    for path in written:
        print(path)
    return 0


if __name__ == '__main__':
    sys.exit(main())
