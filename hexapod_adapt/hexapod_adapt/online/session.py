# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
One adaptation run as an ask/tell session (ROS-free): which gait next, and when to stop.

    session = AdaptationSession(archive, config, start)
    while (niche := session.ask()) is not None:
        session.tell(niche, walk(niche))  # a speed [m/s] or a TrialOutcome
    result = session.result()

The session owns everything a run decides: M-BOA over the map's elites, the prior it starts
from (the map, or the map re-scored under a known damage, and the newer priors a streaming
re-score sends), the tip screen that vetoes gaits that tip in simulation, the success floor and
the stop. Whoever walks the trials drives it: adapt_node through the ROS graph,
``run_experiment`` in a simulator, the tests with a lookup table (:func:`adapt`). What the prior
or the floor changes in M-BOA's settings is resolved once, at construction
(:func:`run_rules`), and shows in the result's ``config``.
"""

from __future__ import annotations

from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass, field, replace
import enum
from functools import partial
import math
import time
from typing import Callable, Protocol, Sequence

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.simulation import engine_of_map
from hexapod_adapt.online.adaptation import (
    AdaptationResult,
    candidates,
    TrialAborted,
    TrialCancelled,
    TrialOutcome,
)
from hexapod_adapt.online.bank import DamageBank
from hexapod_adapt.online.ceiling import quick_rescore, RescoreStopped
from hexapod_adapt.online.diagnosis import (
    Diagnosis,
    GapCalibration,
    HypothesisWalks,
    Posterior,
    TrialRecord,
    WalksStopped,
    Weighing,
)
from hexapod_adapt.online.mboa import Mboa, MboaConfig, MIN_SPEED_RANGE, StopReason, Trial
from hexapod_adapt.online.prior import simulated_tilts, TipScreen
from hexapod_adapt.online.safety import KIN_WEIGHT, record_tilt, RISK_LIMIT, SafetyModel
from hexapod_sim.damage import Damage
import numpy as np

#: Asked before each trial for a newer prior, one speed per elite (None: nothing new), e.g. a
#: streaming re-score's ``update``.
PriorUpdates = Callable[[], 'np.ndarray | None']


@dataclass(frozen=True)
class PriorStart:
    """What a source of damage-informed priors gives a run: speeds, what they are, updates."""

    speeds: np.ndarray | None  # None: no prior could be had (``note`` says why)
    note: str  # what the prior is, for the operator
    updates: PriorUpdates | None = None


class PriorSource(Protocol):
    """Where a run gets the map re-scored under a damage, on the map's engine."""

    def start(self, archive: Archive, damage: Damage, source: str) -> PriorStart:
        """Return the prior of ``damage`` (``source``: where the damage is known from)."""

    def diagnosis(self, archive: Archive, tip_guard: float) -> DiagnosisPlan | None:
        """Return a blind run's diagnosis of its damage (None: none can be made)."""


#: A named hypothesis must hold this much of the posterior before the run takes it as the damage.
NAME_THRESHOLD = 0.9
#: A named damage is given up when its probability falls below this.
RELEASE_THRESHOLD = 0.5
#: Whether a leg set whose hypotheses of several kinds hold the threshold together is named
#: (won on a tuning set: studies/diagnosis/README.md, "Naming the leg set"; a bank of one kind
#: has one hypothesis per leg set, and names as without it).
NAME_LEG_SETS = True
#: [rad] a named damage's tip screen vetoes gaits that tilt past the trials' tip guard less this
#: in simulation: the map's engine is not the robot, and a gait near the guard there may tip on
#: other physics (studies/diagnosis/README.md, "A margin for the named damage's screen").
SCREEN_MARGIN = 0.0
#: While a blind run weighs lifted legs, its safety model takes the tilt of a leg set believed at
#: least this much as the largest over the kinds that unload those legs (:data:`UNLOADING_KINDS`):
#: the lifted bank stands in for them, and they walk alike but do not tilt alike (None: each
#: its own walk). 0.05 (:data:`~hexapod_adapt.online.safety.KIN_WEIGHT`) won on a tuning set
#: (studies/diagnosis/README.md, "The safety model's lifted bank stands in for five kinds").
KIN_TILTS: float | None = KIN_WEIGHT
#: The kinds that leave a leg unloaded, which the lifted bank stands in for.
UNLOADING_KINDS = ('lifted', 'unpowered_coxa', 'unpowered_tibia', 'no_tibia', 'shortened')


class FirstGait(enum.Enum):
    """Which gait a diagnosing run that names nothing walks first."""

    FASTEST = 'fastest'  # the map's fastest (intact) gait, as M-BOA's prior has it
    EXPECTED = 'expected'  # the fastest on average over the hypotheses (see blended_prior)
    #: of the gaits expected within FIRST_SLACK of the fastest (the FIRST_CANDIDATES fastest at
    #: most), the one whose trial tells the hypotheses apart best (Diagnosis.separation)
    INFORMATIVE = 'informative'


