# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The blind run's safety model (hexapod_adapt.online.safety): each gait's risk of tipping.

First on walks whose tilts the test sets (the model's arithmetic), then in a session over the
default map whose hypotheses are walked on MuJoCo: no gait above the limit is ever offered.
"""

from __future__ import annotations

from dataclasses import replace
import math

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
from hexapod_adapt.online.adaptation import DEFAULT_TIP_GUARD, recorded_trial
from hexapod_adapt.online.bank import DamageBank
from hexapod_adapt.online.diagnosis import HypothesisWalks, TrialRecord
from hexapod_adapt.online.mboa import PROFILES
from hexapod_adapt.online.safety import record_tilt, SafetyModel
from hexapod_adapt.online.session import AdaptationSession, diagnosis_plan, SessionStart
from hexapod_sim import create_simulator, SimConfig
from hexapod_sim.damage import Damage
import numpy as np
import pytest

GUARD = math.radians(30.0)


def tilted(peak: float, n: int = 50) -> TrialRecord:
    """Return a record whose body rolls up to ``peak`` [rad] and back."""
    t = np.linspace(0.1, 5.0, n)
    roll = peak * np.sin(np.linspace(0.0, math.pi, n))
    attitude = np.column_stack([roll, np.zeros(n), np.zeros(n)])
    return TrialRecord(t, np.column_stack([0.05 * t, 0 * t]), attitude, 0.0, 1.0)


def model(tilts: np.ndarray, weights=None, **kwargs) -> SafetyModel:
    """Return a safety model over gaits on a line (x = 2 gait / n) whose walks tilt ``tilts``."""
    tilts = np.asarray(tilts, dtype=float)  # (gaits, hypotheses + 1)
    n, h = tilts.shape[0], tilts.shape[1] - 1
    descriptors = np.zeros((n, 6))
    descriptors[:, 0] = 2.0 * np.arange(n) / n
    if weights is None:
        weights = np.full(h + 1, 1.0 / (h + 1))
    return SafetyModel(
        np.arange(n),
        descriptors,
        lambda niche, k: tilted(tilts[niche, k]),
        h,
        GUARD,
        np.asarray(weights, dtype=float),
        **kwargs,
    )


def test_record_tilt_is_the_largest_roll_or_pitch_and_an_unwalkable_gait_may_tip():
    assert record_tilt(tilted(0.3)) == pytest.approx(0.3, abs=1e-3)
    assert record_tilt(None) == math.pi


def test_the_risk_is_the_belief_in_the_hypotheses_under_which_a_gait_tips():
    # gait 0 tips under hypothesis 0 only; gait 1 under none; gait 2 under every one
    tilts = [[1.2, 0.1, 0.1], [0.1, 0.1, 0.1], [1.0, 1.0, 1.0]]
    m = model(tilts, shift=0.0, offset=0.0)  # the walks alone: no trial may move them
    assert m.risk(1) < 0.01 and m.risk(2) > 0.99
    assert m.risk(0) == pytest.approx(1 / 3, abs=0.01)
    assert m.tips(0) and m.limit < 1 / 3  # above the default limit of 0.25: vetoed
    m.weigh(np.array([0.01, 0.98, 0.01]))  # the trials say hypothesis 1
    assert m.risk(0) < 0.02 and not m.tips(0)
    m.weigh(np.array([0.9, 0.05, 0.05]))
    assert m.tips(0) and m.risks[0] > 0.85
    assert m.tilts[0] == pytest.approx(0.9 * 1.2 + 0.1 * 0.1, abs=0.01)


def test_a_hypothesis_believed_too_little_to_matter_is_not_walked_until_believed_again():
    tilts = np.array([[1.2, 0.1, 0.1], [0.1, 0.1, 0.1]])
    walked: list[tuple[int, int]] = []
    m = model(tilts, weights=[1e-12, 0.5, 0.5 - 1e-12], shift=0.0, offset=0.0)
    m.walk = lambda niche, k: walked.append((niche, k)) or tilted(tilts[niche, k])
    assert not m.tips(0) and m.risk(0) < 0.01  # its tipping under hypothesis 0 is not believed
    assert sorted(walked) == [(0, 1), (0, 2)]
    m.weigh(np.array([0.9, 0.05, 0.05]))  # the trials say hypothesis 0: it is walked now
    assert m.tips(0) and (0, 0) in walked and len(walked) == len(set(walked)) == 3


def test_a_trial_that_tilted_more_than_predicted_raises_its_neighbours_risk_most():
    n = 20
    tilts = np.full((n, 2), 0.2)  # every walk predicts 0.2 rad
    m = model(tilts, weights=[0.5, 0.5], offset=0.0)  # the local part alone
    before = [m.risk(i) for i in range(n)]
    assert max(before) < 0.05  # 0.3 rad under the guard, the trials' shift not yet known
    m.observe(10, 0.9, tipped=True)  # it tipped: the guard was passed
    after = [m.risk(i) for i in range(n)]
    assert after[10] > 0.5 and after[11] > 0.3  # near (0.1 away): raised
    assert after[0] == pytest.approx(before[0], abs=0.01)  # far (1.0 away): as before
    # a trial that tilted less than predicted lowers the risk about it
    m2 = model(np.full((n, 2), 0.45), weights=[0.5, 0.5])
    high = m2.risk(10)
    m2.observe(10, 0.1, tipped=False)
    assert m2.risk(10) < high
    # with the constant part, a tip raises every gait's risk: a damage the walks lack
    m3 = model(tilts, weights=[0.5, 0.5], offset=0.15)
    far = m3.risk(0)
    m3.observe(10, 0.9, tipped=True)
    assert m3.risk(0) > far + 0.05 and m3.risk(11) > m3.risk(0)


def test_a_tilt_not_measured_teaches_nothing_unless_the_trial_tipped():
    m = model(np.full((5, 2), 0.2), weights=[0.5, 0.5])
    unknown = m.risk(2)
    m.observe(2, math.nan, tipped=False)
    assert m.risk(2) == unknown
    m.observe(2, math.nan, tipped=True)
    assert m.risk(2) > 0.3


def test_bad_settings_are_refused():
    with pytest.raises(ValueError, match='weights'):
        model(np.full((3, 3), 0.1), weights=[0.5, 0.5])
    with pytest.raises(ValueError, match='risk limit'):
        model(np.full((3, 2), 0.1), limit=1.5)
    with pytest.raises(ValueError, match='spread'):
        model(np.full((3, 2), 0.1), spread=0.0)
    with pytest.raises(ValueError, match='offset'):
        model(np.full((3, 2), 0.1), offset=-0.1)


@pytest.fixture(scope='module')
def archive():
    return load_archive(shipped_map(DEFAULT_MAP))


def test_a_blind_session_never_offers_a_gait_above_the_limit(archive):
    """
    Over the default map, its hypotheses walked on MuJoCo: each gait asked for is under the limit.

    The trials (legs 2 and 5 lifted, MuJoCo at its converged step) tell the session their tilt
    and record; every gait it offers is one the safety model, asked then, kept under its limit,
    and every gait it skipped was above it.
    """
    damages = [Damage.lifted([2]), Damage.lifted([5]), Damage.lifted([2, 5]), Damage.lifted([1])]
    speeds = np.array([archive.speeds()[archive.elite_indices()] * 0.5 for _ in damages])
    bank = DamageBank('mujoco', tuple(damages), speeds)
    plan = diagnosis_plan(archive, bank, DEFAULT_TIP_GUARD, walks=HypothesisWalks(archive))
    assert plan.safety is not None
    safety = plan.safety
    config = replace(PROFILES['default'], max_trials=4, min_speed=0.9)  # never done early
    session = AdaptationSession(archive, config, SessionStart(diagnosis=plan))
    index_of = {int(n): i for i, n in enumerate(session.niches)}
    with create_simulator(SimConfig.converged('mujoco')) as sim:
        trial = recorded_trial(archive, Damage.lifted([2, 5]), sim, tip_guard=DEFAULT_TIP_GUARD)
        while (niche := session.ask()) is not None:
            assert safety.risks[index_of[niche]] <= safety.limit
            session.tell(niche, trial(niche))
            if session.named is not None:
                break
    for veto in session.vetoes:
        assert veto.risk is not None and veto.risk > safety.limit
    assert session.result().niches  # it walked


def test_a_named_damages_screen_vetoes_gaits_within_its_margin_of_the_guard(archive):
    """With a margin, a gait whose simulated tilt lies just under the guard is vetoed too."""
    damage = Damage.lifted([2, 5])
    bank = DamageBank('mujoco', (damage,), archive.speeds()[archive.elite_indices()][None])
    margin = math.radians(25.0)  # most gaits tilt more than 5 degrees: the first few do
    walks = HypothesisWalks(archive)
    plain = diagnosis_plan(archive, bank, DEFAULT_TIP_GUARD, walks=walks)
    wary = diagnosis_plan(archive, bank, DEFAULT_TIP_GUARD, walks=walks, screen_margin=margin)
    screen, wary_screen = plain.screen_of(damage), wary.screen_of(damage)
    assert wary_screen.guard == pytest.approx(DEFAULT_TIP_GUARD - margin)
    near = None
    for position in np.argsort(-bank.speeds[0], kind='stable')[:300]:
        screen.tips(int(position))
        if DEFAULT_TIP_GUARD - margin < screen.tilts[int(position)] <= DEFAULT_TIP_GUARD:
            near = int(position)
            break
    assert near is not None, 'no gait of the 300 fastest tilts within the margin of the guard'
    assert not screen.tips(near) and wary_screen.tips(near)
    for bad in (-0.1, DEFAULT_TIP_GUARD, math.nan):
        with pytest.raises(ValueError, match='screen_margin'):
            diagnosis_plan(archive, bank, DEFAULT_TIP_GUARD, walks=walks, screen_margin=bad)


def test_with_kin_tilts_a_lifted_hypothesis_tilts_as_the_worst_kind_that_unloads_its_legs(archive):
    """
    The lifted bank stands in for five kinds; kin tilts make its safety model weigh their worst.

    Gait 13896 (the default map's fastest) with legs 1+4 lifted stays under the 30 deg guard on
    MuJoCo; with their tibias unpowered it tips (measured: 19 and 42 deg;
    studies/diagnosis/README.md): only the kin model says it may.
    """
    from hexapod_adapt.online.safety import record_tilt
    from hexapod_adapt.online.session import UNLOADING_KINDS

    legs = [1, 4]
    bank = DamageBank(
        'mujoco', (Damage.lifted(legs),), archive.speeds()[archive.elite_indices()][None]
    )
    walks = HypothesisWalks(archive)
    plain = diagnosis_plan(archive, bank, DEFAULT_TIP_GUARD, walks=walks, kin_tilts=None).safety
    kin = diagnosis_plan(archive, bank, DEFAULT_TIP_GUARD, walks=walks, kin_tilts=0.0).safety
    index = int(np.flatnonzero(plain.niches == 13896)[0])
    tilts = {kind: record_tilt(walks(13896, Damage.of(kind, legs))) for kind in UNLOADING_KINDS}
    assert tilts['lifted'] < DEFAULT_TIP_GUARD < tilts['unpowered_tibia'], tilts
    assert plain.simulated(index)[0] == pytest.approx(tilts['lifted'])
    assert kin.simulated(index)[0] == pytest.approx(max(tilts.values()))
    assert plain.simulated(index)[1] == kin.simulated(index)[1]  # intact: none of these
    assert kin.risk(index) > plain.risk(index)
    # gated by belief: a hypothesis believed less than the kin weight tilts as itself
    gated = diagnosis_plan(archive, bank, DEFAULT_TIP_GUARD, walks=walks, kin_tilts=0.9).safety
    assert gated.weights[0] < 0.9
    assert gated.simulated(index)[0] == pytest.approx(tilts['lifted'])
    gated.weigh(np.array([0.95, 0.05]))
    assert gated.simulated(index)[0] == pytest.approx(max(tilts.values()))
    # the wider bank names each kind: its hypotheses tilt as themselves
    every = DamageBank('mujoco', (Damage.of('locked', legs),), bank.speeds)
    locked = diagnosis_plan(archive, every, DEFAULT_TIP_GUARD, walks=walks, kin_tilts=0.0)
    assert locked.safety.simulated(index)[0] == pytest.approx(
        record_tilt(walks(13896, Damage.of('locked', legs)))
    )


def test_a_stop_ends_a_blind_run_between_two_hypothesis_walks_and_keeps_the_trial(archive):
    """
    A cancel asked while a blind run walks its hypotheses ends the run there, as 'cancelled'.

    The safety model's and the diagnosis's walks are many (about 0.1 s each on MuJoCo, more on
    PyBullet).
    """
    from hexapod_adapt.online.diagnosis import WalksStopped

    damages = [Damage.lifted([2]), Damage.lifted([5]), Damage.lifted([2, 5])]
    speeds = np.array([archive.speeds()[archive.elite_indices()] * 0.5 for _ in damages])
    bank = DamageBank('mujoco', tuple(damages), speeds)
    config = replace(PROFILES['default'], max_trials=4, min_speed=0.9)
    walks = HypothesisWalks(archive)
    with walks.stoppable(lambda: True):  # the walks themselves: a new one is not made
        with pytest.raises(WalksStopped, match='gait 13896 under leg 2 lifted'):
            walks(13896, damages[0])
    assert walks.walked == 0
    walks(13896, damages[0])
    with walks.stoppable(lambda: True):
        assert walks(13896, damages[0]) is not None  # one made already is given

    def plan(**kw):
        return diagnosis_plan(archive, bank, DEFAULT_TIP_GUARD, **kw)

    # in ask: the safety model's kin walks of the first gait
    start = SessionStart(diagnosis=plan(walks=walks, kin_tilts=0.0))
    session = AdaptationSession(archive, config, start)
    asked: list[int] = []
    assert session.ask(lambda: len(asked) > 3 or asked.append(1)) is None
    assert len(asked) == 4 and session.result().message == 'cancelled' and session.ask() is None
    # in tell: the diagnosis's walks of the trial's gait (no safety model walked it); it is kept
    start = SessionStart(diagnosis=plan(walks=HypothesisWalks(archive), safety=None))
    session = AdaptationSession(archive, config, start)
    niche = session.ask()
    with create_simulator(SimConfig.converged('mujoco')) as sim:
        outcome = recorded_trial(archive, damages[2], sim, tip_guard=DEFAULT_TIP_GUARD)(niche)
    told = session.tell(niche, outcome, lambda: True)
    assert told is not None and session.finished and session.result().message == 'cancelled'
    result = session.result()
    assert result.niches == [niche] and len(result.named) == 1 and session.ask() is None


def test_hypotheses_walked_in_two_processes_are_those_walked_in_one(archive):
    """
    ``workers`` walks a gait's hypotheses at once, in a pool: the same walks, the same run.

    A blind session over the same bank, its walks in one process and in two: the same first
    gait, the same walks to the bit, the same posterior after one trial; a stop during a batch
    keeps what was walked before it and makes nothing after.
    """
    from hexapod_adapt.online.diagnosis import WalksStopped

    damages = [Damage.lifted([2]), Damage.lifted([5]), Damage.lifted([2, 5])]
    speeds = np.array([archive.speeds()[archive.elite_indices()] * 0.5 for _ in damages])
    bank = DamageBank('mujoco', tuple(damages), speeds)
    config = replace(PROFILES['default'], max_trials=4, min_speed=0.9)
    with create_simulator(SimConfig.converged('mujoco')) as sim:
        trial = recorded_trial(archive, damages[2], sim, tip_guard=DEFAULT_TIP_GUARD)
        runs = {}
        for workers in (1, 2):
            walks = HypothesisWalks(archive, workers=workers)
            plan = diagnosis_plan(archive, bank, DEFAULT_TIP_GUARD, walks=walks)
            session = AdaptationSession(archive, config, SessionStart(diagnosis=plan))
            niche = session.ask()
            session.tell(niche, trial(niche))
            runs[workers] = (niche, walks, plan.diagnosis.posterior().probabilities)
    (niche, one, p_one), (niche_two, two, p_two) = runs[1], runs[2]
    assert niche == niche_two and one.walked == two.walked > len(damages) + 1
    for key, record in one._walks.items():
        assert record is not None and two._walks[key] is not None
        np.testing.assert_array_equal(record.attitude, two._walks[key].attitude)
        np.testing.assert_array_equal(record.position, two._walks[key].position)
    np.testing.assert_array_equal(p_one, p_two)

    fresh = HypothesisWalks(archive, workers=2)
    with fresh.stoppable(lambda: fresh.walked >= 1):  # a stop once the first walk is in
        with pytest.raises(WalksStopped, match='3 walks were not all made: stopped'):
            fresh.prefetch([(niche, d) for d in damages])
    assert fresh.walked == 1  # the walk made before the stop is kept, and no other
    for key in fresh._walks:
        np.testing.assert_array_equal(fresh._walks[key].attitude, one._walks[key].attitude)
    with pytest.raises(ValueError, match='workers must be a positive integer'):
        HypothesisWalks(archive, workers=0)
