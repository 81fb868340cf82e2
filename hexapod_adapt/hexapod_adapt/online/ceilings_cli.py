# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Cache the ceilings of a map: every gait under each damage (:mod:`hexapod_adapt.online.ceiling`).

    python -m hexapod_adapt.online.ceilings_cli --scenarios S1 S2 S3 S4 --engine mujoco --workers 2
    python -m hexapod_adapt.online.ceilings_cli --damage-kind locked weak --cache-dir DIR ...
    python -m hexapod_adapt.online.ceilings_cli --damage 1:locked,4:weak:0.3 --cache-dir DIR
    python -m hexapod_adapt.online.ceilings_cli --damage-kind ... --cache-dir DIR --missing
    python -m hexapod_adapt.online.ceilings_cli --cache-dir DIR --pack   # pack DIR's loose cases
    python -m hexapod_adapt.online.ceilings_cli --damage-kind ... --cache-dir DIR --summary
"""

from __future__ import annotations

import argparse
from pathlib import Path
import sys
import time
from typing import NamedTuple

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
from hexapod_adapt.online.ceiling import (
    approximate_ceiling,
    cached_ceiling,
    cached_names,
    Ceiling,
    ceiling,
    deepest_share,
    pack_ceilings,
    TOP_FRACTION,
)
from hexapod_sim import ENGINES
from hexapod_sim.damage import Damage, EXPERIMENT_KINDS, parse_damage
from hexapod_sim.scenarios import scenario, SCENARIO_NAMES
from hexapod_util.cli import input_file, number, output_dir, run_command
from hexapod_util.files import atomic_write_bytes


def _damage_arg(text: str) -> Damage:
    try:
        return parse_damage(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _add_readings(ap: argparse.ArgumentParser) -> None:
    """Add the options that compute nothing: each reads or packs the cache."""
    ap.add_argument(
        '--missing',
        action='store_true',
        help='compute nothing: print how many of the cases asked for the cache lacks (a file'
        ' that is damaged or made for another map counts as lacking)',
    )
    ap.add_argument(
        '--pack',
        action='store_true',
        help="compute nothing: move the cache's loose files into zip packs (read as before;"
        ' for a cache to ship, packed as its cases finish)',
    )
    ap.add_argument(
        '--summary',
        nargs='?',
        const='-',
        default=None,
        metavar='FILE',
        help='compute nothing: print a table of the cases asked for, kind by kind: how many the'
        " cache holds (how many in full) and each scenario's range of ceilings; or, given a"
        f" Markdown FILE, write it between FILE's {SUMMARY_MARKS[0]} and {SUMMARY_MARKS[1]}"
        ' lines',
    )
    ap.add_argument(
        '--list',
        action='store_true',
        help="compute nothing: print the file names of the cache's cases, loose or packed, one"
        ' a line',
    )


def build_parser() -> argparse.ArgumentParser:
    """Return the command-line options of ``python -m hexapod_adapt.online.ceilings_cli``."""
    ap = argparse.ArgumentParser(
        prog='ceiling', description='Cache the ceilings of a map: every gait under each damage.'
    )
    ap.add_argument(
        '--archive', type=input_file, default=None, help='map (default: the shipped default map)'
    )
    ap.add_argument('--engine', choices=ENGINES, default='mujoco', help='trial engine')
    ap.add_argument(
        '--scenarios',
        nargs='+',
        choices=SCENARIO_NAMES,
        default=None,
        help='failure scenarios, every orientation of each (default S1-S4 unless --damage is'
        ' given)',
    )
    ap.add_argument(
        '--damage-kind',
        nargs='+',
        choices=EXPERIMENT_KINDS,
        default=['lifted'],
        metavar='KIND',
        help="how the scenarios' legs fail, one or more of: "
        + ', '.join(EXPERIMENT_KINDS)
        + ' (default lifted, as in the thesis)',
    )
    ap.add_argument(
        '--damage',
        nargs='*',
        type=_damage_arg,
        default=[],
        metavar='SPEC',
        help='other damage, each LEG:KIND[:STRENGTH][,...], e.g. 1:locked,4:weak:0.3 (none'
        ' given: none, e.g. to drop those of an earlier --damage)',
    )
    ap.add_argument(
        '--partial',
        nargs='+',
        choices=EXPERIMENT_KINDS,
        default=[],
        metavar='KIND',
        help=f'kinds whose cases not cached yet walk only the intact-fastest {TOP_FRACTION:.0%}%'
        ' of the map (a partial ceiling: the rest estimated)',
    )
    ap.add_argument(
        '--top',
        type=number(int, 1, 10_000_000),
        default=None,
        help='approximate: evaluate only the TOP gaits that walk best under the damage on'
        ' --guide-engine (whose ceiling is read from, or made in, the cache)',
    )
    ap.add_argument('--guide-engine', choices=ENGINES, default='mujoco', help='for --top')
    ap.add_argument(
        '--cache-dir', type=output_dir, required=True, help='where ceilings are cached'
    )
    ap.add_argument('--workers', type=number(int, 1, 256), default=1, help='worker processes')
    _add_readings(ap)
    return ap


#: the lines a Markdown file's table of the cache lies between (``--summary FILE``)
SUMMARY_MARKS = ('<!-- ceilings-summary: start -->', '<!-- ceilings-summary: end -->')


def write_summary(path: Path, rows: list[str]) -> None:
    """Put ``rows`` between ``path``'s :data:`SUMMARY_MARKS` (written whole or not at all)."""
    text = path.read_text(encoding='utf-8')
    start, end = SUMMARY_MARKS
    a, b = text.find(start), text.find(end)
    if a < 0 or b < a:
        raise ValueError(f'{path} has no {start} line followed by an {end} line')
    table = '\n'.join(rows)
    atomic_write_bytes(path, f'{text[: a + len(start)]}\n{table}\n{text[b:]}'.encode())


