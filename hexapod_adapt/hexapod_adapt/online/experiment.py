# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Thesis experiment 5.2 on one map (ROS-free): adapt in every orientation of each failure scenario.

Each run is an :class:`~hexapod_adapt.online.session.AdaptationSession` driven by trials in a
simulator with the damage (:func:`~hexapod_adapt.online.adaptation.simulated_trial`), next to
the control tripod with the same damage; ``run_experiment`` returns one :class:`ExperimentRow`
per run. ``run_experiment`` (the console command) and ``make bench-adapt`` drive it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
import math
from typing import Callable, Sequence, TYPE_CHECKING

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.simulation import engine_of_map, map_physics
from hexapod_adapt.online.adaptation import (
    AdaptationResult,
    map_speed,
    recorded_trial,
    simulated_trial,
)
from hexapod_adapt.online.diagnosis import (
    calibrate_gap,
    GapCalibration,
    HypothesisWalks,
    Weighing,
)
from hexapod_adapt.online.mboa import MboaConfig
from hexapod_adapt.online.prior import simulated_tilts, TipScreen
from hexapod_adapt.online.safety import RISK_LIMIT
from hexapod_adapt.online.session import (
    adapt,
    BlindRules,
    diagnosis_plan,
    KIN_TILTS,
    NAME_LEG_SETS,
    SCREEN_MARGIN,
    SessionStart,
)
from hexapod_gait import preset
from hexapod_sim import create_simulator, evaluate_gait, SimConfig, Simulator
from hexapod_sim.damage import Damage
from hexapod_sim.scenarios import scenario as orientations_of
import numpy as np

if TYPE_CHECKING:  # the ceiling module imports this one's siblings only
    from hexapod_adapt.online.bank import DamageBank
    from hexapod_adapt.online.ceiling import Ceiling

#: Trial budget of the experiment's runs. Thesis 5.2 stops a run only by M-BOA's rule (alpha);
#: this cap (100 trials = 8 min 20 s of walking) only bounds a run that never meets it, so the
#: trial counts measured are the rule's, not a budget's.
EXPERIMENT_MAX_TRIALS = 100