#: FirstGait.INFORMATIVE's candidates: expected at least (1 - FIRST_SLACK) x the fastest, and
#: at most FIRST_CANDIDATES of them (judgement, before its runs: studies/diagnosis/README.md,
#: "A first gait that tells the hypotheses apart").
FIRST_SLACK = 0.10
FIRST_CANDIDATES = 8


@dataclass(frozen=True)
class BlindRules:
    """
    How a diagnosing run adapts and stops while it names no damage.

    ``offset_std`` [m/s]: M-BOA's shared shift of the map's speeds (``MboaConfig.offset_std``),
    so that trials all slower than the map lower every untried gait's prediction.
    ``alpha_stop``: stop on alpha alone, as a named damage's run does (False: the profile's
    ``stop_gain`` too, which a blind GP seldom lets end a run before its budget). The defaults
    won on a tuning set (studies/diagnosis/README.md, "The stop rule"). ``bank_prior``: M-BOA's
    prior is the hypotheses' re-scores and the map's speeds (for "none of these") weighed by
    the posterior, after every trial (False: the map's speeds). ``first``: the first trial's
    gait (:class:`FirstGait`; the default won on a tuning set: studies/diagnosis/README.md, "The
    first gait"); M-BOA chooses the later ones. ``unfit_fallback``: once the posterior holds a
    damage that fits no trial (:meth:`DiagnosisPlan.assess`), the run adapts and stops as blind
    M-BOA without a diagnosis does (the request's offset and expected-gain stop), to its end
    (on since it won on a tuning set: studies/diagnosis/README.md, "Falling back").
    ``fallback_alpha_stop``: a run fallen back stops on alpha alone (the expected-gain stop
    left out), as a run naming nothing does.
    """

    offset_std: float = 0.05
    alpha_stop: bool = True
    bank_prior: bool = False
    first: FirstGait = FirstGait.EXPECTED
    unfit_fallback: bool = True
    fallback_alpha_stop: bool = False


@dataclass(frozen=True)
class DiagnosisPlan:
    """
    A blind run's diagnosis, and what the run becomes when it names a damage.

    ``diagnosis`` weighs hypothesis h, whose damage is ``damages[h]`` and whose re-score of the
    map is ``priors[h]`` (one speed per elite, a damage bank's row). Once hypothesis h holds
    ``threshold`` of the posterior, the run goes on as the damage-informed prior of that damage
    (its re-score, its stop rule, its tip screen: ``screen_of(damage)``); once it falls below
    ``release``, the run goes back to the map as it is, under ``blind``'s rules. ``safety``: the
    gaits whose risk of tipping is above its limit are not tried, a damage named or not (None:
    no such screen). ``leg_sets``: when no one hypothesis holds the threshold but hypotheses of
    one leg set do together (a lifted leg and its unpowered coxa walk alike), name that leg set:
    the fewest of its hypotheses that hold it, the run going on as their re-scores weighed by
    the posterior, with every one's tip screen. ``wider``: makes the plan of a wider bank,
    which a run that names nothing weighs its trials under, once the damage this bank holds
    most probable fits none of them, before it falls back to blind M-BOA (None: it falls back).
    ``rescore(damage, stop)``: a row of ``priors`` that is NaN (a damage not cached) is filled by
    it when its hypothesis is named, in place, so the plan's later runs have it too; ``stop()``
    true ends it early with :class:`~hexapod_adapt.online.ceiling.RescoreStopped`. ``walks``:
    the hypotheses' walks behind ``diagnosis`` and ``safety`` (a session stops them on a cancel).
    """

    diagnosis: Diagnosis
    damages: tuple[Damage, ...]
    priors: np.ndarray
    screen_of: Callable[[Damage], 'TipScreen | None']
    threshold: float = NAME_THRESHOLD
    release: float = RELEASE_THRESHOLD
    safety: SafetyModel | None = None
    blind: BlindRules = BlindRules()
    leg_sets: bool = NAME_LEG_SETS
    wider: Callable[[], DiagnosisPlan] | None = None
    rescore: Callable[[Damage, Callable[[], bool] | None], np.ndarray] | None = None
    walks: HypothesisWalks | None = None

    def __post_init__(self) -> None:
        if len(self.damages) != len(self.diagnosis.labels) or len(self.priors) != len(
            self.damages
        ):
            raise ValueError('a diagnosis plan needs one damage and one prior per hypothesis')
        if not 0.0 < self.release <= self.threshold < 1.0:
            raise ValueError(
                f'need 0 < release <= threshold < 1, got {self.release} and {self.threshold}'
            )

    def holding(self, probabilities: np.ndarray) -> tuple[int, ...] | None:
        """
        Return the hypotheses the posterior names (None: none holds the threshold).

        One hypothesis past the threshold; else, with ``leg_sets``, the fewest hypotheses of one
        leg set that hold it together, most probable first. None too when the most probable of
        them does not fit the trials (:meth:`Diagnosis.fits`).
        """
        return self.assess(probabilities)[0]

    def assess(self, probabilities: np.ndarray) -> tuple[tuple[int, ...] | None, bool]:
        """
        Return :meth:`holding`'s answer, and whether it is None because what is held misfits.

        The second is True when the posterior holds a damage that does not fit the trials.
        """
        held = self._holding(np.asarray(probabilities, dtype=float)[: len(self.damages)])
        if held is None or self.diagnosis.fits(held[0]):
            return held, False
        return None, True

    def _holding(self, p: np.ndarray) -> tuple[int, ...] | None:
        best = int(np.argmax(p))
        if p[best] >= self.threshold:
            return (best,)
        if not self.leg_sets:
            return None
        for legs in {d.failed_legs for d in self.damages}:
            members = [h for h, d in enumerate(self.damages) if d.failed_legs == legs]
            members.sort(key=lambda h: -p[h])
            held = np.cumsum(p[members])
            if held[-1] >= self.threshold:  # at most one leg set can: the threshold is > 1/2
                return tuple(members[: int(np.argmax(held >= self.threshold)) + 1])
        return None

    def label_of(self, named: tuple[int, ...]) -> str:
        """Say what ``named`` names, e.g. ``leg 1 lifted, unpowered coxa or unpowered tibia``."""
        damages = [self.damages[h] for h in named]
        conditions = [{d.condition for d in damage.legs} for damage in damages]
        if len(damages) == 1 or any(len(c) != 1 for c in conditions):  # or mixed on its legs
            return ' or '.join(damage.label for damage in damages)
        legs = damages[0].failed_legs
        where = f'{"legs" if len(legs) > 1 else "leg"} {"+".join(map(str, legs))}'
        kinds = [c.pop() for c in conditions]
        return f'{where} {", ".join(kinds[:-1])} or {kinds[-1]}'

    def unscored(self, named: tuple[int, ...]) -> bool:
        """Whether any of ``named`` has no re-score yet (a NaN row: :meth:`prior_of` makes it)."""
        return any(np.isnan(self.priors[h]).any() for h in named)

    def prior_of(
        self,
        named: tuple[int, ...],
        probabilities: np.ndarray,
        stop: Callable[[], bool] | None = None,
    ) -> np.ndarray:
        """
        Return the re-scores of ``named`` weighed by their share of ``probabilities``.

        A re-score not made yet (a NaN row) is made now by ``rescore`` (``stop`` as it takes it).
        """
        rows = np.asarray(self.priors, dtype=float)  # a float array: itself, filled in place
        for h in named:
            if self.unscored((h,)):
                if self.rescore is None:
                    raise ValueError(f'{self.damages[h].label} has no re-score and no rescore')
                rows[h] = self.rescore(self.damages[h], stop)
        w = np.asarray(probabilities, dtype=float)[list(named)]
        return (w / w.sum()) @ rows[list(named)]


