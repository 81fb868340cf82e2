# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The robust-speed study's candidate maps (studies/robust_speed/README.md), in one place.

``python -m studies.robust_speed.candidates`` prints one ``NAME:VARIANTS:STATISTIC`` a line, the
longest run first: robust_study.sh starts the maps from it, resume_long_runs.sh counts them.
"""

from __future__ import annotations

import argparse

#: name -> (variants per gait, statistic); 0 variants: the nominal map (one walk per gait).
CANDIDATES: dict[str, tuple[int, str]] = {
    'nominal': (0, 'min'),
    'k4_min': (4, 'min'),
    'k4_q25': (4, 'q25'),
    'k4_mean-std': (4, 'mean-std'),
    'k8_min': (8, 'min'),
    'k8_q25': (8, 'q25'),
    'k8_mean-std': (8, 'mean-std'),
}


def main(argv: list[str] | None = None) -> None:
    # no options: --help says what the study does instead of running it
    argparse.ArgumentParser(description=__doc__.strip().splitlines()[0]).parse_args(argv)
    for name, (variants, statistic) in CANDIDATES.items():
        print(f'{name}:{variants}:{statistic}')


if __name__ == '__main__':
    main()
