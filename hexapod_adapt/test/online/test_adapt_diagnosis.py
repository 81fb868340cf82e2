# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Naming the damage from the trials (hexapod_adapt.online.diagnosis) and a session that acts on it.

The hypotheses are walked on the map's engine (MuJoCo, at the map's physics step); the trials
on MuJoCo at its converged step, a physics the hypotheses were not walked in, and without foot
contacts, as a robot gives them.
"""

from __future__ import annotations

from dataclasses import replace
import math
import time

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
from hexapod_adapt.online import diagnosis as diagnosis_module
from hexapod_adapt.online.adaptation import candidates, recorded_trial, TrialOutcome
from hexapod_adapt.online.bank import DamageBank
from hexapod_adapt.online.ceiling import RescoreStopped
from hexapod_adapt.online.diagnosis import (
    ASLEEP_NATS,
    calibrate_gap,
    Diagnosis,
    feature_names,
    feature_noise,
    GapCalibration,
    HypothesisWalks,
    NONE_LABEL,
    signature,
    TrialRecord,
    Weighing,
)
from hexapod_adapt.online.experiment import intact_gap
from hexapod_adapt.online.mboa import MboaConfig, PROFILES
from hexapod_adapt.online.prior import TipScreen
from hexapod_adapt.online.session import (
    AdaptationSession,
    BlindRules,
    diagnosis_plan,
    DiagnosisPlan,
    FirstGait,
    SessionStart,
)
from hexapod_sim import create_simulator, SimConfig
from hexapod_sim.damage import Damage
from hexapod_sim.traces import trace_gait
import numpy as np
import pytest


@pytest.fixture(scope='module')
def archive():
    return load_archive(shipped_map(DEFAULT_MAP))


@pytest.fixture(scope='module')
def walks(archive):
    return HypothesisWalks(archive)


@pytest.fixture(scope='module')
def trial_sim():
    with create_simulator(SimConfig.converged('mujoco')) as sim:
        yield sim


def fastest(archive, k: int) -> list[int]:
    niches = archive.elite_indices()
    return [int(n) for n in niches[np.argsort(-archive.fitness[niches], kind='stable')][:k]]


def straight_walk(speed: float, crab: float, yaw_rate: float = 0.0, n: int = 500) -> TrialRecord:
    t = np.linspace(0.01, 5.0, n)
    yaw = yaw_rate * t
    heading = crab  # the start's yaw is 0: the walking direction is the crab angle
    position = np.column_stack([speed * t * math.cos(heading), speed * t * math.sin(heading)])
    attitude = np.column_stack([np.zeros(n), np.full(n, 0.02), yaw])
    return TrialRecord(t, position, attitude, crab, 0.5)


def test_a_record_refuses_what_is_not_a_trial():
    good = straight_walk(0.2, 0.3)
    with pytest.raises(ValueError, match='increasing time stamps'):
        TrialRecord(good.t[::-1], good.position, good.attitude, 0.3, 0.5)
    with pytest.raises(ValueError, match=r'attitude must be \(500, 3\)'):
        TrialRecord(good.t, good.position, good.attitude[:, :2], 0.3, 0.5)
    bad = good.position.copy()
    bad[7, 0] = np.nan
    with pytest.raises(ValueError, match='must be finite'):
        TrialRecord(good.t, bad, good.attitude, 0.3, 0.5)
    with pytest.raises(ValueError, match='period > 0'):
        TrialRecord(good.t, good.position, good.attitude, 0.3, 0.0)
    with pytest.raises(ValueError, match='holds no foot contacts'):
        signature(good, contacts=True)


def test_the_signature_measures_speed_drift_yaw_rate_and_tilt():
    s = dict(zip(feature_names(False), signature(straight_walk(0.2, 0.3, yaw_rate=0.05), False)))
    # the heading is taken at the window's start (after 1 s of settling): a turning walk drifts
    assert s['speed'] == pytest.approx(0.2, abs=0.01)
    assert abs(s['drift']) < 0.02
    assert s['yaw_rate'] == pytest.approx(0.05, abs=1e-6)
    assert s['pitch'] == pytest.approx(0.02) and s['roll'] == pytest.approx(0.0)
    assert all(abs(v) < 1e-12 for k, v in s.items() if '_phase_' in k)  # no swing in the tilt


def test_a_temperature_tempers_each_trial_s_evidence_and_weighing_refuses_nonsense():
    walks = {0: straight_walk(0.2, 0.0), 1: straight_walk(0.15, 0.0)}
    trial = straight_walk(0.19, 0.0)
    odds = []
    for temperature in (1.0, 0.5):
        diagnosis = Diagnosis(
            ('a', 'b'), lambda niche, h: walks[h], weighing=Weighing(temperature=temperature)
        )
        p = diagnosis.observe(7, trial).probabilities
        odds.append(math.log(p[0] / p[1]))
    assert odds[0] > 0.5 and odds[1] == pytest.approx(odds[0] / 2)
    for bad in (
        {'temperature': 0.0},
        {'temperature': 1.5},
        {'none_prior': 1.0},
        {'wake_walks': 0},
        {'wake_walks': 2.5},
        {'wake_walks': True},
    ):
        with pytest.raises(ValueError):
            Weighing(**bad)


def _walk(speed: float, yaw_rate: float, pitch: float) -> TrialRecord:
    record = straight_walk(speed, 0.0, yaw_rate)
    attitude = record.attitude.copy()
    attitude[:, 1] = pitch
    return TrialRecord(record.t, record.position, attitude, 0.0, 0.5)


def test_a_hypothesis_far_behind_is_not_walked_until_it_could_matter(monkeypatch):
    # 30 hypotheses; hypothesis 29 walks far from the others (faster, turning, pitched), and
    # the trials are hypothesis 0's walks twice, then 29's four times
    def walk(niche: int, h: int) -> TrialRecord:
        odd = h == 29
        return _walk(0.1 + 0.004 * h + 0.4 * odd, 0.6 * odd, 0.02 + 0.3 * odd)

    trials = [(n, walk(n, 0 if n < 2 else 29)) for n in range(6)]
    labels = tuple(f'h{h}' for h in range(30))
    walked: list[tuple[int, int]] = []
    lazy = Diagnosis(labels, lambda n, h: walked.append((n, h)) or walk(n, h))
    monkeypatch.setattr(diagnosis_module, 'ASLEEP_NATS', math.inf)  # every hypothesis walked
    every = Diagnosis(labels, walk)
    asleep, walks = [], []
    for niche, record in trials:
        expected = every.observe(niche, record).probabilities
        monkeypatch.setattr(diagnosis_module, 'ASLEEP_NATS', ASLEEP_NATS)
        before = len(walked)
        got = lazy.observe(niche, record).probabilities
        asleep.append(lazy.asleep)
        walks.append(len(walked) - before)
        monkeypatch.setattr(diagnosis_module, 'ASLEEP_NATS', math.inf)
        # the same posterior: an asleep hypothesis's bound is below 1e-10 of the leader's
        assert np.allclose(got, expected, rtol=1e-6, atol=1e-9), (asleep, got, expected)
    # 29 fell asleep, woke when the trials turned to it, and leads; the others sleep now
    assert asleep[:2] == [1, 1] and asleep[-1] == 29 and np.argmax(got) == 29, asleep
    assert len(set(walked)) == len(walked)  # each walk once
    assert walks[1] == 29 and walks[-1] == 1, walks  # a trial walks the hypotheses in play


def test_when_no_hypothesis_fits_a_trial_wakes_at_most_its_cap_of_walks():
    # 60 hypotheses, each walking straight at its own speed; the trials turn and pitch as none
    # does, so the most probable loses many nats a trial and asleep bounds keep coming within
    # reach of it (the judge's trials in issue 67's runs)
    def walk(niche: int, h: int) -> TrialRecord:
        return _walk(0.1 + 0.01 * h, 0.0, 0.02)

    labels = tuple(f'h{h}' for h in range(60))
    trials = [(n, _walk(0.45, 0.5 * (-1) ** n, 0.2 + 0.05 * n)) for n in range(12)]
    costs = {}
    for cap in (None, 5):
        walked: list[tuple[int, int]] = []
        weighing = Weighing(wake_walks=cap)
        diagnosis = Diagnosis(
            labels, lambda n, h: walked.append((n, h)) or walk(n, h), weighing=weighing
        )
        per_trial = []
        for niche, record in trials:
            before = len(walked)
            p = diagnosis.observe(niche, record).probabilities
            # waking walks the gaits of earlier trials; the trial's own gait is the awake ones'
            per_trial.append(sum(n != niche for n, _ in walked[before:]))
            assert p.sum() == pytest.approx(1.0)
            # the most probable has weighed every trial so far: no bound leads the posterior
            leader = int(np.argmax(p))
            assert leader == 29 and all((n, leader) in walked for n in range(niche + 1))
        costs[cap] = per_trial
        assert len(set(walked)) == len(walked)  # each walk once
        assert diagnosis.asleep > 0 and diagnosis.simulated == len(walked)
    assert max(costs[5]) <= 5 < max(costs[None]), costs
    assert sum(costs[5]) < sum(costs[None])


def test_with_a_fit_floor_a_probable_hypothesis_that_fits_badly_is_not_named():
    # two hypotheses far from the trials (3 and 4 speed noise scales); the nearer one holds
    # the posterior, but its mean log likelihood (-2.9) lies below a floor of -2
    walks = {0: straight_walk(0.32, 0.0), 1: straight_walk(0.36, 0.0)}
    trial = straight_walk(0.2, 0.0)
    for floor, named in ((None, (0,)), (-2.0, None)):
        weighing = Weighing(none_prior=0.01, fit_floor=floor)
        diagnosis = Diagnosis(('near', 'far'), lambda niche, h: walks[h], weighing=weighing)
        plan = DiagnosisPlan(diagnosis, (Damage.lifted([1]), Damage.lifted([2])), np.zeros((2, 3)),
                             lambda d: None, leg_sets=False)  # fmt: skip
        for niche in range(4):
            p = diagnosis.observe(niche, trial).probabilities
        assert p[0] > 0.9 and plan.holding(p) == named, (p, floor)
    assert diagnosis.fits(1) is False
    with pytest.raises(ValueError, match='fit_floor'):
        Weighing(fit_floor=0.5)


def test_a_session_whose_most_probable_damage_does_not_fit_says_so_and_stays_blind(archive):
    walks = {0: straight_walk(0.32, 0.0), 1: straight_walk(0.36, 0.0)}
    trial = TrialOutcome(0.2, record=straight_walk(0.2, 0.0))
    n = len(archive.elite_indices())
    for floor, named, unfit in ((None, (0,), False), (-2.0, None, True)):
        weighing = Weighing(none_prior=0.01, fit_floor=floor)
        diagnosis = Diagnosis(('near', 'far'), lambda niche, h: walks[h], weighing=weighing)
        plan = DiagnosisPlan(diagnosis, (Damage.lifted([1]), Damage.lifted([2])), np.zeros((2, n)),
                             lambda d: None, leg_sets=False)  # fmt: skip
        config = replace(PROFILES['default'], max_trials=4, min_speed=0.9)
        session = AdaptationSession(archive, config, SessionStart(diagnosis=plan))
        while (niche := session.ask()) is not None:
            session.tell(niche, trial)
        assert session.named == named and session.unfit is unfit, floor
        result = session.result()
        assert result.unfit is unfit and result.named[-1] == ('' if unfit else 'leg 1 lifted')


def test_a_run_whose_leader_does_not_fit_may_fall_back_to_blind_m_boa(archive):
    walks = {0: straight_walk(0.32, 0.0), 1: straight_walk(0.36, 0.0)}
    trial = TrialOutcome(0.2, record=straight_walk(0.2, 0.0))
    n = len(archive.elite_indices())
    config = replace(PROFILES['default'], max_trials=4, min_speed=0.9)
    for fallback, alpha_stop in ((False, False), (True, False), (True, True)):
        weighing = Weighing(none_prior=0.01, fit_floor=-2.0)
        diagnosis = Diagnosis(('near', 'far'), lambda niche, h: walks[h], weighing=weighing)
        rules = BlindRules(unfit_fallback=fallback, fallback_alpha_stop=alpha_stop)
        plan = DiagnosisPlan(diagnosis, (Damage.lifted([1]), Damage.lifted([2])), np.zeros((2, n)),
                             lambda d: None, leg_sets=False, blind=rules)  # fmt: skip
        session = AdaptationSession(archive, config, SessionStart(diagnosis=plan))
        blind = session.rules
        assert (blind.offset_std, blind.stop_gain) == (BlindRules().offset_std, None)
        while not session.unfit and (niche := session.ask()) is not None:
            session.tell(niche, trial)
        assert session.unfit
        rules = session.result().config
        if fallback:  # the request's own: blind M-BOA as without a diagnosis
            stop_gain = None if alpha_stop else config.stop_gain
            assert (rules.offset_std, rules.stop_gain) == (config.offset_std, stop_gain)
            assert session.opt.config == rules
        else:
            assert rules == blind


def test_a_run_that_no_hypothesis_fits_weighs_its_trials_under_a_wider_bank(archive):
    # the first bank's two hypotheses are far from the trials; the wider bank holds one that
    # walks as they do: the run weighs every trial so far under it and names it, not falling back
    walks = {0: straight_walk(0.32, 0.0), 1: straight_walk(0.36, 0.0), 2: straight_walk(0.2, 0.0)}
    trial = TrialOutcome(0.2, record=straight_walk(0.2, 0.0))
    n = len(archive.elite_indices())
    weighing = Weighing(none_prior=0.01, fit_floor=-2.0)
    damages = (Damage.lifted([1]), Damage.lifted([2]), Damage.of('locked', [3]))
    seen: list[tuple[int, int]] = []  # (hypothesis, niche) of each walk of the wider diagnosis

    def plan_of(hypotheses: tuple[int, ...], wider=None) -> DiagnosisPlan:
        def walk(niche: int, h: int) -> TrialRecord:
            if len(hypotheses) == 3:
                seen.append((h, niche))
            return walks[hypotheses[h]]

        diagnosis = Diagnosis(tuple(damages[h].label for h in hypotheses), walk, weighing=weighing)
        priors = np.zeros((len(hypotheses), n))
        priors[2:] = np.nan  # the locked leg's re-score is not cached: made when it is named
        return DiagnosisPlan(diagnosis, tuple(damages[h] for h in hypotheses), priors,
                             lambda d: None, leg_sets=False, wider=wider,
                             rescore=rescore)  # fmt: skip

    def rescore(damage: Damage, stop) -> np.ndarray:  # quick_rescore's contract, in short
        if stop is not None and stop():
            raise RescoreStopped(damage.label)
        time.sleep(0.01)
        return np.full(n, 0.25)

    config = replace(PROFILES['default'], max_trials=6, min_speed=0.9)
    unfit_at = 0  # the trial after which the first bank's leader fits no trial
    for wider in (None, lambda: plan_of((0, 1, 2))):
        seen.clear()
        session = AdaptationSession(
            archive, config, SessionStart(diagnosis=plan_of((0, 1), wider))
        )
        tried = []
        while session.named is None and (niche := session.ask()) is not None:
            session.tell(niche, trial)
            tried.append(niche)
            unfit_at = unfit_at or (len(tried) if session.unfit else 0)
        result = session.result()
        if wider is None:  # the leader never fits: the run names nothing
            assert session.named is None and session.unfit and result.named[-1] == ''
            assert result.widened == 0 and 0 < unfit_at < len(tried)
            continue
        # widened then: every trial so far weighed again, the one that fits named at once
        assert result.widened == unfit_at and len(tried) == unfit_at
        assert session.named == (2,) and not session.unfit, session.posterior.describe()
        assert result.named[-1] == 'leg 3 locked' and set(result.named[:-1]) == {''}
        # named, its re-score is made by the next ask (the trial's feedback says so first)
        assert session.rescoring == 'leg 3 locked' and session.result().rescore_s == 0.0
        session.ask()
        assert session.rescoring is None and session.result().rescore_s >= 0.01
        np.testing.assert_array_equal(session.start.diagnosis.priors[2], np.full(n, 0.25))
        assert sorted({niche for _, niche in seen}) == sorted(tried)
        assert session.start.diagnosis.damages == damages
    # a cancel during that re-score ends the run there, keeping nothing of the re-score
    session = AdaptationSession(
        archive, config, SessionStart(diagnosis=plan_of((0, 1), lambda: plan_of((0, 1, 2))))
    )
    while session.named is None and (niche := session.ask()) is not None:
        session.tell(niche, trial)
    assert session.rescoring == 'leg 3 locked'
    asked: list[int] = []
    assert session.ask(lambda: asked.append(1) is None) is None
    assert asked and session.result().message == 'cancelled' and session.rescoring is None
    assert np.isnan(session.start.diagnosis.priors[2]).all() and session.ask() is None


@pytest.mark.parametrize(
    'true,others',
    [
        (Damage.lifted([1]), [Damage.lifted([4]), Damage.lifted([1, 4])]),
        (Damage.of('locked', [2]), [Damage.of('locked', [5]), Damage.lifted([2])]),
        (Damage.of('no_tibia', [3]), [Damage.of('no_tibia', [6]), Damage.lifted([3])]),
        (Damage.of('unpowered_femur', [6]), [Damage.of('unpowered_femur', [1]), Damage()]),
    ],
    ids=lambda v: v.label if isinstance(v, Damage) else '',
)
def test_trials_of_each_kind_name_it_among_its_neighbours(archive, walks, trial_sim, true, others):
    hypotheses = [true, *others]
    diagnosis = Diagnosis(tuple(d.label for d in hypotheses), walks.under(hypotheses))
    for niche in fastest(archive, 2):
        trace = trace_gait(archive.genotypes[niche], trial_sim, true, archive.trial_duration)
        post = diagnosis.observe(niche, TrialRecord.from_trace(trace, contacts=False))
    # named, and more likely than the rest together (a lost tibia and a lifted leg both leave
    # the leg unloaded: two trials put 0.86 on the true one of that pair)
    assert post.leader == 0, post.describe()
    assert post.probabilities[0] > 0.5, post.describe()


def test_a_damage_no_hypothesis_holds_is_none_of_these(archive, walks, trial_sim):
    hypotheses = [Damage.lifted([2]), Damage.lifted([5]), Damage.lifted([2, 5])]
    diagnosis = Diagnosis(tuple(d.label for d in hypotheses), walks.under(hypotheses))
    true = Damage.lifted([1, 4])
    for niche in fastest(archive, 2):
        trace = trace_gait(archive.genotypes[niche], trial_sim, true, archive.trial_duration)
        post = diagnosis.observe(niche, TrialRecord.from_trace(trace, contacts=False))
    assert post.top(1)[0][0] == NONE_LABEL, post.describe()


def _tilted(record: TrialRecord, roll: float, pitch: float) -> TrialRecord:
    """Return ``record`` as an IMU mounted ``roll`` and ``pitch`` rad off would give it."""
    return replace(record, attitude=record.attitude + np.array([roll, pitch, 0.0]))


def test_a_calibration_measures_a_constant_bias_and_refuses_too_few_gaits():
    walks = [straight_walk(0.2, 0.1), straight_walk(0.3, -0.2, 0.05), straight_walk(0.25, 0.4)]
    same = calibrate_gap(walks, walks)
    base = feature_noise(feature_names(False))
    assert np.allclose(same.offset, 0.0) and np.allclose(same.noise, base)
    biased = calibrate_gap([_tilted(w, 0.05, -0.02) for w in walks], walks)
    names = feature_names(False)
    expect = np.zeros(len(names))
    expect[names.index('roll')], expect[names.index('pitch')] = 0.05, -0.02
    assert np.allclose(biased.offset, expect) and np.allclose(biased.noise, base)
    # gaits the simulation misses by different amounts widen those features' noise
    slower = calibrate_gap([straight_walk(0.15, 0.1), straight_walk(0.3, -0.2, 0.05)], walks[:2])
    speed = names.index('speed')
    assert slower.offset[speed] == pytest.approx(-0.025, abs=1e-3)
    assert slower.noise[speed] > base[speed]
    with pytest.raises(ValueError, match='two or more gaits'):
        calibrate_gap(walks[:1], walks[:1])
    with pytest.raises(ValueError, match='two or more gaits'):
        calibrate_gap(walks, walks[:2])
    with pytest.raises(ValueError, match='features each'):
        GapCalibration(np.zeros(3), np.ones(3))
    with pytest.raises(ValueError, match='noise scales > 0'):
        GapCalibration(np.zeros(len(names)), np.zeros(len(names)))
    with pytest.raises(ValueError, match='foot contacts'):
        Diagnosis(('a',), lambda niche, h: None, contacts=True, calibration=same)


def test_a_robot_whose_imu_is_mounted_off_is_diagnosed_once_calibrated(archive, walks, trial_sim):
    """
    An IMU 6 deg off in roll: the true damage fits worse; three intact walks calibrate it away.

    The trials here are the hypotheses' own physics, so the bias is the whole gap: a floor of
    -2 nats a trial turns the true damage away uncalibrated and keeps it calibrated.
    """
    roll, pitch = math.radians(6.0), math.radians(-2.0)
    intact = fastest(archive, 3)
    observed = [
        _tilted(
            TrialRecord.from_trace(
                trace_gait(archive.genotypes[n], trial_sim, Damage(), archive.trial_duration),
                contacts=False,
            ),
            roll,
            pitch,
        )
        for n in intact
    ]
    calibration = calibrate_gap(observed, [walks(n, Damage()) for n in intact])
    hypotheses = [Damage.lifted([1]), Damage.lifted([4]), Damage.lifted([1, 4])]
    labels = tuple(d.label for d in hypotheses)
    strict = Weighing(fit_floor=-2.0)
    plain = Diagnosis(labels, walks.under(hypotheses), weighing=strict)
    calibrated = Diagnosis(
        labels, walks.under(hypotheses), weighing=strict, calibration=calibration
    )
    for niche in fastest(archive, 2):
        trace = trace_gait(archive.genotypes[niche], trial_sim, hypotheses[0], 5.0)
        record = _tilted(TrialRecord.from_trace(trace, contacts=False), roll, pitch)
        before, after = plain.observe(niche, record), calibrated.observe(niche, record)
    assert before.leader == 0 and not plain.fits(0), before.describe()
    assert after.leader == 0 and after.probabilities[0] > 0.9, after.describe()
    assert calibrated.fits(0)


def test_the_experiment_s_calibration_walks_the_fastest_gaits_on_the_trials_physics(
    archive, walks, trial_sim
):
    """
    On the hypotheses' own physics next to no gap; on softer servos, one the walks measure.

    (A trial samples every physics step, a hypothesis's walk every fourth: the means differ by
    under 2 mm/s or 2 mrad. The default map's fastest gaits hardly feel the floor's friction:
    at 0.3 the gap is under 1 cm/s; servos of compliance slope 64, the calibration study's
    other physics, move it 3 cm/s.)
    """
    base = feature_noise(feature_names(False))
    same = intact_gap(archive, trial_sim, walks, 3)
    assert np.max(np.abs(same.offset)) < 0.002 and np.allclose(same.noise, base, atol=1e-3)
    converged = SimConfig.converged('mujoco')
    softer = replace(converged, mujoco=replace(converged.mujoco, compliance_slope=64))
    with create_simulator(softer) as sim:
        other = intact_gap(archive, sim, walks, 3)
    assert np.max(np.abs(other.offset)) > 0.01 and np.all(other.noise >= base)


def _bank(archive, damages: list[Damage]) -> DamageBank:
    """Return a bank of ``damages`` whose re-scores are the map's speeds, each scaled apart."""
    speeds = np.array(
        [archive.speeds()[archive.elite_indices()] * (0.5 + 0.1 * k) for k in range(len(damages))]
    )
    assert speeds.shape == (len(damages), len(archive.elite_indices()))
    return DamageBank('mujoco', tuple(damages), speeds)


