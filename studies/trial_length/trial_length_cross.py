# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Trial length across engines, on the tuning set: the MuJoCo tuning map, trials on PyBullet.

No ratios (PyBullet's ceilings are contact artifacts, docs/adaptation.md): each run's adapted gait
is judged by its speed over 5 s from standing under the damage on PyBullet (the map's measure),
against the damaged control tripod there (each run's success floor, as in the product). Every
third tuning case (21), default profile, budget 24, for the thesis's trial (5 s from standing)
and settled trials (1 s, then 2, 3 or 5 s timed).

    python -m studies.trial_length.trial_length_cross  # its section of results/trial_length.txt
"""

from __future__ import annotations

import argparse
from dataclasses import replace
import sys

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.online.adaptation import map_speed, simulated_trial
from hexapod_adapt.online.mboa import PROFILES, TRIAL_BUDGET
from hexapod_adapt.online.replay import control_speeds
from hexapod_adapt.online.session import adapt, SessionStart
from hexapod_sim import create_simulator, SimConfig
import numpy as np
from studies.tuning_set import TUNING_DAMAGES

MAP = 'studies/out/tuning_map_s2.npz'
ENGINE = 'pybullet'
TRIALS = ((0.0, 5.0), (1.0, 2.0), (1.0, 3.0), (1.0, 5.0))  # (settle, timed) [s]


def main(argv: list[str] | None = None) -> int:
    # no options: --help says what the study does instead of running it
    argparse.ArgumentParser(description=__doc__.strip().splitlines()[0]).parse_args(argv)
    archive = load_archive(MAP)
    damages = TUNING_DAMAGES[::3]
    controls = control_speeds(damages, ENGINE, archive.trial_duration)
    print(
        f'{len(damages)} tuning cases, trials on {ENGINE}; damaged tripod mean'
        f' {np.mean(list(controls.values())):.3f} m/s'
    )
    print(
        'settle + timed   speed median  25th pct  beat the tripod  trials median  walking median'
    )
    with create_simulator(SimConfig(engine=ENGINE)) as sim:
        for settle, timed in TRIALS:
            speeds, beats, trials, walking = [], 0, [], []
            for d in damages:
                config = replace(PROFILES['default'], max_trials=TRIAL_BUDGET)
                result = adapt(
                    archive,
                    simulated_trial(archive, d, sim, timed, settle),
                    config,
                    SessionStart(floor=controls[d]),
                )
                judged = map_speed(archive, result.best_niche, d, sim)
                speeds.append(judged)
                beats += judged > controls[d]
                trials.append(len(result.trials))
                walking.append(len(result.trials) * (settle + timed))
            print(
                f'{settle:g} + {timed:g} s        {np.median(speeds):.3f}         '
                f'{np.percentile(speeds, 25):.3f}     {beats} of {len(damages)}          '
                f'{np.median(trials):.0f}             {np.median(walking):.0f} s',
                flush=True,
            )
    return 0


if __name__ == '__main__':
    sys.exit(main())