@dataclass(frozen=True)
class ExperimentSetup:
    """
    How the experiment's runs are made; every field has the thesis's choice as default.

    ``scenarios``: the failure scenarios, each run in every orientation. ``config``: M-BOA's
    settings (default: the thesis's, :data:`EXPERIMENT_MAX_TRIALS` trials). Trials run on
    ``trial_engine`` (default: the map's) at the map's physics step on the map's own engine and
    at the converged step on any other (``map_physics``), or as ``trial_config`` sets up.
    ``ceilings(damage, engine)``: the map's ceiling under each run's damage (a row then gets the
    ratio to it; with a ``tip_guard``, the best gait that stays within it). ``floor``: the damaged
    control tripod is each run's success floor. ``priors(damage)``: M-BOA starts from these speeds
    (the map re-scored under the damage), and gaits that tip past ``tip_guard`` there are vetoed,
    as adapt_node's. ``setup`` names the configuration in the rows. ``trial_duration`` (default:
    the map's) and ``settle``: trials time that long after walking ``settle`` s untimed; the
    adapted gait is then judged as the map's gaits are (5 s from standing). ``bank``: damage
    hypotheses for runs without a prior when ``config.use_bank`` asks; ``leave_out`` drops each
    run's own damage from them. ``kind``: what the failed legs suffer
    (:data:`hexapod_sim.damage.EXPERIMENT_KINDS`). ``tip_guard`` [rad]: trials that tilt the body
    past it are stopped and scored 0 (pi: no guard). ``diagnose``: runs without a prior name
    their damage from the trials among ``bank``'s (:class:`~hexapod_adapt.online.session.
    DiagnosisPlan`); with a ``tip_guard``, a safety model with risk limit ``safety`` (None:
    none) screens their gaits (:class:`~hexapod_adapt.online.safety.SafetyModel`), and
    ``blind`` says how they adapt and stop while they name nothing, ``weighing`` how a trial
    weighs the hypotheses, ``leg_sets`` whether they may name a leg set of several kinds,
    ``screen_margin`` [rad] how far below the guard a named damage's screen vetoes, ``wider``
    the bank they weigh once none of ``bank``'s fits (``leave_out`` drops their damage there too).
    ``calibrate``: before the runs, the map's this many fastest gaits are walked intact on the
    trials' physics, and the diagnosis weighs the trials against the gap they measure
    (:func:`~hexapod_adapt.online.diagnosis.calibrate_gap`; 0: none). ``kin_tilts``: the
    safety model's lifted hypotheses believed at least this much tilt as the worst kind that
    unloads their legs (:data:`~hexapod_adapt.online.session.KIN_TILTS`; None: as themselves).
    ``walk_workers``: the processes that walk the hypotheses (the same walks, sooner).
    """

    scenarios: Sequence[str] = ('S1', 'S2', 'S3', 'S4')
    config: MboaConfig | None = None
    trial_engine: str | None = None
    trial_config: SimConfig | None = None
    ceilings: Callable[[Damage, str], 'Ceiling'] | None = None
    floor: bool = False
    priors: Callable[[Damage], np.ndarray] | None = None
    setup: str = 'thesis'
    trial_duration: float | None = None
    settle: float = 0.0
    bank: DamageBank | None = None
    leave_out: bool = False
    kind: str = 'lifted'
    tip_guard: float = math.pi
    diagnose: bool = False
    safety: float | None = RISK_LIMIT
    blind: BlindRules = BlindRules()
    weighing: Weighing = Weighing()
    leg_sets: bool = NAME_LEG_SETS
    screen_margin: float = SCREEN_MARGIN
    wider: DamageBank | None = None
    calibrate: int = 0
    kin_tilts: float | None = KIN_TILTS
    walk_workers: int = 1


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
    #: a diagnosing run's damage named after each trial ('' none), '|'-joined
    named: str = ''
    named_legs: str = ''  # the legs of each, e.g. '1+4|1+4' ('' where none)
    posterior: str = ''  # its last posterior's top hypotheses
    trial_speeds: tuple[float, ...] = ()  # each trial's measured speed, in order (tipped: 0)
    vetoed: int = 0  # gaits a tip screen or the safety model kept from being tried
    #: the hypotheses' walks this run simulated (the runs before it may have walked the rest)
    hypothesis_walks: int = 0
    #: whether the run ended saying no hypothesis fits its trials (the most probable did not)
    unfit: bool = False
    widened: int = 0  # the trial after which its diagnosis weighed the wider bank (0: never)
    trial_niches: tuple[int, ...] = ()  # each trial's gait (archive niche), in order
    trial_tipped: tuple[bool, ...] = ()  # whether the tip guard stopped each trial

    def best_after(self, k: int) -> float:
        """Return the best speed the first ``k`` trials measured (all, if the run stopped)."""
        return max(self.trial_speeds[:k], default=float('nan'))

    def named_after(self, k: int) -> str:
        """Return the damage the diagnosis named after trial ``k`` (its last if it stopped)."""
        names = self.named.split('|') if self.named else []
        return names[min(k, len(names)) - 1] if names else ''

    def legs_named_after(self, k: int) -> tuple[int, ...]:
        """Return the legs the diagnosis named after trial ``k`` (() none)."""
        if not self.named:
            return ()
        sets = self.named_legs.split('|')
        legs = sets[min(k, len(sets)) - 1]
        return tuple(int(leg) for leg in legs.split('+')) if legs else ()


def _screen(archive: Archive, damage: Damage, engine: str, guard: float) -> TipScreen | None:
    """Return the tip screen of a run or ceiling on ``engine`` (None: no guard)."""
    if guard >= math.pi:
        return None
    return TipScreen(simulated_tilts(archive, damage, engine), guard)


