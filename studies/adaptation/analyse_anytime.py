# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
How good can a blind search be after n trials? M-BOA's best-so-far ratio, with no stopping rule.

On the tuning set (hexapod_adapt.online.replay: the seed-2 map, 63 cases of locked legs, weak
servos and lost tibias; replayed from ceilings), for each kernel the ratio best-so-far / ceiling
after 3, 6, 10, 16 and 24 trials (median and 10th percentile over the cases). Kernels:
- the default profile's (Matern 5/2 on the duty factors, rho 0.2, variance 0.01 (m/s)^2), run
  through the product's Mboa;
- 'bank features' (tried 2026-11-23): the same plus c x D D^T, with D (gaits x 21) each gait's
  speed change under the damage bank's 21 lifted failures (studies/out/bank). A Bayesian linear
  model over the bank's responses: damage of another kind may be a blend of the modelled ones. A
  full GP refit per trial here (the product has no such kernel); with c = 0 it picks the same
  trials as Mboa (checked below).
'Left out' rows: the 21 lifted cases of the bank, each with its own case dropped from D.

    python -m studies.adaptation.analyse_anytime  # its section of results/analyses.txt
"""

from __future__ import annotations

import argparse
from dataclasses import replace
import sys

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.online.bank import BANK_DAMAGES, load_bank
from hexapod_adapt.online.ceiling import cached_ceiling
from hexapod_adapt.online.mboa import matern52, Mboa, PROFILES
from hexapod_adapt.online.replay import control_speeds
import numpy as np
from scipy.linalg import cho_solve, solve_triangular
from studies.tuning_set import TUNING_DAMAGES

MAP = 'studies/out/tuning_map_s2.npz'
TRIALS = 24
AT = (3, 6, 10, 16, 24)


def mboa_curve(desc, prior, truth) -> list[float]:
    """Best-so-far ratio after each trial of the default profile, never stopping."""
    opt = Mboa(desc, prior, replace(PROFILES['default'], max_trials=TRIALS))
    out = []
    while len(opt.trials) < TRIALS:
        i = opt.next_index()
        opt.observe(i, float(truth[i]))
        out.append(opt.best().measured / truth.max())
    return out


def posterior(kernel, diag, prior, idx, ys, noise) -> tuple[np.ndarray, np.ndarray]:
    """GP posterior mean and variance of every gait after the trials ``idx`` measured ``ys``."""
    chol = np.linalg.cholesky(kernel[np.ix_(idx, idx)] + noise * np.eye(len(idx)))
    k_mt = kernel[:, idx]
    mu = prior + k_mt @ cho_solve((chol, True), np.array(ys) - prior[idx])
    v = solve_triangular(chol, k_mt.T, lower=True)
    return mu, diag - np.sum(v * v, axis=0)


def feature_curve(kernel, prior, truth, kappa, noise) -> tuple[list[float], list[int]]:
    """The same loop with a precomputed kernel matrix (full refit per trial)."""
    diag = np.diag(kernel).copy()
    idx, ys, out = [], [], []
    mu, var = prior.copy(), diag.copy()
    while len(ys) < TRIALS:
        ucb = mu + kappa * np.sqrt(np.maximum(var, 0.0))
        ucb[idx] = -np.inf
        i = int(np.argmax(ucb))
        idx.append(i)
        ys.append(float(truth[i]))
        out.append(max(ys) / truth.max())
        mu, var = posterior(kernel, diag, prior, idx, ys, noise)
    return out, idx


def with_rule(kernel, prior, truth, floor, cfg) -> tuple[float, int]:
    """
    One run with M-BOA's stopping rule and the product's floor (the feature kernel's loop).

    Stop when the best measured reaches alpha x the highest posterior mean and the floor.
    """
    diag = np.diag(kernel).copy()
    idx, ys = [], []
    mu, var = prior.copy(), diag.copy()
    while len(ys) < TRIALS:
        if ys and max(ys) >= floor and max(ys) >= cfg.alpha * mu.max():
            break
        ucb = mu + cfg.kappa * np.sqrt(np.maximum(var, 0.0))
        ucb[idx] = -np.inf
        i = int(np.argmax(ucb))
        idx.append(i)
        ys.append(float(truth[i]))
        mu, var = posterior(kernel, diag, prior, idx, ys, cfg.noise)
    return max(ys) / truth.max(), len(ys)


def line(label: str, curves: list[list[float]]) -> str:
    b = np.array(curves)
    cols = [n - 1 for n in AT]
    med = ' '.join(f'{np.median(b[:, j]):.3f}' for j in cols)
    p10 = ' '.join(f'{np.percentile(b[:, j], 10):.3f}' for j in cols)
    return f'{label:42s} median {med} | 10th pct {p10}'


def main(argv: list[str] | None = None) -> int:
    # no options: --help says what the study does instead of running it
    argparse.ArgumentParser(description=__doc__.strip().splitlines()[0]).parse_args(argv)
    archive = load_archive(MAP)
    niches = archive.elite_indices()
    desc, prior = archive.descriptors[niches], archive.speeds()[niches]
    bank = load_bank(archive, 'mujoco', ['studies/out/bank'])
    d = PROFILES['default']
    base = d.signal_variance * matern52(desc, desc, d.length_scale)
    out_set = {
        c: cached_ceiling(archive, c, 'mujoco', ['studies/out/ceilings']) for c in TUNING_DAMAGES
    }
    in_set = {c: cached_ceiling(archive, c, 'mujoco', ['studies/out/bank']) for c in BANK_DAMAGES}
    # the refit loop with c = 0 is the product's M-BOA: same trials on the first five cases
    for c in list(out_set.values())[:5]:
        _, idx = feature_curve(base, prior, c.speeds, d.kappa, d.noise)
        opt = Mboa(desc, prior, replace(d, max_trials=TRIALS))
        for _ in range(TRIALS):
            i = opt.next_index()
            opt.observe(i, float(c.speeds[i]))
        assert idx == [t.index for t in opt.trials], 'the replay is not the product M-BOA'
    print(f'best-so-far / ceiling after {", ".join(map(str, AT))} trials (no stopping rule)')
    print(
        line(
            'default profile, out of set (63)',
            [mboa_curve(desc, prior, c.speeds) for c in out_set.values()],
        )
    )
    print(
        line(
            'default profile, lifted (21)',
            [mboa_curve(desc, prior, c.speeds) for c in in_set.values()],
        )
    )
    for scale in (0.3, 1.0, 3.0):
        diff = bank.speeds.T - prior[:, None]
        kernel = base + scale * diff @ diff.T
        curves = [
            feature_curve(kernel, prior, c.speeds, d.kappa, d.noise)[0] for c in out_set.values()
        ]
        print(line(f'bank features c={scale:g}, out of set', curves))
        curves = []
        for dmg, c in in_set.items():
            diff = bank.without(dmg).speeds.T - prior[:, None]
            curves.append(
                feature_curve(base + scale * diff @ diff.T, prior, c.speeds, d.kappa, d.noise)[0]
            )
        print(line(f'bank features c={scale:g}, left out', curves), flush=True)
    # the same kernels with M-BOA's stopping rule and the damaged tripod as floor (the product's)
    floors = control_speeds(TUNING_DAMAGES, 'mujoco', archive.trial_duration)
    print('with the stopping rule (out of set): median / 10th pct / min ratio, median trials')
    for scale in (0.0, 0.3, 1.0, 3.0):
        diff = bank.speeds.T - prior[:, None]
        kernel = base + scale * diff @ diff.T
        runs = [with_rule(kernel, prior, c.speeds, floors[dmg], d) for dmg, c in out_set.items()]
        r = np.array([x for x, _ in runs])
        print(
            f'{"default profile" if scale == 0 else f"bank features c={scale:g}":42s}'
            f' {np.median(r):.3f} / {np.percentile(r, 10):.3f} / {r.min():.3f},'
            f' {np.median([t for _, t in runs]):.0f} trials',
            flush=True,
        )
    return 0


if __name__ == '__main__':
    sys.exit(main())
