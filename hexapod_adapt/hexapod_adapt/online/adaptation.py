# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
An adaptation run: M-BOA over an archive's elites with a trial function (ROS-free).

``adapt(archive, trial, config)`` asks ``trial(niche)`` for the measured speed [m/s] of the
elite in ``niche`` until M-BOA's stopping rule holds. The trial function is where the world
comes in: the simulator with damage (:func:`simulated_trial`, the thesis's experiment 5.2),
or, in ``adapt_node``, a trial through the ROS graph on the simulator or the robot.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
import math
import time
from typing import Callable, Sequence, TYPE_CHECKING

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.simulation import engine_of_map, map_physics
from hexapod_adapt.online.mboa import Mboa, MboaConfig, MIN_SPEED_RANGE, StopReason, Trial
from hexapod_adapt.online.prior import simulated_tilts, TipScreen
from hexapod_gait import preset
from hexapod_sim import create_simulator, evaluate_gait, SimConfig, Simulator
from hexapod_sim.damage import Damage
from hexapod_sim.scenarios import scenario as orientations_of
import numpy as np

if TYPE_CHECKING:  # the ceiling module imports this one's siblings only
    from hexapod_adapt.online.bank import DamageBank
    from hexapod_adapt.online.ceiling import Ceiling


@dataclass
class AdaptationResult:
    """The outcome of one adaptation run: trials, the best gait found and why it stopped."""

    success: bool  # the best gait met M-BOA's rule (alpha, the floor) when the run ended
    message: str
    trials: list[Trial] = field(default_factory=list)
    niches: list[int] = field(default_factory=list)  # archive niche of each trial
    tipped: list[int] = field(default_factory=list)  # niches whose trial the tip guard stopped
    vetoed: list[int] = field(default_factory=list)  # niches never tried: they tip in simulation
    best_niche: int = -1
    best_speed: float = float('nan')
    elapsed: float = 0.0


@dataclass(frozen=True)
class TrialOutcome:
    """
    What one trial measured, when it can say more than a speed.

    ``tipped``: the body tilted past the tip guard and the trial was stopped; it counts as a
    failed trial (``speed`` 0) and that gait is never tried again. ``peak_tilt``: the largest
    roll or pitch the trial saw [rad] (nan if not measured).
    """

    speed: float  # m/s
    tipped: bool = False
    peak_tilt: float = float('nan')


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


def _with_prior(opt: Mboa, prior: np.ndarray) -> Mboa:
    """Return M-BOA started again from ``prior``, with ``opt``'s trials learned again."""
    again = Mboa(opt.descriptors, prior, opt.config, hypotheses=opt.hypotheses)
    again.vetoed = set(opt.vetoed)
    for t in opt.trials:
        again.observe(t.index, t.measured, tipped=t.tipped)
    return again


def adapt(
    archive: Archive,
    trial: Callable[[int], float | TrialOutcome],
    config: MboaConfig | None = None,
    on_trial: Callable[[Trial, int, Mboa], None] | None = None,
    should_cancel: Callable[[], bool] | None = None,
    floor: Callable[[], float] | None = None,
    prior: np.ndarray | None = None,
    hypotheses: np.ndarray | None = None,
    prior_update: Callable[[], np.ndarray | None] | None = None,
    screen: TipScreen | None = None,
    on_veto: Callable[[int, float], None] | None = None,
) -> AdaptationResult:
    """
    Run M-BOA until it stops (never more than ``config.max_trials`` trials).

    ``trial(niche)`` returns the measured speed, or a :class:`TrialOutcome`: one that tipped
    counts as a failed trial (0 m/s) and its gait is never tried again.

    ``prior``, if given, replaces the map's speeds as M-BOA's prior mean: one speed per elite, in
    the order of ``archive.elite_indices()`` (e.g. the map re-scored under a known damage,
    :mod:`hexapod_adapt.online.prior`). ``hypotheses`` (h, elites), if given, are other prior means
    the trials weigh against it (a damage bank's speeds, :mod:`hexapod_adapt.online.bank`).

    ``floor``, if given, measures a reference before the first trial, e.g. the damaged control
    tripod (:func:`tripod_floor`): success then also needs the best gait to walk at least that
    fast (and at least ``config.min_speed``).

    ``prior_update``, if given, is asked before each trial for a newer prior (None: no change),
    e.g. a re-score still streaming in (:mod:`hexapod_adapt.online.streaming_prior`); M-BOA then
    starts from it again and re-learns the trials so far.

    ``screen``, if given (a :class:`~hexapod_adapt.online.prior.TipScreen`), is asked about each
    gait before it is tried, and about the gait that sets alpha's bar before the run may stop: a
    gait that tips in simulation is vetoed (never tried, and no bar), and M-BOA picks again;
    ``on_veto(niche, tilt)``, if given, hears of each (tilt in rad).

    With ``prior`` or ``prior_update`` the run stops on alpha alone (``config.stop_gain`` is for
    blind runs).
    """
    config = config or MboaConfig()
    if (prior is not None or prior_update is not None) and config.stop_gain > 0:
        # the known damage's re-score is trusted: its best, tried first, ends the run on alpha
        config = replace(config, stop_gain=0.0)
    niches, descriptors, map_prior = candidates(archive)
    if prior is None:
        prior = map_prior
    elif np.shape(prior) != map_prior.shape:
        raise ValueError(
            f'a prior needs one speed per gait ({len(map_prior)}), got {np.shape(prior)}'
        )
    if floor is not None:
        reference = float(floor())
        if math.isfinite(reference) and reference > config.min_speed:
            config = replace(config, min_speed=min(reference, MIN_SPEED_RANGE[1]))
    opt = Mboa(descriptors, prior, config, hypotheses=hypotheses)
    t0 = time.monotonic()
    result = AdaptationResult(False, '')

    def vetoed(index: int | None) -> bool:
        """Veto ``index`` if the screen says it tips (False: no screen, no gait, or upright)."""
        if screen is None or index is None or not screen.tips(index):
            return False
        opt.veto(index)
        result.vetoed.append(int(niches[index]))
        if on_veto:
            on_veto(int(niches[index]), screen.tilts[index])
        return True

    while True:
        while vetoed(opt.leading_index()):  # alpha's bar: only a gait the run could keep
            pass
        reason = opt.stop_reason()
        if reason is not StopReason.CONTINUE:
            # success is the rule's, whether it ended the run or the budget did
            result.success = opt.alpha_met()
            result.message = opt.should_stop()[1]
            break
        if should_cancel and should_cancel():
            result.message = 'cancelled'
            break
        newer = prior_update() if prior_update is not None else None
        if newer is not None:
            opt = _with_prior(opt, newer)  # its bar is vetted before the run may stop
        index = opt.next_index()
        if vetoed(index):
            continue
        niche = int(niches[index])
        try:
            outcome = trial(niche)
        except TrialCancelled:
            result.message = 'cancelled'
            break
        except TrialAborted as exc:
            result.message = f'trial {len(opt.trials) + 1} aborted: {exc}'
            break
        if not isinstance(outcome, TrialOutcome):
            outcome = TrialOutcome(float(outcome))
        measured = 0.0 if outcome.tipped else float(outcome.speed)
        if not math.isfinite(measured):  # bad odometry: never fed to the GP, never a "best"
            result.message = (
                f'trial {len(opt.trials) + 1} (gait {niche}) measured a non-finite speed '
                f'({measured!r} m/s): the odometry is broken; run stopped'
            )
            break
        t = opt.observe(index, measured, tipped=outcome.tipped)
        result.niches.append(niche)
        if outcome.tipped:
            result.tipped.append(niche)
        if on_trial:
            on_trial(t, niche, opt)
    result.trials = list(opt.trials)
    best = opt.best()
    if best is not None:
        result.best_niche = int(niches[best.index])
        result.best_speed = best.measured
    result.elapsed = time.monotonic() - t0
    return result


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


#: Trial budget of the experiment's runs. Thesis 5.2 stops a run only by M-BOA's rule (alpha);
#: this cap (100 trials = 8 min 20 s of walking) only bounds a run that never meets it, so the
#: trial counts measured are the rule's, not a budget's (the node's default budget is 20).
EXPERIMENT_MAX_TRIALS = 100


def _hypotheses(
    config: MboaConfig,
    bank: DamageBank | None,
    damage: Damage,
    leave_out: bool,
    known: bool,
) -> np.ndarray | None:
    """Return the bank's speeds for a run (None: no bank asked for, or the damage is known)."""
    if bank is None or known:
        return None
    return bank.hypotheses(config.use_bank, damage if leave_out else None)


@dataclass
class ExperimentRow:
    """One run of the thesis 5.2 experiment: one failure orientation, one trial engine."""

    scenario: str
    failed_legs: tuple[int, ...]
    trials: int
    success: bool
    best_niche: int
    #: the adapted gait [m/s], timed as the map and the control tripod are (the map's trial
    #: duration from standing), whatever the trials' timing
    best_speed: float
    control_speed: float  # the control tripod with the same damage [m/s]
    intact_control_speed: float  # the control tripod without damage, same engine [m/s]
    elapsed: float  # wall-clock seconds of the run (simulated trials)
    map_engine: str  # engine that made the map
    trial_engine: str  # engine the trials ran on (another one: a stand-in for the reality gap)
    walking_time: float = 0.0  # s walked in trials (trials x trial duration)
    ceiling_speed: float = float('nan')  # the map's best gait with this damage [m/s] (if asked)
    ceiling_niche: int = -1
    ratio: float = float('nan')  # best_speed / ceiling_speed (regret = 1 - ratio)
    gaits_beating_intact_control: int = -1  # map gaits faster than the intact tripod, damaged
    setup: str = 'thesis'  # M-BOA profile, '+prior' when it started from a damage-informed prior
    trial_speed: float = float('nan')  # the best trial as the run's trials measured it [m/s]
    damage_kind: str = 'lifted'  # what failed_legs suffer (hexapod_sim.damage.EXPERIMENT_KINDS)
    tipped_trials: int = 0  # trials the tip guard stopped


def run_experiment(
    archive: Archive,
    scenarios: Sequence[str] = ('S1', 'S2', 'S3', 'S4'),
    config: MboaConfig | None = None,
    on_row: Callable[[ExperimentRow], None] | None = None,
    trial_engine: str | None = None,
    trial_config: SimConfig | None = None,
    ceilings: Callable[[Damage, str], 'Ceiling'] | None = None,
    floor: bool = False,
    priors: Callable[[Damage], np.ndarray] | None = None,
    setup: str = 'thesis',
    trial_duration: float | None = None,
    settle: float = 0.0,
    bank: DamageBank | None = None,
    leave_out: bool = False,
    kind: str = 'lifted',
    tip_guard: float = math.pi,
) -> list[ExperimentRow]:
    """
    Thesis experiment 5.2 on one map.

    Adapt in every orientation of each failure scenario (library trials in the simulator,
    collisions not fatal), next to the control tripod gait. Trials run on ``trial_engine``
    (default: the engine that made the map) with its default settings, at the map's physics steps
    per row on the map's own engine and at the converged step on any other (:func:`map_physics`),
    or as ``trial_config`` sets it up (its engine is then the trial engine). Without ``config``:
    the thesis's settings with :data:`EXPERIMENT_MAX_TRIALS`. With ``ceilings(failed_legs,
    engine)`` (e.g. :func:`hexapod_adapt.online.ceiling.ceiling` over a cache, which walks the
    gaits on the same physics), each row also gets the map's ceiling under its damage and the
    adapted/ceiling ratio; with a ``tip_guard``, the ceiling is the best gait that stays within
    it (a guarded trial scores 0 for any other). ``floor``: the damaged control tripod, measured
    first, is the run's success floor. ``priors(failed_legs)``: M-BOA starts from these
    speeds (the map re-scored under the damage, :mod:`hexapod_adapt.online.prior`), with the gaits
    that tip past ``tip_guard`` there at 0 (:class:`TipScreen`, as adapt_node). ``setup`` names
    the configuration in the rows. ``trial_duration`` (default: the map's) and ``settle``: trials
    time that long after walking ``settle`` s untimed (:func:`simulated_trial`); the walking
    time counts both, and the adapted gait is then judged as the map's gaits are (its speed over
    the map's trial duration from standing) so that every timing is compared alike.
    ``bank``: damage hypotheses for runs without a prior, when ``config``'s ``use_bank`` asks
    for them; ``leave_out`` drops each run's own damage from them (damage the
    bank does not model). ``kind``: what the failed legs of each orientation suffer (the thesis's
    ``lifted``, or any of :data:`hexapod_sim.damage.EXPERIMENT_KINDS`); ``ceilings`` and
    ``priors`` then get that :class:`Damage` in place of the legs. ``tip_guard`` [rad]: trials
    that tilt the body past it are stopped and scored 0, as adapt_node's (pi: no guard).
    """
    config = config or MboaConfig(max_trials=EXPERIMENT_MAX_TRIALS)
    duration = archive.trial_duration
    map_engine = engine_of_map(archive)

    def screen(damage: Damage, engine: str) -> TipScreen | None:
        """Return the tip screen of a run or ceiling on ``engine`` (None: no guard)."""
        if tip_guard >= math.pi:
            return None
        return TipScreen(simulated_tilts(archive, damage, engine), tip_guard)

    if trial_config is not None:
        if trial_engine not in (None, trial_config.engine):
            raise ValueError(
                f'trial_engine {trial_engine!r} and trial_config ({trial_config.engine}) disagree'
            )
        trial_engine = trial_config.engine
    trial_engine = trial_engine or map_engine
    rows = []
    trial_config = trial_config or map_physics(archive, trial_engine)
    with create_simulator(trial_config) as sim:
        intact = evaluate_gait(
            preset('control'), sim, collisions_fatal=False, failed_legs=()
        ).speed
        for name in scenarios:
            for legs in orientations_of(name):
                damage = Damage.of(kind, legs)
                control = evaluate_gait(
                    preset('control'), sim, collisions_fatal=False, failed_legs=damage
                ).speed
                result = adapt(
                    archive,
                    simulated_trial(archive, damage, sim, trial_duration, settle, tip_guard),
                    config,
                    floor=(lambda: control) if floor else None,
                    prior=priors(damage) if priors is not None else None,
                    hypotheses=_hypotheses(config, bank, damage, leave_out, priors is not None),
                    # the prior's gaits that tip in its own simulation: vetoed, as adapt_node's
                    screen=screen(damage, map_engine) if priors is not None else None,
                )
                adapted = result.best_speed
                if settle > 0 or (trial_duration or duration) != duration:
                    # settled or shorter trials measure another thing: judge the gait as the map
                    adapted = map_speed(archive, result.best_niche, damage, sim)
                row = ExperimentRow(
                    name,
                    tuple(legs),
                    len(result.trials),
                    result.success,
                    result.best_niche,
                    adapted,
                    control,
                    intact,
                    result.elapsed,
                    map_engine,
                    trial_engine,
                    walking_time=len(result.trials) * ((trial_duration or duration) + settle),
                    setup=setup,
                    trial_speed=result.best_speed,
                    damage_kind=kind,
                    tipped_trials=len(result.tipped),
                )
                if ceilings is not None:
                    c = ceilings(damage, trial_engine)
                    # the best gait a guarded trial can keep: none that tips past the guard
                    upright = screen(damage, trial_engine)
                    best = (
                        int(np.argmax(c.speeds))
                        if upright is None
                        else upright.best_upright(c.speeds)
                    )
                    row = replace(row, gaits_beating_intact_control=c.beating(intact))
                    if best is not None:  # None: every gait tips, no ceiling to compare with
                        row = replace(
                            row,
                            ceiling_speed=float(c.speeds[best]),
                            ceiling_niche=int(c.niches[best]),
                            ratio=adapted / float(c.speeds[best]),
                        )
                rows.append(row)
                if on_row:
                    on_row(row)
    return rows