def diagnosis_plan(
    archive: Archive,
    bank: DamageBank,
    tip_guard: float = math.pi,
    contacts: bool = False,
    threshold: float = NAME_THRESHOLD,
    walks: HypothesisWalks | None = None,
    safety: float | None = RISK_LIMIT,
    blind: BlindRules = BlindRules(),
    weighing: Weighing = Weighing(),
    leg_sets: bool = NAME_LEG_SETS,
    screen_margin: float = SCREEN_MARGIN,
    wider: DamageBank | None = None,
    calibration: GapCalibration | None = None,
    kin_tilts: float | None = KIN_TILTS,
    workers: int = 1,
) -> DiagnosisPlan | None:
    """
    Return the diagnosis of a blind run over ``bank``'s damages (None: the bank is empty).

    The hypotheses are walked on the bank's engine (the map's) by ``walks`` (runs that share
    one walk each gait once); with a ``tip_guard`` below pi, a named damage screens gaits as a
    known one does (:func:`informed_start`), and a :class:`SafetyModel` over the same walks
    with risk limit ``safety`` (None: none) screens them, a damage named or not. ``blind``: how
    the run adapts and stops while it names nothing; ``weighing``: how a trial weighs the
    hypotheses; ``leg_sets``: whether a leg set may be named (:class:`DiagnosisPlan`);
    ``screen_margin`` [rad]: a named damage's screen vetoes tilts past ``tip_guard`` less it.
    ``wider``: the bank a run weighs once none of ``bank``'s fits (:class:`DiagnosisPlan`),
    diagnosed as this one is, over the same walks, with the fit floor
    ``weighing.wider_fit_floor``. ``calibration``: the trials' gap to the map's engine,
    measured on the intact robot (``diagnosis.calibrate_gap``; None: none). ``kin_tilts``: the
    safety model takes the tilt of a lifted hypothesis believed at least this much as the worst
    of :data:`UNLOADING_KINDS` on its legs (:data:`KIN_TILTS`; None: its own).
    ``workers``: the processes that walk the hypotheses when ``walks`` is not given, and
    re-score a damage named but not cached (:func:`quick_rescore`): the same, sooner.
    """
    if len(bank) == 0:
        return None
    if not (math.isfinite(screen_margin) and 0.0 <= screen_margin < tip_guard):
        raise ValueError(f'screen_margin must lie in [0, tip_guard), got {screen_margin}')
    walks = walks or HypothesisWalks(archive, bank.engine, workers)
    labels = tuple(d.label for d in bank.damages)
    diagnosis = Diagnosis(
        labels,
        walks.under(bank.damages),
        contacts,
        weighing,
        calibration,
        prefetch=walks.prefetcher(bank.damages),
    )

    def screen_of(damage: Damage) -> TipScreen | None:
        if tip_guard >= math.pi:
            return None
        return TipScreen(simulated_tilts(archive, damage, bank.engine), tip_guard - screen_margin)

    model = None
    if safety is not None and tip_guard < math.pi:
        model = _safety_model(archive, bank, walks, diagnosis, tip_guard, safety, kin_tilts)
    wide = replace(weighing, fit_floor=weighing.wider_fit_floor)  # the wider bank's own floor
    same = (contacts, threshold, walks, safety, blind, wide, leg_sets, screen_margin)
    widen = partial(
        diagnosis_plan, archive, wider, tip_guard, *same, calibration=calibration,
        kin_tilts=kin_tilts, workers=workers,
    )  # fmt: skip
    return DiagnosisPlan(
        diagnosis,
        bank.damages,
        bank.speeds,
        screen_of,
        threshold,
        safety=model,
        blind=blind,
        leg_sets=leg_sets,
        wider=widen if wider else None,
        rescore=lambda damage, stop: quick_rescore(
            archive, damage, bank.engine, stop=stop, workers=workers
        ),
        walks=walks,
    )