class Case(NamedTuple):
    """One damage case asked for."""

    scenario: str  # '-' for a --damage
    kind: str  # 'other' for a --damage
    damage: Damage
    partial: bool


def asked_cases(args: argparse.Namespace) -> list[Case]:
    """Return the cases the options ask for: the full ones first, each in the order given."""
    scenarios = args.scenarios
    if scenarios is None:
        scenarios = [] if args.damage else ['S1', 'S2', 'S3', 'S4']
    cases = [
        Case(name, kind, Damage.of(kind, legs), kind in args.partial)
        for kind in dict.fromkeys(args.damage_kind)
        for name in scenarios
        for legs in scenario(name)
    ]
    cases += [Case('-', 'other', damage, False) for damage in args.damage]
    return sorted(cases, key=lambda case: case.partial)


def summary(cached: list[tuple[Case, Ceiling | None]]) -> list[str]:
    """Return a Markdown table of ``cached``: per kind, the cases held, each scenario's range."""
    names = list(dict.fromkeys(case.scenario for case, _ in cached))
    rows = [
        '| kind | cases cached (in full) | '
        + ' | '.join('other' if name == '-' else name for name in names)
        + ' |',
        '|---|---|' + '---|' * len(names),
    ]
    kinds = sorted(dict.fromkeys(case.kind for case, _ in cached), key=lambda k: k == 'other')
    for kind in kinds:
        mine = [(case.scenario, c) for case, c in cached if case.kind == kind]
        held = [c for _, c in mine if c is not None]
        cells = [kind, f'{len(held)} of {len(mine)} ({sum(c.walked is None for c in held)})']
        for name in names:
            best = [c.best_speed for n, c in mine if n == name and c is not None]
            cells.append(f'{min(best):.3f}-{max(best):.3f}' if best else '')
        rows.append('| ' + ' | '.join(cells) + ' |')
    return rows


def main(argv: list[str] | None = None) -> int:
    """Compute (or find in the cache) every ceiling asked for; one line per damage case."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if (args.missing or args.summary is not None) and args.top:
        parser.error('--missing and --summary read exact ceilings: leave out --top')
    if sum((args.missing, args.pack, args.list, args.summary is not None)) > 1:
        parser.error(
            '--missing, --pack, --list and --summary each compute nothing: give one of them'
        )

    def run() -> int:
        if args.list:
            print('\n'.join(sorted(cached_names(args.cache_dir))))
            return 0
        if args.pack:  # the cases cached so far, whatever is still missing
            packs = pack_ceilings(args.cache_dir)
            print(f'packed the loose cases of {args.cache_dir} into {len(packs)} packs')
            return 0
        archive = load_archive(args.archive or shipped_map(DEFAULT_MAP))
        cases = asked_cases(args)
        if args.missing or args.summary is not None:
            cached = [
                (case, cached_ceiling(archive, case.damage, args.engine, [args.cache_dir]))
                for case in cases
            ]
            if args.summary not in (None, '-'):
                write_summary(Path(args.summary), summary(cached))
            elif args.summary:
                print('\n'.join(summary(cached)))
            else:
                print(sum(c is None for _, c in cached))
            return 0
        full: list[Ceiling] = []  # the full cases made or read: they come first
        checked = False
        for name, _, damage, partial in cases:
            if partial and not checked:
                share = deepest_share(archive, full)
                if share > TOP_FRACTION:
                    print(
                        f"a full case's fastest gait lies at {share:.1%} of the intact order,"
                        f' past the partial share {TOP_FRACTION:.0%}: no partial case is made'
                        ' (raise ceiling.TOP_FRACTION; maps/ceilings/README.md)',
                        file=sys.stderr,
                    )
                    return 1
                checked = True
            t0 = time.monotonic()
            if args.top:
                guide = ceiling(archive, damage, args.guide_engine, args.cache_dir, args.workers)
                c = approximate_ceiling(
                    archive, damage, args.engine, guide, args.top, args.cache_dir, args.workers
                )
            else:
                c = ceiling(
                    archive, damage, args.engine, args.cache_dir, args.workers, partial=partial
                )
                if not partial:
                    full.append(c)
            print(
                f'{args.engine} {name} {damage.label}: ceiling {c.best_speed:.3f} m/s'
                f' (gait {c.best_niche}), {int(c.walked_mask.sum())} of {len(c.speeds)} gaits'
                f' walked, {time.monotonic() - t0:.0f} s',
                flush=True,
            )
        return 0

    return run_command(
        'ceiling',
        run,
        'finished damage cases are cached and the one in progress kept; run again to go on',
    )


if __name__ == '__main__':
    sys.exit(main())