def test_a_trial_without_a_record_keeps_the_naming_one_entry_per_trial(archive, walks, trial_sim):
    # a first trial that tipped (no record: no evidence) and then one of leg 4 lifted: what
    # was named after each trial stays aligned with the trials ("named by trial 2" counts)
    damages = [Damage.lifted([1]), Damage.lifted([4]), Damage.lifted([3, 6])]
    plan = diagnosis_plan(archive, _bank(archive, damages), walks=walks)
    config = replace(PROFILES['default'], max_trials=6, min_speed=0.9)
    session = AdaptationSession(archive, config, SessionStart(diagnosis=plan))
    niche = session.ask()
    session.tell(niche, TrialOutcome(0.0, True, 1.0))
    assert session.result().named == [''] and session.result().named_legs == [()]
    walk = recorded_trial(archive, damages[1], trial_sim)
    niche = session.ask()
    session.tell(niche, walk(niche))
    result = session.result()
    assert session.named == (1,) and len(result.trials) == 2
    assert result.named == ['', damages[1].label] and result.named_legs == [(), (4,)]


def test_a_blind_session_goes_on_as_the_damage_it_names_and_back_when_contradicted(
    archive, walks, trial_sim
):
    damages = [Damage.lifted([1]), Damage.lifted([4]), Damage.lifted([3, 6])]
    plan = diagnosis_plan(archive, _bank(archive, damages), walks=walks)
    # a success floor no gait reaches: the run goes on through the budget, whatever it names
    config = replace(PROFILES['default'], max_trials=6, min_speed=0.9)
    session = AdaptationSession(archive, config, SessionStart(diagnosis=plan))
    blind = BlindRules()  # while nothing is named: the shared shift
    assert session.rules.offset_std == blind.offset_std > 0
    first = recorded_trial(archive, damages[1], trial_sim)
    niche = session.ask()
    session.tell(niche, first(niche))
    assert session.named == (1,), session.posterior.describe()
    assert session.rules.stop_gain is None  # as the damage's prior: alpha's rule alone
    assert session.rules.offset_std == 0.0
    assert session.result().named == [damages[1].label]
    # trials that say another damage: the named one is given up (and the other named)
    other = recorded_trial(archive, damages[2], trial_sim)
    for _ in range(3):
        niche = session.ask()
        if niche is None:
            break
        session.tell(niche, other(niche))
        if session.named != (1,):
            break
    assert session.named in (None, (2,)), session.posterior.describe()
    assert session.result().posterior.startswith(damages[2].label) or session.named is None