def _safety_model(
    archive: Archive,
    bank: DamageBank,
    walks: HypothesisWalks,
    diagnosis: Diagnosis,
    tip_guard: float,
    limit: float,
    kin_tilts: float | None,
) -> SafetyModel:
    """Return a blind run's safety model over ``bank``'s walks (:func:`diagnosis_plan`)."""
    niches, descriptors, _ = candidates(archive)
    under = (*bank.damages, Damage.lifted(()))  # the last: intact, for none of these
    kins = [_unloading_kin(d) for d in under]

    def worst_kin(niche: int, h: int) -> TrialRecord | None:
        """Return the most tilted walk of the kinds hypothesis ``h`` stands in for."""
        return max((walks(niche, d) for d in kins[h]), key=record_tilt)

    def prefetch(niche: int, own: Sequence[int], kin: Sequence[int]) -> None:
        """Walk what ``own`` and ``worst_kin`` will ask for gait ``niche``, at once."""
        damages = [under[h] for h in own] + [d for h in kin for d in kins[h]]
        walks.prefetch((niche, d) for d in damages)

    return SafetyModel(
        niches,
        descriptors,
        lambda niche, h: walks(niche, under[h]),
        len(bank.damages),
        tip_guard,
        diagnosis.posterior().probabilities,
        limit=limit,
        kin=None if kin_tilts is None else worst_kin,
        kin_weight=kin_tilts or 0.0,
        prefetch=prefetch,
    )


def _unloading_kin(damage: Damage) -> tuple[Damage, ...]:
    """Return the damages a lifted-leg hypothesis stands in for (itself for any other)."""
    legs = damage.failed_legs
    if not legs or not damage.thesis:
        return (damage,)
    return tuple(Damage.of(kind, legs) for kind in UNLOADING_KINDS)


@dataclass(frozen=True)
class SessionStart:
    """
    What a session knows before its first trial, besides the map and M-BOA's settings.

    ``prior``: one speed per elite (``archive.elite_indices()``'s order) to start from instead
    of the map's, e.g. the map re-scored under a known damage; ``updates`` sends newer ones
    between trials. ``screen``: asked about each gait before it is tried (a gait that tips in
    simulation is vetoed). ``hypotheses`` (h, elites): other prior means the trials weigh
    (a damage bank). ``floor`` [m/s]: a reference measured before the run (the damaged control
    tripod): success also needs the best gait to walk that fast. ``note``: what the prior is.
    ``diagnosis``: a blind run's diagnosis (trials that carry a record name the damage).
    """

    prior: np.ndarray | None = None
    updates: PriorUpdates | None = None
    screen: TipScreen | None = None
    hypotheses: np.ndarray | None = None
    floor: float | None = None
    note: str = ''
    diagnosis: DiagnosisPlan | None = None

    @property
    def informed(self) -> bool:
        """Whether M-BOA starts from a prior of a known damage (not the map's own speeds)."""
        return self.prior is not None or self.updates is not None


def informed_start(
    archive: Archive,
    damage: Damage | None,
    source: str,
    priors: PriorSource,
    tip_guard: float = math.pi,
    floor: float | None = None,
    diagnose: bool = False,
) -> SessionStart:
    """
    Return the start of a run that knows ``damage`` (None: the map as it is, blind).

    M-BOA starts from ``priors``' re-score under it. With a ``tip_guard`` below pi, each gait is
    walked under the damage before its trial, tilt recorded, and one that tilts past the guard
    there is never tried (:class:`TipScreen`). A blind run with ``diagnose`` names its damage
    from the trials, when ``priors`` can make a diagnosis (:class:`DiagnosisPlan`).
    """
    if damage is None:
        plan = priors.diagnosis(archive, tip_guard) if diagnose else None
        if plan is None:
            return SessionStart(floor=floor, note=source)
        n = len(plan.damages)
        pending = sum(plan.unscored((h,)) for h in range(n))
        note = (
            f'{source}; the damage is named from the trials among {n}'
            f' {"hypothesis" if n == 1 else "hypotheses"}, and the run goes on as the prior of'
            ' the one named'
            + (f' ({pending} not cached: one is re-scored when named)' if pending else '')
        )
        return SessionStart(floor=floor, note=note, diagnosis=plan)
    got = priors.start(archive, damage, source)
    if got.speeds is None:
        return SessionStart(floor=floor, note=got.note)
    screen, note = None, got.note
    if tip_guard < math.pi:
        screen = TipScreen(simulated_tilts(archive, damage, engine_of_map(archive)), tip_guard)
        note += screen_note(screen)
    return SessionStart(got.speeds, got.updates, screen, floor=floor, note=note)


