# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Replaying adaptation runs against ceilings: M-BOA with trials answered from a table (ROS-free).

A ceiling (:mod:`hexapod_adapt.online.ceiling`) holds every gait of a map evaluated under one
damage, so an adaptation run under that damage can be replayed without a simulator: each trial's
speed is looked up. Studies (``studies/``) score M-BOA settings this way on damage cases they
choose; the library holds no damage set of its own.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Iterable, Sequence

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.online.adaptation import AdaptationResult
from hexapod_adapt.online.bank import DamageBank
from hexapod_adapt.online.ceiling import Ceiling
from hexapod_adapt.online.mboa import MboaConfig
from hexapod_adapt.online.session import adapt, SessionStart
from hexapod_gait import preset
from hexapod_sim import create_simulator, evaluate_gait, SimConfig
from hexapod_sim.damage import Damage
import numpy as np


def lookup_trial(c: Ceiling) -> Callable[[int], float]:
    """Return a trial function that answers a gait's speed under ``c``'s damage from ``c``."""
    speed = dict(zip(c.niches.tolist(), c.speeds.tolist()))
    return lambda niche: speed[int(niche)]


@dataclass(frozen=True)
class TuningRun:
    """One replayed adaptation run on one damage case."""

    damage: str
    kind: str
    legs: int  # number of damaged legs
    trials: int
    success: bool
    best_speed: float  # m/s
    ceiling_speed: float  # m/s
    ratio: float  # best / ceiling
    control_speed: float  # the damaged control tripod [m/s] (the floor)
    walking_time: float  # s


def replay(
    archive: Archive,
    c: Ceiling,
    config: MboaConfig,
    control_speed: float = 0.0,
    bank: DamageBank | None = None,
) -> AdaptationResult:
    """
    Run M-BOA on ``archive`` with trials answered from ``c`` (floor: ``control_speed``).

    With ``bank`` and ``config.use_bank``, the bank's hypotheses too.
    """
    hypotheses = bank.hypotheses(config.use_bank) if bank is not None else None
    start = SessionStart(hypotheses=hypotheses, floor=control_speed)
    return adapt(archive, lookup_trial(c), config, start)


def control_speeds(damages: Iterable[Damage], engine: str, duration: float) -> dict[Damage, float]:
    """Return the control tripod's speed under each damage on ``engine`` [m/s]."""
    with create_simulator(SimConfig(engine=engine)) as sim:
        return {
            d: evaluate_gait(
                preset('control'), sim, duration=duration, collisions_fatal=False, failed_legs=d
            ).speed
            for d in damages
        }


def score(
    archive: Archive,
    ceilings: Sequence[Ceiling],
    controls: dict[Damage, float],
    config: MboaConfig,
    bank: DamageBank | None = None,
) -> list[TuningRun]:
    """Replay one run per damage case with ``config`` (and ``bank``, if it uses one)."""
    runs = []
    for c in ceilings:
        result = replay(archive, c, config, controls[c.damage], bank)
        runs.append(
            TuningRun(
                c.damage.label,
                c.damage.legs[0].kind if c.damage.legs else 'intact',
                len(c.damage.legs),
                len(result.trials),
                result.success,
                result.best_speed,
                c.best_speed,
                result.best_speed / c.best_speed,
                controls[c.damage],
                len(result.trials) * archive.trial_duration,
            )
        )
    return runs


@dataclass(frozen=True)
class Summary:
    """A setting's figures over the tuning set (the issue's acceptance figures)."""

    runs: int
    ratio_median: float
    ratio_min: float
    ratio_p10: float  # 10th percentile
    ratio_median_worst_group: float  # lowest median over (kind, number of legs) groups
    trials_median: float
    trials_max: int
    walking_median: float  # s
    below_control: int  # runs whose best is slower than the damaged control tripod


def summarise(runs: Sequence[TuningRun]) -> Summary:
    """Return the figures of ``runs``."""
    ratio = np.array([r.ratio for r in runs])
    trials = np.array([r.trials for r in runs])
    groups: dict[tuple[str, int], list[float]] = {}
    for r in runs:
        groups.setdefault((r.kind, r.legs), []).append(r.ratio)
    return Summary(
        len(runs),
        float(np.median(ratio)),
        float(np.min(ratio)),
        float(np.percentile(ratio, 10)),
        min(float(np.median(v)) for v in groups.values()),
        float(np.median(trials)),
        int(np.max(trials)),
        float(np.median([r.walking_time for r in runs])),
        sum(r.best_speed < r.control_speed for r in runs),
    )


def residual_statistics(archive: Archive, ceilings: Sequence[Ceiling]) -> dict[str, float]:
    """
    How far damage moves speeds from the map's prediction, over the tuning set [(m/s)^2].

    ``total``: variance of (damaged - map) speed over every gait and case; ``within``: its
    variance about each case's own mean (what a GP around the map's prior has to learn).
    """
    prior = archive.speeds()
    total, within = [], []
    for c in ceilings:
        r = c.speeds - prior[c.niches]
        total.append(r)
        within.append(r - r.mean())
    return {
        'total': float(np.var(np.concatenate(total))),
        'within': float(np.var(np.concatenate(within))),
        'mean': float(np.mean(np.concatenate(total))),
    }