def _start(
    archive: Archive,
    s: ExperimentSetup,
    config: MboaConfig,
    damage: Damage,
    control: float,
    walks: HypothesisWalks | None,
    calibration: GapCalibration | None = None,
) -> SessionStart:
    """
    Return a run's session start: its prior and screen, or its bank's hypotheses; its floor.

    A diagnosing run's hypotheses are walked by ``walks`` (shared by the experiment's runs).
    """
    floor = control if s.floor else None
    if s.priors is not None:  # the prior's gaits that tip in its own simulation: vetoed
        screen = _screen(archive, damage, engine_of_map(archive), s.tip_guard)
        return SessionStart(s.priors(damage), screen=screen, floor=floor)
    hypotheses, plan = None, None
    if s.bank is not None:
        hypotheses = s.bank.hypotheses(config.use_bank, damage if s.leave_out else None)
        if s.diagnose:
            bank = s.bank.without(damage) if s.leave_out else s.bank
            wider = s.wider.without(damage) if s.leave_out and s.wider else s.wider
            plan = diagnosis_plan(
                archive,
                bank,
                s.tip_guard,
                walks=walks,
                safety=s.safety,
                blind=s.blind,
                weighing=s.weighing,
                leg_sets=s.leg_sets,
                screen_margin=s.screen_margin,
                wider=wider,
                calibration=calibration,
                kin_tilts=s.kin_tilts,
            )
    return SessionStart(hypotheses=hypotheses, floor=floor, diagnosis=plan)


def _with_ceiling(row: ExperimentRow, archive: Archive, s: ExperimentSetup, damage: Damage):
    """Return ``row`` with the map's ceiling under its damage, when ``s.ceilings`` is given."""
    c = s.ceilings(damage, row.trial_engine)
    # the best gait a guarded trial can keep: none that tips past the guard
    upright = _screen(archive, damage, row.trial_engine, s.tip_guard)
    speeds = c.walked_speeds  # a partial ceiling's estimates are no ceiling
    best = c.best_index if upright is None else upright.best_upright(speeds)
    row = replace(row, gaits_beating_intact_control=c.beating(row.intact_control_speed))
    if best is None or not c.walked_mask[best]:  # every gait walked tips: no ceiling
        return row
    return replace(
        row,
        ceiling_speed=float(c.speeds[best]),
        ceiling_niche=int(c.niches[best]),
        ratio=row.best_speed / float(c.speeds[best]),
    )


def _row(
    archive: Archive,
    s: ExperimentSetup,
    result: AdaptationResult,
    where: tuple[str, tuple[int, ...], str],
    speeds: tuple[float, float, float],
) -> ExperimentRow:
    """
    Return the row of one run.

    ``where``: scenario, legs, trial engine; ``speeds``: the adapted gait, the control tripod
    damaged and intact [m/s].
    """
    name, legs, trial_engine = where
    duration = s.trial_duration or archive.trial_duration
    return ExperimentRow(
        name,
        tuple(legs),
        len(result.trials),
        result.success,
        result.best_niche,
        speeds[0],
        speeds[1],
        speeds[2],
        result.elapsed,
        engine_of_map(archive),
        trial_engine,
        walking_time=len(result.trials) * (duration + s.settle),
        setup=s.setup,
        trial_speed=result.best_speed,
        damage_kind=s.kind,
        tipped_trials=len(result.tipped),
        named='|'.join(result.named),
        named_legs='|'.join('+'.join(map(str, legs)) for legs in result.named_legs),
        posterior=result.posterior,
        unfit=result.unfit,
        widened=result.widened,
        trial_speeds=tuple(float(t.measured) for t in result.trials),
        vetoed=len(result.vetoed),
        trial_niches=tuple(int(n) for n in result.niches),
        trial_tipped=tuple(bool(t.tipped) for t in result.trials),
    )