def blended_prior(plan: DiagnosisPlan, map_prior: np.ndarray) -> np.ndarray:
    """
    Return the speeds a blind run expects of each gait: the plan's re-scores and ``map_prior``.

    Each weighed by its hypothesis's probability ("none of these": the map's own speeds).
    """
    p = plan.diagnosis.posterior().probabilities
    map_prior = np.asarray(map_prior, dtype=float)
    rows = np.where(np.isnan(plan.priors), map_prior, plan.priors)  # not re-scored: the map's
    return p[:-1] @ rows + p[-1] * map_prior


def screen_note(screen: TipScreen) -> str:
    """Say what a prior's tip screen will do, to follow what the prior is."""
    return (
        '; each gait is walked there first with the tilt recorded, and one that tilts past the'
        f' {math.degrees(screen.guard):.0f} deg tip guard is never tried'
    )


def run_rules(config: MboaConfig, start: SessionStart) -> MboaConfig:
    """
    Return the M-BOA settings a run keeps to: ``config`` with what its start changes.

    A run from a known damage's prior stops on alpha alone (its first trial is the re-score's
    best; ``stop_gain`` is for blind runs), and one told its damage (no diagnosis) shifts every
    gait by ``config.prior_offset_std``. A diagnosing run that names nothing keeps to its plan's
    :class:`BlindRules`; one that names a damage, to the profile's own shift. A floor above
    ``config.min_speed`` raises the success floor to it.
    """
    plan = start.diagnosis
    if start.informed and config.stop_gain is not None:
        config = replace(config, stop_gain=None)
    if start.informed and plan is None:
        config = replace(config, offset_std=config.prior_offset_std)
    elif plan is not None and not start.informed:
        stop_gain = None if plan.blind.alpha_stop else config.stop_gain
        config = replace(config, offset_std=plan.blind.offset_std, stop_gain=stop_gain)
    floor = start.floor
    if floor is not None and math.isfinite(floor) and floor > config.min_speed:
        config = replace(config, min_speed=min(float(floor), MIN_SPEED_RANGE[1]))
    return config


def _with_prior(opt: Mboa, prior: np.ndarray, config: MboaConfig | None = None) -> Mboa:
    """Return M-BOA started again from ``prior`` (and ``config``), ``opt``'s trials learned."""
    again = Mboa(opt.descriptors, prior, config or opt.config, hypotheses=opt.hypotheses)
    again.vetoed = set(opt.vetoed)
    for t in opt.trials:
        again.observe(t.index, t.measured, tipped=t.tipped)
    return again


@dataclass
class Veto:
    """A gait the tip screen kept from being tried."""

    niche: int
    tilt: float  # its peak tilt in simulation under the damage (the safety model's: predicted)
    risk: float | None = None  # the safety model's risk of tipping (None: a damage's screen)


