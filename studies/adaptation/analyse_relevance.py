# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Tried 2026-11-23, not adopted: M-BOA over a mixture of kernels, one per failure hypothesis.

A lifted leg's duty factor no longer matters, so each hypothesis (intact, each leg, each pair of
legs: 22) uses the default profile's Matern kernel without the duty factors of its failed legs;
the prior mean is the map's for all (no simulation of the damage). Hypotheses are weighted by
their GP marginal likelihood (with the determinant), as hexapod_adapt.online.mboa.mixture does.
Replayed on the tuning set (the seed-2 map; 63 out-of-set cases, and its 21 lifted cases): the
best-so-far ratio after 3, 6, 10, 16, 24 trials with no stopping rule, then with M-BOA's rule and
the damaged tripod as floor. 'single' is the default profile (it reproduces
studies/adaptation/results/analyses.txt).

    python -m studies.adaptation.analyse_relevance 0.2  # its section of results/analyses.txt
"""

from __future__ import annotations

import argparse
import itertools
import sys

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.online.bank import BANK_DAMAGES
from hexapod_adapt.online.ceiling import cached_ceiling
from hexapod_adapt.online.mboa import matern52, PROFILES
from hexapod_adapt.online.replay import control_speeds
import numpy as np
from scipy.linalg import solve_triangular
from studies.tuning_set import TUNING_DAMAGES

MAP = 'studies/out/tuning_map_s2.npz'
#: failure hypotheses: the legs (0-based descriptor dimensions) whose duty factors are ignored
HYPOTHESES = [()] + [(i,) for i in range(6)] + list(itertools.combinations(range(6), 2))
AT = (3, 6, 10, 16, 24)


def run(kernels, prior, truth, floor, rule: bool, budget: int = 24):
    """One replayed run over a mixture of ``kernels`` (h, m, m); default profile otherwise."""
    d = PROFILES['default']
    s2 = d.signal_variance
    idx, ys, best = [], [], []
    mu, var = prior.copy(), np.full(len(prior), s2)
    while len(ys) < budget:
        if rule and ys and max(ys) >= floor and max(ys) >= d.alpha * mu.max():
            break
        ucb = mu + d.kappa * np.sqrt(np.maximum(var, 0.0))
        ucb[idx] = -np.inf
        i = int(np.argmax(ucb))
        idx.append(i)
        ys.append(float(truth[i]))
        best.append(max(ys) / truth.max())
        y = np.array(ys) - prior[idx]
        means, variances, log_w = [], [], []
        for k in kernels:
            chol = np.linalg.cholesky(k[np.ix_(idx, idx)] + d.noise * np.eye(len(idx)))
            white = solve_triangular(chol, y, lower=True)
            k_mt = k[:, idx]
            means.append(prior + k_mt @ solve_triangular(chol.T, white, lower=False))
            v = solve_triangular(chol, k_mt.T, lower=True)
            variances.append(s2 - np.sum(v * v, axis=0))
            log_w.append(-0.5 * white @ white - np.sum(np.log(np.diag(chol))))
        w = np.exp(np.array(log_w) - max(log_w))
        w /= w.sum()
        means = np.array(means)
        mu = w @ means
        var = w @ np.array(variances) + w @ (means - mu) ** 2
    return (max(ys) / truth.max(), len(ys)) if rule else best


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument(
        'rho', type=float, nargs='?', default=PROFILES['default'].length_scale,
        help="the kernels' length scale (default: the default profile's)",
    )  # fmt: skip
    rho = ap.parse_args(argv).rho
    archive = load_archive(MAP)
    niches = archive.elite_indices()
    desc, prior = archive.descriptors[niches], archive.speeds()[niches]
    s2 = PROFILES['default'].signal_variance
    kernels = np.array(
        [
            s2 * matern52(desc[:, keep], desc[:, keep], rho)
            for keep in ([k for k in range(6) if k not in h] for h in HYPOTHESES)
        ]
    )
    sets = {
        'out': {
            c: cached_ceiling(archive, c, 'mujoco', ['studies/out/ceilings'])
            for c in TUNING_DAMAGES
        },
        'lifted': {
            c: cached_ceiling(archive, c, 'mujoco', ['studies/out/bank']) for c in BANK_DAMAGES
        },
    }
    floors = control_speeds(TUNING_DAMAGES + BANK_DAMAGES, 'mujoco', archive.trial_duration)
    cols = [n - 1 for n in AT]
    for label, cases in sets.items():
        for name, ks in (('single', kernels[:1]), ('mixture', kernels)):
            curves = np.array(
                [run(ks, prior, c.speeds, floors[d], False) for d, c in cases.items()]
            )
            med = ' '.join(f'{np.median(curves[:, j]):.3f}' for j in cols)
            p10 = ' '.join(f'{np.percentile(curves[:, j], 10):.3f}' for j in cols)
            print(f'rho={rho} {label:6s} {name} median {med} | p10 {p10}', flush=True)
            runs = [run(ks, prior, c.speeds, floors[d], True) for d, c in cases.items()]
            r = np.array([x for x, _ in runs])
            print(
                f'   with rule: {np.median(r):.3f} / {np.percentile(r, 10):.3f} / {r.min():.3f},'
                f' {np.median([t for _, t in runs]):.0f} trials',
                flush=True,
            )
    return 0


if __name__ == '__main__':
    sys.exit(main())