def _one_run(
    archive: Archive,
    s: ExperimentSetup,
    config: MboaConfig,
    sim: Simulator,
    where,
    intact: float,
    walks: HypothesisWalks | None = None,
    calibration: GapCalibration | None = None,
) -> ExperimentRow:
    """Adapt once under ``where``'s damage (scenario, legs, trial engine); return its row."""
    damage = Damage.of(s.kind, where[1])
    control = evaluate_gait(
        preset('control'), sim, collisions_fatal=False, failed_legs=damage
    ).speed
    walk = recorded_trial if s.diagnose else simulated_trial
    trial = walk(archive, damage, sim, s.trial_duration, s.settle, s.tip_guard)
    walked = 0 if walks is None else walks.walked
    start = _start(archive, s, config, damage, control, walks, calibration)
    result = adapt(archive, trial, config, start)
    adapted = result.best_speed
    if s.settle > 0 or (s.trial_duration or archive.trial_duration) != archive.trial_duration:
        # settled or shorter trials measure another thing: judge the gait as the map
        adapted = map_speed(archive, result.best_niche, damage, sim)
    row = _row(archive, s, result, where, (adapted, control, intact))
    if walks is not None:
        row = replace(row, hypothesis_walks=walks.walked - walked)
    return row if s.ceilings is None else _with_ceiling(row, archive, s, damage)


def intact_gap(
    archive: Archive,
    sim: Simulator,
    walks: HypothesisWalks,
    gaits: int,
    duration: float | None = None,
) -> GapCalibration:
    """
    Return the gap of ``sim``'s trials to ``walks``' engine: the map's ``gaits`` fastest, intact.

    As an operator calibrates a robot before a mission: each gait walked once by the intact
    robot (a trial, timed as the runs' are) and simulated as the hypotheses are.
    """
    trial = recorded_trial(archive, Damage.lifted(()), sim, duration)
    elites = archive.elite_indices()
    niches = elites[np.argsort(-archive.fitness[elites], kind='stable')]  # fastest first
    observed, simulated = [], []
    for niche in niches:
        record, expected = trial(int(niche)).record, walks(int(niche), Damage.lifted(()))
        if record is not None and expected is not None:
            observed.append(record)
            simulated.append(expected)
        if len(observed) == gaits:
            break
    return calibrate_gap(observed, simulated)


def run_experiment(
    archive: Archive,
    setup: ExperimentSetup | None = None,
    on_row: Callable[[ExperimentRow], None] | None = None,
) -> list[ExperimentRow]:
    """Run thesis experiment 5.2 on ``archive`` as ``setup`` says; ``on_row`` hears each row."""
    s = setup or ExperimentSetup()
    config = s.config or MboaConfig(max_trials=EXPERIMENT_MAX_TRIALS)
    trial_engine = s.trial_engine
    if s.trial_config is not None:
        if trial_engine not in (None, s.trial_config.engine):
            raise ValueError(
                f'trial_engine {trial_engine!r} and trial_config ({s.trial_config.engine})'
                ' disagree'
            )
        trial_engine = s.trial_config.engine
    trial_engine = trial_engine or engine_of_map(archive)
    rows = []
    walks = None
    if s.diagnose and s.bank:
        walks = HypothesisWalks(archive, s.bank.engine, s.walk_workers)
    with create_simulator(s.trial_config or map_physics(archive, trial_engine)) as sim:
        intact = evaluate_gait(
            preset('control'), sim, collisions_fatal=False, failed_legs=()
        ).speed
        calibration = None
        if walks is not None and s.calibrate > 0:
            calibration = intact_gap(archive, sim, walks, s.calibrate, s.trial_duration)
        for name in s.scenarios:
            for legs in orientations_of(name):
                where = (name, tuple(legs), trial_engine)
                row = _one_run(archive, s, config, sim, where, intact, walks, calibration)
                rows.append(row)
                if on_row:
                    on_row(row)
    return rows