def test_blind_rules_hold_while_nothing_is_named_and_the_prior_s_once_named(
    archive, walks, trial_sim
):
    damages = [Damage.lifted([1]), Damage.lifted([4])]
    blind = BlindRules(offset_std=0.1, alpha_stop=True)
    plan = diagnosis_plan(archive, _bank(archive, damages), walks=walks, blind=blind)
    config = replace(PROFILES['default'], max_trials=6)
    session = AdaptationSession(archive, config, SessionStart(diagnosis=plan))
    assert session.rules.stop_gain is None and session.rules.offset_std == 0.1
    first = recorded_trial(archive, damages[1], trial_sim)
    niche = session.ask()
    session.tell(niche, first(niche))
    assert session.named == (1,), session.posterior.describe()
    # as the damage's prior: its rules, not the blind ones
    assert session.rules.stop_gain is None and session.rules.offset_std == 0.0
    # the default plan keeps the profile's expected-gain stop and no offset
    shipped = diagnosis_plan(archive, _bank(archive, damages), walks=walks)
    rules = AdaptationSession(archive, config, SessionStart(diagnosis=shipped)).rules
    assert (rules.stop_gain, rules.offset_std) == (
        None if BlindRules().alpha_stop else config.stop_gain,
        BlindRules().offset_std,
    )


