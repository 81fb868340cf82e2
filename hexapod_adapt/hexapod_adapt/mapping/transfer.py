# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
How a map's gaits walk on physics that did not make it (ROS-free).

The figures that decide about a map are measured on another engine than the one that made it:
its fastest gaits' median speed and how many of them tip over, and how well that engine's speed
ranking agrees with the map's over its fastest gaits and some at random. Intact robot, 5 s from
standing, collisions not fatal (as a robot trial: the robot cannot tell).
"""

from __future__ import annotations

from dataclasses import dataclass
import math

from hexapod_adapt.mapping.archive import Archive
from hexapod_sim import evaluate_gaits, Simulator
from hexapod_sim.simulator import TIP_OVER_DEG
import numpy as np
from scipy.stats import spearmanr


@dataclass(frozen=True)
class TransferFigures:
    """A map's gaits on one engine: its ``top`` fastest, and the ranking over ``ranked`` gaits."""

    engine: str
    top: int
    top_speed_median: float  # m/s on ``engine``
    top_tipped: int  # of the ``top`` fastest, how many tilted past TIP_OVER_DEG or fell
    spearman: float  # the map's speeds against ``engine``'s over the ranked gaits
    ranked: int
    top_map_speed_median: float  # m/s, the map's own figure for the same gaits


def ranked_gaits(archive: Archive, fastest: int = 300, random: int = 100, seed: int = 0):
    """
    Return the niches to rank: the ``fastest`` by the map's speed, then ``random`` others.

    The random ones are drawn without replacement (seeded) from the elites not among the fastest.
    """
    elites = archive.elite_indices()
    speeds = archive.speeds()
    order = elites[np.argsort(-speeds[elites], kind='stable')]
    top, rest = order[:fastest], order[fastest:]
    rng = np.random.default_rng(seed)
    others = rng.choice(rest, min(random, len(rest)), replace=False) if len(rest) else rest
    return np.concatenate([top, others]).astype(np.int64)


def transfer_figures(
    archive: Archive,
    sim: Simulator,
    top: int = 100,
    fastest: int = 300,
    random: int = 100,
    seed: int = 0,
) -> TransferFigures:
    """Walk the map's ranked gaits (:func:`ranked_gaits`) on ``sim``, intact; its figures."""
    if top > fastest:
        raise ValueError(f'the top {top} must be among the {fastest} fastest')
    niches = ranked_gaits(archive, fastest, random, seed)
    results = evaluate_gaits(
        list(archive.genotypes[niches]),
        sim,
        collisions_fatal=False,
        failed_legs=(),
        record_tilt=True,
    )
    speeds = np.array([r.speed for r in results])
    tipped = np.array([r.peak_tilt > math.radians(TIP_OVER_DEG) for r in results])
    map_speeds = archive.speeds()[niches]
    n = min(top, len(niches))
    rho = float(spearmanr(map_speeds, speeds)[0]) if len(niches) > 2 else float('nan')
    return TransferFigures(
        engine=sim.engine,
        top=n,
        top_speed_median=float(np.median(speeds[:n])),
        top_tipped=int(tipped[:n].sum()),
        spearman=rho,
        ranked=len(niches),
        top_map_speed_median=float(np.median(map_speeds[:n])),
    )
