# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Does the leader fit? A damage the bank lacks against one it holds, open loop (issue 67).

With the default bank (the 21 lifted legs) a locked leg is named as some lifted leg at 1.00:
the posterior only compares hypotheses. This asks whether the leader's own fit tells the two
cases apart: each damage of ``--kinds`` (every leg set of S1-S4) walks the map's ``--gaits``
fastest gaits on MuJoCo at its converged step, in a ``--variant`` physics the hypotheses were
not walked in (``f0.6``: foot friction 0.6; ``s64``: servo compliance slope 64; ``stock``);
the same gaits are walked under the 21 lifted hypotheses on the map's engine. After the last
trial, the leader of the shipped weighing and its fit: the mean over the trials of its Student-t
log likelihood (0: a perfect match). Prints, per kind, the leaders on the right legs and how many
fit at least each floor. MuJoCo only: PyBullet and DART take no part in choosing a floor.

    python -m studies.diagnosis.fit_floor --variant f0.6
"""

from __future__ import annotations

import argparse

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
from hexapod_adapt.online.bank import BANK_DAMAGES
from hexapod_adapt.online.diagnosis import student_log_likelihood, Weighing
from hexapod_sim.damage import Damage
import numpy as np
from studies.diagnosis.calibration import posteriors, residuals, variant_physics

FLOORS = (-8.0, -10.0, -12.0, -14.0, -16.0, -20.0, -25.0)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--variant', default='stock')
    parser.add_argument(
        '--kinds', nargs='+', default=['lifted', 'locked', 'unpowered_femur', 'weak']
    )
    parser.add_argument('--gaits', type=int, default=3)
    args = parser.parse_args(argv)
    archive = load_archive(shipped_map(DEFAULT_MAP))
    elites = archive.elite_indices()
    order = np.argsort(-archive.fitness[elites], kind='stable')
    gaits = [int(n) for n in elites[order][: args.gaits]]
    bank = list(BANK_DAMAGES)  # the hypotheses come first among the walked damages
    others = [kind for kind in args.kinds if kind != 'lifted']
    damages = bank + [Damage.of(kind, d.failed_legs) for kind in others for d in bank]
    kind_of = ['lifted'] * len(bank) + [kind for kind in others for _ in bank]
    r = residuals(archive, damages, variant_physics(args.variant), gaits)
    keep = np.zeros(len(damages), bool)
    keep[: len(bank)] = True
    shipped = Weighing()
    print(
        f'variant {args.variant}: kind | leaders on the right legs | fit at least '
        + ', '.join(f'{f:g}' for f in FLOORS)
    )
    for kind in args.kinds:
        rows = [i for i, k in enumerate(kind_of) if k == kind]
        fits, right = [], 0
        for d in rows:
            last = posteriors(r[d], shipped.temperature, shipped.none_deviation, keep)[-1]
            lead = int(np.argmax(last[:-1]))
            walked = [g for g in range(len(gaits)) if np.isfinite(r[d, g, lead]).all()]
            fits.append(np.mean([student_log_likelihood(r[d, g, lead]) for g in walked]))
            right += damages[lead].failed_legs == damages[d].failed_legs
        fit = np.array(fits)
        counts = ', '.join(str(int(np.sum(fit >= f))) for f in FLOORS)
        print(f'{kind} | {right} of {len(rows)} | {counts}', flush=True)
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