def test_a_bank_prior_is_the_re_scores_weighed_by_the_posterior(archive, walks, trial_sim):
    damages = [Damage.lifted([1]), Damage.lifted([4]), Damage.lifted([3, 6])]
    bank = _bank(archive, damages)
    blind = BlindRules(bank_prior=True)
    # evidence so tempered that no hypothesis is named: the run stays blind, its prior following
    # the posterior
    weighing = Weighing(temperature=0.01)
    plan = diagnosis_plan(archive, bank, walks=walks, blind=blind, weighing=weighing)
    config = replace(PROFILES['default'], max_trials=4, min_speed=0.9)
    session = AdaptationSession(archive, config, SessionStart(diagnosis=plan))
    _, _, map_prior = candidates(archive)
    np.testing.assert_allclose(session.opt.prior, 0.8 * bank.speeds.mean(axis=0) + 0.2 * map_prior)
    trial = recorded_trial(archive, damages[1], trial_sim)
    niche = session.ask()
    session.tell(niche, trial(niche))
    p = session.posterior.probabilities
    np.testing.assert_allclose(session.opt.prior, p[:-1] @ bank.speeds + p[-1] * map_prior)
    assert p[1] == max(p) and session.named is None


def test_the_first_gait_may_be_the_fastest_on_average_over_the_hypotheses(
    archive, walks, trial_sim
):
    damages = [Damage.lifted([1]), Damage.lifted([4])]
    _, _, map_prior = candidates(archive)
    speeds = np.tile(map_prior * 0.2, (2, 1))
    robust = int(np.argsort(map_prior)[len(map_prior) // 2])  # a gait of middling intact speed
    speeds[:, robust] = map_prior.max()  # walks under every hypothesis as the best does intact
    bank = DamageBank('mujoco', tuple(damages), speeds)
    config = replace(PROFILES['default'], max_trials=3, min_speed=0.9)
    firsts = {}
    for first in FirstGait:
        plan = diagnosis_plan(archive, bank, walks=walks, blind=BlindRules(first=first))
        session = AdaptationSession(archive, config, SessionStart(diagnosis=plan))
        firsts[first] = niche = session.ask()
        session.tell(niche, recorded_trial(archive, damages[0], trial_sim)(niche))
        assert session.ask() not in (None, niche)  # M-BOA chooses the second
    assert firsts[FirstGait.FASTEST] == int(session.niches[np.argmax(map_prior)])
    assert firsts[FirstGait.EXPECTED] == int(session.niches[robust])
    assert firsts[FirstGait.INFORMATIVE] == int(session.niches[robust])  # none near it


def test_a_trial_that_tells_hypotheses_apart_has_a_high_separation():
    """Two hypotheses that walk alike share the truth's posterior; two far apart do not."""
    apart = {0: straight_walk(0.3, 0.0), 1: straight_walk(0.0, 0.0)}
    alike = {0: straight_walk(0.3, 0.0), 1: straight_walk(0.3, 0.0)}
    labels = ('a', 'b')
    far = Diagnosis(labels, lambda niche, h: apart[h]).separation(7)
    near = Diagnosis(labels, lambda niche, h: alike[h]).separation(7)
    assert 0.9 < far <= 1.0 and 0.0 < near <= 0.5
    cannot = Diagnosis(labels, lambda niche, h: None if h else apart[0])  # b: not walked
    assert 0.0 < cannot.separation(7) <= 0.5  # b counts 0


def test_the_informative_first_gait_tells_the_hypotheses_apart_best_of_those_near_the_fastest(
    archive, walks
):
    """Of the fastest gaits expected within the slack, the one with the highest separation."""
    from hexapod_adapt.online.session import FIRST_CANDIDATES, FIRST_SLACK

    damages = [Damage.lifted([1]), Damage.lifted([2, 5])]
    _, _, map_prior = candidates(archive)
    bank = DamageBank('mujoco', tuple(damages), np.tile(map_prior, (2, 1)))
    plan = diagnosis_plan(
        archive, bank, walks=walks, blind=BlindRules(first=FirstGait.INFORMATIVE)
    )
    session = AdaptationSession(archive, PROFILES['default'], SessionStart(diagnosis=plan))
    first = session.ask()
    order = np.argsort(-map_prior, kind='stable')[:FIRST_CANDIDATES]
    near = [
        int(session.niches[i])
        for i in order
        if map_prior[i] >= (1 - FIRST_SLACK) * map_prior[order[0]]
    ]
    apart = {niche: plan.diagnosis.separation(niche) for niche in near}
    assert len(near) > 1 and first == max(apart, key=apart.get)
    assert all(0.0 <= value <= 1.0 for value in apart.values())


def _leg_one_plan(archive, walks, leg_sets: bool, tips: dict[int, int] | None = None):
    """Return a plan whose first two hypotheses (leg 1 lifted, its coxa dead) walk alike."""
    damages = (Damage.lifted([1]), Damage.of('unpowered_coxa', [1]), Damage.lifted([4]))
    alike = (damages[0], damages[0], damages[2])  # the first two: the very same walks
    diagnosis = Diagnosis(tuple(d.label for d in damages), walks.under(alike))
    bank = _bank(archive, list(damages))
    tips = tips or {}

    def screen_of(damage: Damage) -> TipScreen:
        tipping = tips.get(damages.index(damage))  # this damage's one gait that tips
        return TipScreen(lambda positions: np.where(positions == tipping, 1.0, 0.1), 0.5)

    plan = DiagnosisPlan(diagnosis, damages, bank.speeds, screen_of, leg_sets=leg_sets)
    return plan, damages


def test_a_plan_names_the_fewest_hypotheses_of_one_leg_set_that_hold_it():
    damages = (
        Damage.lifted([1]),
        Damage.of('unpowered_coxa', [1]),
        Damage.of('unpowered_tibia', [1]),
        Damage.lifted([4]),
    )
    plan = DiagnosisPlan(
        Diagnosis(tuple(d.label for d in damages), lambda niche, h: None),
        damages,
        np.zeros((4, 3)),
        lambda damage: None,
        leg_sets=True,
    )
    # p: the four hypotheses, then none of these
    assert plan.holding(np.array([0.92, 0.03, 0.0, 0.05, 0.0])) == (0,)
    assert plan.holding(np.array([0.41, 0.39, 0.15, 0.03, 0.02])) == (0, 1, 2)
    assert plan.holding(np.array([0.55, 0.05, 0.36, 0.0, 0.04])) == (0, 2)
    assert plan.holding(np.array([0.5, 0.2, 0.1, 0.15, 0.05])) is None  # the set holds 0.8
    assert replace(plan, leg_sets=False).holding(np.array([0.41, 0.39, 0.15, 0.03, 0.02])) is None
    assert plan.label_of((0, 1)) == 'leg 1 lifted or unpowered coxa'
    assert plan.label_of((1, 0, 2)) == 'leg 1 unpowered coxa, lifted or unpowered tibia'
    assert plan.label_of((3,)) == 'leg 4 lifted'


def test_a_session_named_a_leg_set_goes_on_as_its_weighed_re_scores_and_every_screen(
    archive, walks, trial_sim
):
    config = replace(PROFILES['default'], max_trials=3, min_speed=0.9)
    trial = recorded_trial(archive, Damage.lifted([1]), trial_sim)
    # without leg sets the two that walk alike share the posterior and nothing is named
    plan, damages = _leg_one_plan(archive, walks, leg_sets=False)
    session = AdaptationSession(archive, config, SessionStart(diagnosis=plan))
    niche = session.ask()
    session.tell(niche, trial(niche))
    p = session.posterior.probabilities
    assert p[0] == pytest.approx(p[1]) and p[0] + p[1] > 0.9, session.posterior.describe()
    assert session.named is None and session.result().named_legs == [()]
    # with them the leg set is named; each of its screens vetoes its own tipping gait
    _, _, map_prior = candidates(archive)
    order = [int(i) for i in np.argsort(-map_prior, kind='stable')]
    tips = {0: order[5], 1: order[6]}
    plan, damages = _leg_one_plan(archive, walks, leg_sets=True, tips=tips)
    session = AdaptationSession(archive, config, SessionStart(diagnosis=plan))
    niche = session.ask()
    session.tell(niche, trial(niche))
    assert session.named == (0, 1), session.posterior.describe()
    np.testing.assert_allclose(session.opt.prior, 0.5 * (plan.priors[0] + plan.priors[1]))
    assert session.screen.tips(order[5]) and session.screen.tips(order[6])
    assert not session.screen.tips(order[7])
    assert session.result().named == ['leg 1 lifted or unpowered coxa']
    assert session.result().named_legs == [(1,)]


def test_a_trial_without_a_record_leaves_the_diagnosis_alone(archive, walks):
    damages = [Damage.lifted([1]), Damage.lifted([4])]
    plan = diagnosis_plan(archive, _bank(archive, damages), walks=walks)
    session = AdaptationSession(archive, MboaConfig(max_trials=3), SessionStart(diagnosis=plan))
    niche = session.ask()
    session.tell(niche, TrialOutcome(0.1))
    assert session.posterior is None and session.named is None
    assert plan.diagnosis.trials == 0


def test_a_trial_recorded_to_mcap_and_read_back_names_its_damage(
    archive, walks, trial_sim, tmp_path
):
    """The odometry a trial publishes (sim_node's 10 Hz at real_time_factor 0), via MCAP."""
    from hexapod_adapt.online.trials import odometry_record
    from hexapod_adapt.ros.graph_port import odom_sample
    from hexapod_adapt.ros.run_recording import RunRecording
    from hexapod_util.recording import read_messages
    from nav_msgs.msg import Odometry

    true = Damage.lifted([2, 5])
    hypotheses = [Damage.lifted([2]), true, Damage.lifted([3, 6])]
    diagnosis = Diagnosis(tuple(d.label for d in hypotheses), walks.under(hypotheses))
    clock = iter(range(1, 10**6))
    rec = RunRecording(lambda topic: '/' + topic.lstrip('/'), lambda: next(clock), print)
    path = rec.start(tmp_path, {'odom': 'nav_msgs/msg/Odometry'})
    niche = fastest(archive, 1)[0]
    trace = trace_gait(archive.genotypes[niche], trial_sim, true, archive.trial_duration, every=24)
    t0_ns = 7 * 10**9  # the reset's stamp: the gait's phase 0
    for t, p, q in zip(trace.t, trace.position, trace.quaternion):
        msg = Odometry()
        stamp = t0_ns + int(round(t * 1e9))
        msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(stamp, 10**9)
        msg.pose.pose.position.x, msg.pose.pose.position.y = float(p[0]), float(p[1])
        o = msg.pose.pose.orientation
        o.x, o.y, o.z, o.w = (float(v) for v in q)
        rec.record('odom', msg)
    rec.stop()
    samples = [odom_sample(m) for topic, m, _ in read_messages(path) if topic == '/odom']
    assert len(samples) == len(trace.t) == 50
    end = t0_ns + int(round(archive.trial_duration * 1e9))
    record = odometry_record(samples, t0_ns, end, trace.gait.crab_angle, trace.gait.period)
    post = diagnosis.observe(niche, record)
    assert post.leader == 1, post.describe()


def test_records_from_the_graph_need_two_samples_and_keep_the_trial_window():
    from hexapod_adapt.online.trials import imu_record, odometry_record, OdomSample, TiltSample

    t0 = 10**9
    odom = [
        OdomSample(t0 + k * 10**8, 0.02 * k, 0.0, 0.0, 0.0, 0.0, attitude=(0.0, 0.01, 0.1))
        for k in range(-3, 60)
    ]
    record = odometry_record(odom, t0, t0 + 5 * 10**9, 0.0, 0.5)
    assert record.t[0] == pytest.approx(0.1) and record.t[-1] == pytest.approx(5.0)
    assert len(record.t) == 50  # the samples stamped before the reset are not the trial's
    assert odometry_record(odom[:4], t0, t0 + 5 * 10**9, 0.0, 0.5) is None  # one sample only
    tilts = [TiltSample(0.0, 100.0 + 0.05 * k, (0.0, 0.02, 1.0 + 0.01 * k)) for k in range(1, 101)]
    robot = imu_record(tilts, 100.0, (0.2, 0.0), 0.0, 0.5)
    assert robot.attitude[0, 2] == 0.0  # yaw in the frame the trial started in
    s = dict(zip(feature_names(False), signature(robot, False)))
    # the speed is along the heading at the window's start (1 s in: yawed 0.2 rad by then)
    assert s['speed'] == pytest.approx(0.2 * math.cos(0.2)) and s['yaw_rate'] == pytest.approx(0.2)
    assert imu_record(tilts[:1], 100.0, (0.2, 0.0), 0.0, 0.5) is None


def test_imu_readings_are_timed_by_their_stamps_not_by_when_they_arrived():
    from hexapod_adapt.online.trials import imu_record, reading_times, TiltSample

    rng = np.random.default_rng(3)
    taken = 0.05 * np.arange(1, 101)  # the bridge reads the IMU at 20 Hz
    delay = 0.002 + rng.exponential(0.01, taken.size)  # delivery: 2 ms at best, jittered
    wall = 1_780_000_000 * 10**9  # the bridge's clock (wall time) [ns]; the receiver's: monotonic
    readings = [
        TiltSample(0.0, 100.0 + t + d, (0.0, 0.0, 0.3 * t), wall + round(t * 1e9))
        for t, d in zip(taken, delay)
    ]
    times = reading_times(readings) - 100.0
    # the stamps' spacing exactly, off by the fastest delivery's delay only
    assert np.allclose(np.diff(times), 0.05, atol=1e-6)
    assert np.allclose(times - taken, delay.min(), atol=1e-6)
    record = imu_record(readings, 100.0, (0.2, 0.0), 0.0, 0.5)
    assert np.allclose(np.diff(record.t), 0.05, atol=1e-6)
    received = np.array([r.received for r in readings]) - 100.0
    assert np.abs(np.diff(received) - 0.05).max() > 0.01  # what receipt times would have given
    unstamped = [TiltSample(r.tilt, r.received, r.attitude) for r in readings]
    assert np.array_equal(reading_times(unstamped), received + 100.0)
    backwards = readings[:50] + [
        TiltSample(r.tilt, r.received, r.attitude, r.stamp_ns - 10**9) for r in readings[50:]
    ]  # a clock stepped back mid-trial: the stamps cannot time it
    assert np.array_equal(reading_times(backwards), received + 100.0)


def test_a_map_with_no_ceilings_cached_is_diagnosed_and_re_scores_the_damage_it_names(
    archive, trial_sim, tmp_path
):
    # a map of the user's own, none of its bank's re-scores made: the hypotheses are weighed all
    # the same (walked when needed); the one named is re-scored then and kept
    from hexapod_adapt.online.session import informed_start
    from hexapod_adapt.online.streaming_prior import StreamingPriors

    keep = fastest(archive, 24)
    small = archive.only(keep)
    damages = [Damage.lifted([1]), Damage.lifted([4]), Damage.lifted([3, 6])]
    priors = StreamingPriors(None, [tmp_path], 2, print, bank=damages)  # 2: adapt_node's workers
    start = informed_start(small, None, 'blind', priors, diagnose=True)
    plan = start.diagnosis
    assert plan is not None and plan.damages == tuple(damages)
    assert np.isnan(plan.priors).all() and '(3 not cached' in start.note
    # told to weigh only what is cached: nothing to weigh, no diagnosis
    cached_only = StreamingPriors(
        None, [tmp_path], 1, print, bank=damages, rescore_when_named=False
    )
    assert informed_start(small, None, 'blind', cached_only, diagnose=True).diagnosis is None
    # the first gait: with no re-score to go by, the map's fastest
    config = replace(PROFILES['default'], max_trials=4, min_speed=0.9)
    session = AdaptationSession(small, config, start)
    niche = session.ask()
    assert niche == keep[0]
    session.tell(niche, recorded_trial(small, damages[1], trial_sim)(niche))
    assert session.named == (1,), session.posterior.describe()
    # named: its re-score is made when the next gait is asked for, once the trial is said
    assert session.rescoring == damages[1].label and np.isnan(plan.priors).all()
    assert session.result().rescore_s == 0.0
    session.ask()
    # made (the map's 24 gaits walked under it), the others still to make
    assert np.isfinite(plan.priors[1]).all() and np.isnan(plan.priors[[0, 2]]).all()
    assert session.rescoring is None and session.result().rescore_s > 0
    # walked in the node's 2 processes, to one process's speeds
    from hexapod_adapt.mapping.simulation import engine_of_map
    from hexapod_adapt.online.ceiling import quick_rescore

    one = quick_rescore(small, damages[1], engine_of_map(small))
    np.testing.assert_array_equal(plan.priors[1], one)
    assert session.rules.offset_std == 0.0 and session.rules.stop_gain is None  # a prior's