@dataclass
class AdaptationSession:
    """
    M-BOA over ``archive``'s elites, asked for the next gait and told each trial's outcome.

    ``ask()`` returns the niche to walk next, or None once the run has stopped (M-BOA's rule,
    the budget, the map used up, or :meth:`end`); ``tell(niche, outcome)`` gives its outcome.
    """

    archive: Archive
    config: MboaConfig = field(default_factory=MboaConfig)
    start: SessionStart = field(default_factory=SessionStart)
    vetoes: list[Veto] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.niches, descriptors, map_prior = candidates(self.archive)
        prior = map_prior if self.start.prior is None else np.asarray(self.start.prior)
        if prior.shape != map_prior.shape:
            raise ValueError(
                f'a prior needs one speed per gait ({len(map_prior)}), got {np.shape(prior)}'
            )
        self._map_prior = map_prior
        if self._bank_prior():
            prior = blended_prior(self.start.diagnosis, map_prior)
        self.rules = run_rules(self.config, self.start)
        self.opt = Mboa(descriptors, prior, self.rules, hypotheses=self.start.hypotheses)
        self._blind = (prior, self.rules)  # what a released diagnosis goes back to
        self.screen = self.start.screen
        self.named: tuple[int, ...] | None = None  # the diagnosis's hypotheses the run goes on as
        self._unscored: tuple[int, ...] | None = None  # named, re-scored by the next ask()
        self._screens: dict[int, TipScreen | None] = {}  # each hypothesis's, made when named
        self.posterior: Posterior | None = None  # the diagnosis's, after the last trial
        self._result = AdaptationResult(False, '', config=self.rules)
        self._asked: int | None = None  # the candidate index of the niche ask() returned
        self._ended = False
        self._said = 0  # vetoes said through new_vetoes()
        self._told: list[tuple[int, TrialOutcome]] = []  # (candidate index, outcome) per trial
        self._t0 = time.monotonic()

    # -- ask / tell -------------------------------------------------------------------------
    def ask(self, stop: Callable[[], bool] | None = None) -> int | None:
        """
        Return the niche of the next gait to try (None: the run has stopped).

        ``stop()`` true during a re-score or the hypotheses' walks this ask makes
        (:attr:`rescoring`; the safety model's) ends the run as 'cancelled' within about a
        second (None: they run to their end).
        """
        if self._ended:
            return None
        try:
            with self._stoppable(stop):
                return self._ask(stop)
        except (RescoreStopped, WalksStopped):
            self.end('cancelled')  # a damage named stays named; its re-score is not kept
            return None

    def _stoppable(self, stop: Callable[[], bool] | None) -> AbstractContextManager[None]:
        """Make the hypotheses' walks (if this run has any) stop once ``stop()`` holds."""
        plan = self.start.diagnosis
        walks = plan.walks if plan is not None else None
        return nullcontext() if walks is None else walks.stoppable(stop)

    def _ask(self, stop: Callable[[], bool] | None) -> int | None:
        if self._asked is not None:
            return int(self.niches[self._asked])  # asked again before a tell: the same gait
        if self._unscored is not None:  # after the trial that named it was said
            named, self._unscored = self._unscored, None
            self._as_prior_of(named, stop)
        while True:
            while self._vetoed(self.opt.leading_index()):  # alpha's bar: a gait it could keep
                pass
            if self.opt.stop_reason() is not StopReason.CONTINUE:
                # success is the rule's, whether it ended the run or the budget did
                self._result.success = self.opt.alpha_met()
                self._end(self.opt.should_stop()[1])
                return None
            newer = self.start.updates() if self.start.updates is not None else None
            if newer is not None:
                self.opt = _with_prior(self.opt, newer)  # its bar is vetted before a stop
            first = self._first_index()  # already screened
            if first is not None:
                self._asked = first
                return int(self.niches[first])
            index = self.opt.next_index()
            if not self._vetoed(index):
                self._asked = index
                return int(self.niches[index])

    def tell(
        self,
        niche: int,
        outcome: float | TrialOutcome,
        stop: Callable[[], bool] | None = None,
    ) -> Trial | None:
        """
        Take the outcome of the trial of ``niche`` (the one :meth:`ask` gave).

        A tipped trial counts as failed (0 m/s) and its gait is never tried again. A non-finite
        speed (broken odometry) is never learned: it ends the run (returns None). ``stop()``
        true while the diagnosis walks the hypotheses under this trial ends the run as
        'cancelled' (the trial is kept and returned; the diagnosis is left unfinished).
        """
        index = self._asked
        if index is None or int(self.niches[index]) != int(niche):
            raise ValueError(f'gait {niche} was not asked for (ask() gives the next gait)')
        self._asked = None
        if not isinstance(outcome, TrialOutcome):
            outcome = TrialOutcome(float(outcome))
        measured = 0.0 if outcome.tipped else float(outcome.speed)
        if not math.isfinite(measured):
            self._end(
                f'trial {len(self.opt.trials) + 1} (gait {niche}) measured a non-finite speed '
                f'({measured!r} m/s): the odometry is broken; run stopped'
            )
            return None
        trial = self.opt.observe(index, measured, tipped=outcome.tipped)
        self._result.niches.append(int(niche))
        if outcome.tipped:
            self._result.tipped.append(int(niche))
        self._told.append((index, outcome))
        plan = self.start.diagnosis
        if plan is not None and plan.safety is not None:  # against the belief it was tried on
            plan.safety.observe(index, outcome.peak_tilt, outcome.tipped)
        if plan is not None and outcome.record is not None:
            try:
                with self._stoppable(stop):
                    self._diagnose(int(niche), outcome.record)
            except WalksStopped:
                self._note_named()  # what the run named before this trial
                self.end('cancelled')
        elif plan is not None:  # no record (a tipped trial): the belief and the naming stand
            self._note_named()
        return trial

    def recorded_trials(self) -> list[tuple[int, TrialRecord]]:
        """Return (niche, record) of each trial so far that recorded its walk (not tipped)."""
        return [
            (int(self.niches[index]), outcome.record)
            for index, outcome in self._told
            if outcome.record is not None and not outcome.tipped
        ]

    def end(self, why: str) -> None:
        """Stop the run before its rule does (a trial aborted, a cancel): ``why`` says so."""
        if not self._ended:
            self._end(why)

    def abort(self, exc: TrialAborted) -> None:
        """Stop the run on a trial that could not be completed (a cancel says 'cancelled')."""
        if isinstance(exc, TrialCancelled):
            self.end('cancelled')
        else:
            self.end(f'trial {len(self.opt.trials) + 1} aborted: {exc}')

    # -- what the run holds -----------------------------------------------------------------
    @property
    def finished(self) -> bool:
        """Whether the run has stopped."""
        return self._ended

    def best(self) -> tuple[int, float] | None:
        """Return (niche, measured speed) of the best upright trial so far (None: none yet)."""
        best = self.opt.best()
        return None if best is None else (int(self.niches[best.index]), best.measured)

    def new_vetoes(self) -> list[Veto]:
        """Return the vetoes since the last call (to say each once)."""
        said, self._said = self._said, len(self.vetoes)
        return self.vetoes[said:]

    @property
    def rescoring(self) -> str | None:
        """
        Return the damage just named whose re-score is not cached (None: none).

        The next :meth:`ask` re-scores the top of the map under it first (about half a minute
        of a core for the default map on MuJoCo): a caller may say so before asking.
        """
        named = self._unscored
        return None if named is None else self.start.diagnosis.label_of(named)

    @property
    def unfit(self) -> bool:
        """Whether the posterior holds a damage that does not fit the trials."""
        return self._result.unfit

    @property
    def widened(self) -> int:
        """Return the trial after which the diagnosis went to its wider bank (0: never)."""
        return self._result.widened

    def result(self) -> AdaptationResult:
        """Return the run's outcome so far: its trials, best gait and why it stopped."""
        r = self._result
        r.trials = list(self.opt.trials)
        best = self.best()
        if best is not None:
            r.best_niche, r.best_speed = best
        if not self._ended:
            r.elapsed = time.monotonic() - self._t0
        return r

    # -- inside -----------------------------------------------------------------------------
    def _end(self, message: str) -> None:
        self._result.message = message
        self._ended = True
        self._asked = None
        self._result.elapsed = time.monotonic() - self._t0

    def _diagnose(self, niche: int, record: TrialRecord) -> None:
        """Weigh the hypotheses by a trial; name a damage or a leg set, keep it, or give it up."""
        plan = self.start.diagnosis
        post = self.posterior = plan.diagnosis.observe(niche, record)
        if plan.safety is not None:
            plan.safety.weigh(post.probabilities)
        holding, self._result.unfit = plan.assess(post.probabilities)
        if self._result.unfit and self.named is None and plan.wider is not None:
            plan = self._widen(plan.wider())
            holding, self._result.unfit = plan.assess(self.posterior.probabilities)
        post = self.posterior
        self._result.posterior = post.describe()
        p = post.probabilities
        if self._result.unfit and plan.blind.unfit_fallback and self.named is None:
            self._fall_back()
        if holding is not None and (holding != self.named or len(holding) > 1):
            self._go_on_as(holding)  # a leg set's weights follow the posterior
        elif self.named is not None and p[list(self.named)].sum() < plan.release:
            self._go_on_as(None)
        elif self.named is None and self._bank_prior():
            self._go_on_as(None)  # the blind prior, weighed by the new posterior
        self._note_named()

    def _note_named(self) -> None:
        """Record what the run names after this trial (one entry per trial told)."""
        plan, named, result = self.start.diagnosis, self.named, self._result
        result.named.append('' if named is None else plan.label_of(named))
        result.named_legs.append(() if named is None else plan.damages[named[0]].failed_legs)

    def _widen(self, wider: DiagnosisPlan) -> DiagnosisPlan:
        """Weigh every trial so far under ``wider``'s hypotheses, and go on diagnosing by it."""
        for index, outcome in self._told:  # as tell() did, each against the belief before it
            if wider.safety is not None:
                wider.safety.observe(index, outcome.peak_tilt, outcome.tipped)
            if outcome.record is not None:
                self.posterior = wider.diagnosis.observe(int(self.niches[index]), outcome.record)
                if wider.safety is not None:
                    wider.safety.weigh(self.posterior.probabilities)
        self.start = replace(self.start, diagnosis=wider)
        self._screens = {}  # by hypothesis: the wider bank numbers them anew
        self._result.widened = len(self._told)
        return wider

    def _fall_back(self) -> None:
        """Adapt and stop as blind M-BOA without a diagnosis, from now on (BlindRules)."""
        prior, rules = self._blind
        plain = run_rules(self.config, replace(self.start, diagnosis=None))  # as if undiagnosed
        if self.start.diagnosis.blind.fallback_alpha_stop:
            plain = replace(plain, stop_gain=None)
        if plain != rules:
            self._blind = (prior, plain)
            self.rules = plain
            self.opt = _with_prior(self.opt, self.opt.prior, plain)
            self._result.config = plain

    def _go_on_as(self, named: tuple[int, ...] | None) -> None:
        """Go on as the damage-informed prior of the ``named`` hypotheses (None: blind)."""
        plan = self.start.diagnosis
        self._unscored = None
        if named is None:
            prior, self.rules = self._blind
            if self._bank_prior():
                prior = blended_prior(plan, self._map_prior)
                self._blind = (prior, self.rules)
            self.screen = self.start.screen
            self._restart(prior)
        else:
            screens = [self._screen_of(h) for h in named]
            if None in screens or len(screens) == 1:
                self.screen = screens[0]  # None: no tip guard
            else:
                self.screen = TipScreen.worst_of(screens)
            if plan.unscored(named):  # slow: made once this trial is said (ask())
                self._unscored = named
            else:
                self._as_prior_of(named)
        self.named = named

    def _as_prior_of(self, named: tuple[int, ...], stop: Callable[[], bool] | None = None) -> None:
        """Go on from the re-scores of ``named`` (one not made yet is made now: ``stop``)."""
        plan = self.start.diagnosis
        fresh = plan.unscored(named)
        t0 = time.monotonic()
        try:
            prior = plan.prior_of(named, self.posterior.probabilities, stop)
        finally:
            if fresh:
                self._result.rescore_s += time.monotonic() - t0
        self.rules = run_rules(self.config, replace(self.start, prior=prior))
        self._restart(prior)

    def _restart(self, prior: np.ndarray) -> None:
        """Start M-BOA again from ``prior`` under :attr:`rules`, the trials learned."""
        self.opt = _with_prior(self.opt, prior, self.rules)
        self._result.config = self.rules

    def _screen_of(self, h: int) -> TipScreen | None:
        """Return hypothesis ``h``'s tip screen (made once: each keeps the gaits it walked)."""
        if h not in self._screens:
            plan = self.start.diagnosis
            self._screens[h] = plan.screen_of(plan.damages[h])
        return self._screens[h]

    def _first_index(self) -> int | None:
        """
        Return the first trial's gait when the blind rules choose it (None: M-BOA's choice).

        With :attr:`FirstGait.EXPECTED`, the untried, unvetoed gait with the best expected speed
        over the hypotheses (:func:`blended_prior`), before any trial of a run naming nothing;
        with :attr:`FirstGait.INFORMATIVE`, of such gaits near it, the one whose trial tells the
        hypotheses apart best.
        """
        plan = self.start.diagnosis
        if (
            plan is None
            or plan.blind.first is FirstGait.FASTEST
            or self.start.informed
            or self.named is not None
            or self.opt.trials
        ):
            return None
        expected = blended_prior(plan, self._map_prior)
        many = FIRST_CANDIDATES if plan.blind.first is FirstGait.INFORMATIVE else 1
        chosen: list[int] = []
        for index in map(int, np.argsort(-expected, kind='stable')):
            if chosen and expected[index] < (1.0 - FIRST_SLACK) * expected[chosen[0]]:
                break
            if index not in self.opt.vetoed and not self._vetoed(index):
                chosen.append(index)
                if len(chosen) == many:
                    break
        if len(chosen) <= 1:
            return chosen[0] if chosen else None
        apart = [plan.diagnosis.separation(int(self.niches[i])) for i in chosen]
        return chosen[int(np.argmax(apart))]

    def _bank_prior(self) -> bool:
        """Whether the blind prior is the bank weighed by the posterior (:class:`BlindRules`)."""
        plan = self.start.diagnosis
        return plan is not None and plan.blind.bank_prior and not self.start.informed

    def _vetoed(self, index: int | None) -> bool:
        """
        Veto ``index`` if a screen says it tips (False: no screen, no gait, or upright).

        The screens: the prior's or the named damage's, then a diagnosing run's safety model,
        named or not (a damage named wrongly has a screen that does not know the real one).
        """
        if index is None:
            return False
        plan = self.start.diagnosis
        for screen in (self.screen, None if plan is None else plan.safety):
            if screen is not None and screen.tips(index):
                self.opt.veto(index)
                niche = int(self.niches[index])
                self._result.vetoed.append(niche)
                risk = screen.risks[index] if isinstance(screen, SafetyModel) else None
                self.vetoes.append(Veto(niche, screen.tilts[index], risk))
                return True
        return False


