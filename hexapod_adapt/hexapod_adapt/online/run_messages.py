# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
What adapt_node does around a session, without ROS: a run's trial procedure and its lines.

The trials' timing in each mode, the trial procedure of each mode, and the lines a run logs and
answers. The node converts messages and parameters; the decisions are here and in
:mod:`hexapod_adapt.online.session`, tested without a graph.
"""

from __future__ import annotations

from dataclasses import dataclass
import math
from typing import Callable

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.online.adaptation import AdaptationResult
from hexapod_adapt.online.diagnosis import Posterior
from hexapod_adapt.online.mboa import MboaConfig, Trial
from hexapod_adapt.online.trials import (
    GaitOf,
    ManualTrials,
    reported_distance_problem,
    RobotTrials,
    SimTrials,
    TrialLogs,
    TrialPort,
    TrialTiming,
    Waiter,
)
from hexapod_description.model import load_model
from hexapod_gait import from_genotype
from hexapod_sim.damage import Damage

Log = Callable[[str], None]


@dataclass(frozen=True)
class RunRequest:
    """One adapt request, checked: M-BOA's settings, the trial length, the prior's damage."""

    config: MboaConfig
    duration: float  # s timed per trial, as asked for
    damage: Damage | None  # the prior's damage (None: the map as it is)
    source: str  # where the damage comes from, or why there is none
    auto: bool  # the damage is whatever is reported (not named by the request, not blind)


#: A run's trial procedure, one per mode.
TrialProcedure = SimTrials | RobotTrials | ManualTrials


def trial_walk(
    mode: str, duration: float, settle: float, bridge: tuple[float, float] | None, warn: Log
) -> tuple[float, float]:
    """
    Return (timed, settling) seconds of a run's trials.

    Sim mode: ``duration`` and the node's ``settle``. On the robot, what bridge_node walks
    (``bridge``: its trial_duration and trial_settle, one home for them); ``duration`` from
    standing if it did not say.
    """
    if mode == 'sim':
        return duration, settle
    if bridge is None:
        warn(
            'bridge_node did not say how it walks a trial (its trial_duration and'
            f' trial_settle): assuming {duration:g} s from standing'
        )
        return duration, 0.0
    if abs(bridge[0] - duration) > 1e-6:
        warn(
            f'trials of {duration:g} s were asked for, but bridge_node walks {bridge[0]:g} s'
            ' timed: its trial_duration is used (set it on bridge_node to change a robot trial)'
        )
    return bridge


def archive_gaits(archive: Archive) -> GaitOf:
    """Return the gait of each niche of ``archive``, its ``archive_index`` set."""
    return lambda niche: from_genotype(archive.genotypes[niche]).replace(archive_index=int(niche))


def trial_procedure(
    mode: str,
    gaits: GaitOf,
    port: TrialPort,
    logs: TrialLogs,
    waiter: Waiter,
    timing: TrialTiming,
    warn: Log,
    tip_guard: float = math.pi,
) -> TrialProcedure:
    """
    Return the trial function of ``mode`` (sim, robot or manual) for the ``gaits`` of a map.

    ``logs``: what ``port`` has received (odometry, robot trial results, the IMU's tilts).
    ``tip_guard`` [rad]: sim and robot trials that tilt the body past it are stopped (the
    odometry's attitude in sim, the robot's IMU on the robot); a manual trial has no attitude to
    watch. ``warn`` hears what a run must tell its operator: a fault, a prompt.
    """
    if mode == 'sim':
        return SimTrials(gaits, port, logs.odom, waiter, timing, warn, tip_guard)
    if mode == 'robot':
        return RobotTrials(
            gaits, port, logs.results, waiter, timing, port.link_problem, warn,
            load_model().max_walking_speed, tilts=logs.tilts, tip_guard=tip_guard,
            link_heard=port.link_heard,
        )  # fmt: skip
    return ManualTrials(gaits, port, logs.results, waiter, timing, warn)


def duplicate_problem(name: str, count: int) -> str:
    """Say why a run cannot go on with ``count`` nodes named ``name`` ('' when one or none)."""
    if count <= 1:
        return ''
    return (
        f'{count} nodes named {name} are in the graph: trials would be ambiguous; stop the extra'
        ' one (or rename it with --ros-args -r __node:=NAME) and call adapt again'
    )


def start_message(archive: Archive, config: MboaConfig, timing: TrialTiming, note: str) -> str:
    """Return the line a run logs as it starts."""
    return (
        f'adaptation started: {archive.n_filled} gaits, at most {config.max_trials} trials '
        f'of {timing.duration:g} s'
        + (f' after {timing.settle:g} s of settling' if timing.settle else '')
        + f', alpha {config.alpha:g}, kappa {config.kappa:g}'
        + (f'; {note}' if note else '')
    )


def trial_message(trial: Trial, niche: int) -> str:
    """Return the line a run logs after each trial."""
    if trial.tipped:
        return (
            f'trial {trial.number}: gait {niche} tilted the body past the tip guard: stopped,'
            f' counted as 0 m/s and never tried again (map {trial.predicted:.3f} m/s)'
        )
    return (
        f'trial {trial.number}: gait {niche} walked {trial.measured:.3f} m/s '
        f'(map {trial.predicted:.3f}, GP {trial.gp_mean:.3f} +/- {trial.gp_std:.3f})'
    )


def veto_message(niche: int, tilt: float, guard: float, risk: float | None = None) -> str:
    """Return the line a run logs when the tip screen (or the safety model) skips a gait."""
    if risk is not None:
        return (
            f'gait {niche} skipped: a {risk:.0%} risk that it tilts the body past the'
            f' {math.degrees(guard):.0f} deg tip guard (predicted {math.degrees(tilt):.0f} deg,'
            ' the damage not known); never tried'
        )
    return (
        f'gait {niche} skipped: it tilts the body {math.degrees(tilt):.0f} deg in simulation'
        f' under the damage, past the {math.degrees(guard):.0f} deg tip guard; never tried'
    )


#: What a run says of a damage it named whose re-score is not cached (made before its next trial).
RESCORE_PENDING = "no re-score cached: the map's fastest gaits are walked under it first"


def rescore_note(named: str) -> str:
    """Say that ``named``, just named, is re-scored before the next trial (not cached)."""
    return f'{named} named, {RESCORE_PENDING}'


def diagnosis_message(
    trial: int,
    named: str,
    posterior: Posterior,
    unfit: bool = False,
    widened: int = 0,
    rescoring: bool = False,
) -> str:
    """
    Say what the trials so far point to, e.g. after trial 2: legs 1+4 lifted 0.97 (named).

    ``unfit``: the most probable damage does not fit the trials (none in the bank does).
    ``widened``: the trial after which the diagnosis went to its wider bank (0: never).
    ``rescoring``: the damage named has no re-score cached: it is made before the next trial.
    """
    wider = ' (none of the first bank fits them: every trial weighed over the wider bank)'
    if named:
        going = f'; the run goes on as {named}'
        if rescoring:
            going += f' ({RESCORE_PENDING})'
    elif unfit:
        going = '; no hypothesis fits the trials: the run goes on blind'
    else:
        going = '; no damage named yet'
    return (
        f'diagnosis after trial {trial}{wider if widened == trial else ""}:'
        f' {posterior.describe()}{going}'
    )


def report_distance(trials: TrialProcedure | None, distance: float) -> str:
    """Hand an operator's measured distance [m] to a waiting manual trial; '' or why not."""
    if isinstance(trials, ManualTrials):
        return trials.report(distance)
    return reported_distance_problem(distance) or 'no manual trial is waiting for a distance'


def start_note(prior: str, servo_check: str = '') -> str:
    """Return what a run tells its operator as it starts: M-BOA's prior, and why."""
    return f'M-BOA starts from {prior}' + (f' ({servo_check})' if servo_check else '')


def result_message(result: AdaptationResult, note: str, recording_problem: str) -> str:
    """Return the adapt response's message: the run's, with the engine note and recording."""
    message = result.message + (f' ({note})' if note else '')
    if result.vetoed:
        gaits = ', '.join(map(str, result.vetoed))
        # by the damage's tip screen, or a blind run's safety model (the log says which)
        message += f'; never tried, predicted to tip past the tip guard: gait(s) {gaits}'
    return message + (f'; recording: {recording_problem}' if recording_problem else '')


def finish_message(result: AdaptationResult) -> str:
    """Return the line a run logs as it ends."""
    best = (
        f'best gait {result.best_niche} at {result.best_speed:.3f} m/s'
        if result.best_niche >= 0
        else 'no gait walked without tipping: none is left on the robot'
    )
    rescored = (
        f' (re-scoring the damage it named took {result.rescore_s:.0f} s)'
        if result.rescore_s > 0
        else ''
    )
    return f'adaptation finished: {result.message}; {len(result.trials)} trials, {best}{rescored}'


def shutdown_message(result: AdaptationResult) -> str:
    """Return the one line a run logs when its node shuts down in the middle of it."""
    best = (
        f'; best gait {result.best_niche} at {result.best_speed:.3f} m/s'
        if result.best_niche >= 0
        else ''
    )
    return (
        f'shutting down: the adaptation ended after {len(result.trials)} trials{best}; the best'
        ' gait was not left on the robot or the simulator (the recording holds every completed'
        ' trial)'
    )
