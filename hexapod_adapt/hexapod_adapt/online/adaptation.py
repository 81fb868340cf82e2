# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
What an adaptation run's trials give and take (ROS-free): outcomes, results, aborts.

A trial function walks one gait of the map and returns its :class:`TrialOutcome` (or a bare
speed); :class:`~hexapod_adapt.online.session.AdaptationSession` decides which gait and when to
stop. :func:`simulated_trial` walks gaits in a simulator with damage (the thesis's experiment
5.2); adapt_node walks them through the ROS graph (:mod:`hexapod_adapt.online.trials`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
import math
from typing import Callable, Sequence

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.online.diagnosis import TrialRecord
from hexapod_adapt.online.mboa import MboaConfig, Trial
from hexapod_sim import evaluate_gait, Simulator
from hexapod_sim.damage import as_damage, Damage
from hexapod_sim.simulator import peak_tilt, upside_down
from hexapod_sim.traces import trace_gait
import numpy as np


@dataclass
class AdaptationResult:
    """The outcome of one adaptation run: trials, the best gait found and why it stopped."""

    success: bool  # the best gait met M-BOA's rule (alpha, the floor) when the run ended
    message: str
    trials: list[Trial] = field(default_factory=list)
    niches: list[int] = field(default_factory=list)  # archive niche of each trial
    tipped: list[int] = field(default_factory=list)  # niches whose trial the tip guard stopped
    vetoed: list[int] = field(default_factory=list)  # niches never tried: predicted to tip
    best_niche: int = -1
    best_speed: float = float('nan')
    elapsed: float = 0.0
    #: the M-BOA settings the run kept to: its request's, with what a prior or a floor changed
    config: MboaConfig | None = None
    #: what a blind run's diagnosis said: the damage named after each trial ('' none), in order
    named: list[str] = field(default_factory=list)
    #: the legs of what it named after each trial (() none): one leg set, whatever the kinds
    named_legs: list[tuple[int, ...]] = field(default_factory=list)
    posterior: str = ''  # the diagnosis's last posterior, its top hypotheses ('' no diagnosis)
    #: whether that posterior's most probable damage did not fit the trials (none in the bank
    #: does: the run went on blind)
    unfit: bool = False
    #: the trial after which the diagnosis widened its bank, none of the first fitting (0: never)
    widened: int = 0
    #: [s] spent re-scoring the damages it named whose re-scores were not cached (0: none)
    rescore_s: float = 0.0


@dataclass(frozen=True)
class TrialOutcome:
    """
    What one trial measured, when it can say more than a speed.

    ``tipped``: the body tilted past the tip guard and the trial was stopped; it counts as a
    failed trial (``speed`` 0) and that gait is never tried again. ``peak_tilt``: the largest
    roll or pitch the trial saw [rad] (nan if not measured). ``record``: the trial's path and
    attitude, for a diagnosis (None: not recorded).
    """

    speed: float  # m/s
    tipped: bool = False
    peak_tilt: float = float('nan')
    record: TrialRecord | None = None


#: The tip guard of adaptation trials [rad] (30 deg): half the tip-over line (60 deg,
#: hexapod_sim.simulator.TIP_OVER_DEG). Robots that tipped rolled at 70-150 deg/s
#: (studies/navigation/README.md), so a gait stopped at 30 deg still has 0.2-0.4 s to stand.
DEFAULT_TIP_GUARD = math.radians(30.0)


def tipped_outcome(peak_tilt: float, guard: float) -> TrialOutcome | None:
    """Return the failed outcome of a trial that tilted past ``guard`` [rad] (None if not)."""
    if math.isfinite(peak_tilt) and peak_tilt > guard:
        return TrialOutcome(0.0, True, float(peak_tilt))
    return None


class TrialAborted(RuntimeError):
    """
    A trial could not be completed (timeout, lost robot link, cancelled).

    The run stops and reports what it has.
    """


class WaitTimedOut(TrialAborted):
    """What a trial waited for did not come in time."""


class TrialCancelled(TrialAborted):
    """The run was cancelled while a trial waited (its goal's cancel)."""


def candidates(archive: Archive) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(niches, descriptors, prior speeds) of the archive's elites."""
    niches = archive.elite_indices()
    if len(niches) == 0:
        raise ValueError('the archive has no elites to try')
    return niches, archive.descriptors[niches], archive.speeds()[niches]


def simulated_trial(
    archive: Archive,
    failed_legs: Sequence[int] | Damage,
    sim: Simulator,
    duration: float | None = None,
    settle: float = 0.0,
    tip_guard: float = math.pi,
) -> Callable[[int], TrialOutcome]:
    """
    Trial function on ``sim`` (any engine) with ``failed_legs`` (leg numbers, or a Damage).

    ``tip_guard`` [rad]: a trial whose body tilts past it is a tipped, failed trial
    (:class:`TrialOutcome`; pi: no guard).

    Collisions are not fatal (thesis 5.2.2: the robot cannot detect them). The gait starts from
    standing; with ``settle`` > 0 it walks that long untimed and the speed is timed over the
    ``duration`` after, as a robot trial is. The simulation is deterministic, so that stretch is
    the difference of two evaluations from the same start: to ``settle + duration`` and to
    ``settle``.
    """
    duration = duration or archive.trial_duration

    def walk(genes: np.ndarray, seconds: float) -> tuple[float, float]:
        r = evaluate_gait(
            genes,
            sim,
            duration=seconds,
            collisions_fatal=False,
            failed_legs=failed_legs,
            record_tilt=True,
        )
        return r.fitness, r.peak_tilt

    def trial(niche: int) -> TrialOutcome:
        genes = archive.genotypes[niche]
        whole, peak = walk(genes, settle + duration)
        tipped = tipped_outcome(peak, tip_guard)
        if tipped is not None:
            return tipped
        if settle <= 0:
            return TrialOutcome(whole / duration, False, peak)
        return TrialOutcome((whole - walk(genes, settle)[0]) / duration, False, peak)

    return trial


def recorded_trial(
    archive: Archive,
    damage: Sequence[int] | Damage,
    sim: Simulator,
    duration: float | None = None,
    settle: float = 0.0,
    tip_guard: float = math.pi,
    contacts: bool = False,
) -> Callable[[int], TrialOutcome]:
    """
    Trial function as :func:`simulated_trial`, whose outcomes carry the trial's record.

    One walk, sampled every physics step (as an evaluation's loop steps it): the speed, the
    peak tilt and a fall are taken from it as an evaluation takes them; its record is timed
    from the gait's start (``contacts``: with the foot contacts, which a robot does not give).
    """
    duration = duration or archive.trial_duration
    damage = as_damage(damage)

    def trial(niche: int) -> TrialOutcome:
        trace = trace_gait(archive.genotypes[niche], sim, damage, settle + duration, every=1)
        if trace is None:
            return TrialOutcome(0.0)
        peak = peak_tilt(trace.quaternion)
        tipped = tipped_outcome(peak, tip_guard)
        if tipped is not None:
            return tipped
        record = TrialRecord.from_trace(trace, contacts)
        if upside_down(trace.quaternion[-1]):
            return TrialOutcome(0.0, False, peak, record)
        start = int(round(settle / sim.dt)) - 1  # the sample at settle s (-1: the start)
        crab = trace.gait.crab_angle
        moved = trace.position[-1, :2] - (trace.position[start, :2] if start >= 0 else 0.0)
        speed = float(moved[0] * math.cos(crab) + moved[1] * math.sin(crab)) / duration
        return TrialOutcome(speed, False, peak, record)

    return trial


def map_speed(
    archive: Archive, niche: int, damage: Sequence[int] | Damage, sim: Simulator
) -> float:
    """
    Return a gait's speed [m/s] as the map's ceilings score it, under ``damage`` on ``sim``.

    The map's trial duration from standing, collisions not fatal: the measure that makes runs
    with any trial timing comparable with each other, the ceiling and the control tripod.
    """
    return evaluate_gait(
        archive.genotypes[niche],
        sim,
        duration=archive.trial_duration,
        collisions_fatal=False,
        failed_legs=damage,
    ).speed