def run_session(
    session: AdaptationSession,
    trial: Callable[[int], float | TrialOutcome],
    on_trial: Callable[[Trial, int, AdaptationSession], None] | None = None,
    cancelled: Callable[[], bool] | None = None,
) -> AdaptationResult:
    """
    Drive ``session`` with ``trial(niche)`` until it stops; return its result.

    ``on_trial(trial, niche, session)`` hears each trial; ``cancelled()``, asked before each,
    ends the run as 'cancelled'. A trial that raises :class:`TrialAborted` ends it with why.
    """
    while (niche := session.ask(cancelled)) is not None:  # a cancel stops a re-score too
        if cancelled is not None and cancelled():
            session.end('cancelled')
            break
        try:
            outcome = trial(niche)
        except TrialAborted as exc:
            session.abort(exc)
            break
        told = session.tell(niche, outcome, cancelled)
        if told is not None and on_trial is not None:
            on_trial(told, niche, session)
    return session.result()


def adapt(
    archive: Archive,
    trial: Callable[[int], float | TrialOutcome],
    config: MboaConfig | None = None,
    start: SessionStart | None = None,
) -> AdaptationResult:
    """Run a whole session on ``trial(niche)`` (a speed or a TrialOutcome); return its result."""
    session = AdaptationSession(archive, config or MboaConfig(), start or SessionStart())
    return run_session(session, trial)
