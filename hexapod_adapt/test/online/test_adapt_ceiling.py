# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The map's ceiling under a damage: against a brute-force loop, cached, never trusted blindly."""

from __future__ import annotations

from dataclasses import replace
import json
import math
import shutil

from hexapod_adapt.mapping.archive import Archive, load_archive
from hexapod_adapt.mapping.maps import DEMO_MAP, shipped_map
from hexapod_adapt.mapping.simulation import engine_of_map, map_physics, UNRECORDED_MAP_ENGINE
from hexapod_adapt.online.ceiling import (
    cache_path,
    cached_ceiling,
    cached_names,
    ceiling,
    ceiling_key,
    compute_ceiling,
    holds_ceiling,
    pack_ceilings,
    WalkingFile,
)
from hexapod_sim import create_simulator, evaluate_gait, SimConfig
from hexapod_sim.damage import Damage
from hypothesis import given, HealthCheck, settings
from hypothesis import strategies as st
import numpy as np
import pytest


@pytest.fixture(scope='module')
def small_map() -> Archive:
    demo = load_archive(shipped_map(DEMO_MAP))
    return demo.only(demo.elite_indices()[:12])


def test_the_ceiling_is_every_gait_evaluated_with_the_damage(small_map):
    """On an engine that did not make the map (MuJoCo, for a PyBullet map): its converged step."""
    legs = (1, 4)
    with create_simulator(map_physics(small_map, 'mujoco')) as sim:
        brute = [
            evaluate_gait(
                small_map.genotypes[n], sim, collisions_fatal=False, failed_legs=legs
            ).speed
            for n in small_map.elite_indices()
        ]
    result = compute_ceiling(small_map, legs, 'mujoco', workers=2, chunk=5)
    assert result.niches.tolist() == small_map.elite_indices().tolist()
    np.testing.assert_array_equal(result.speeds, brute)
    assert result.best_speed == max(brute) and result.beating(max(brute)) == 0
    assert result.best_niche == small_map.elite_indices()[int(np.argmax(brute))]
    assert result.beating(-1.0) == len(brute)


def test_a_map_is_rescored_in_the_physics_that_made_it(small_map):
    """A map made at 4 MuJoCo steps per row (generate_map --substeps 4) is re-scored at 4."""
    from hexapod_adapt.mapping.simulation import map_sim_config, map_substeps, trial_substeps

    def made_at(substeps):
        fingerprint = map_sim_config('mujoco', substeps).fingerprint()
        a = small_map
        return Archive(
            a.centroids,
            a.fitness,
            a.descriptors,
            a.genotypes,
            {**a.metadata, 'simulator': fingerprint},
        )

    one, four = made_at(1), made_at(4)
    assert map_substeps(four, 'mujoco') == 4 and map_substeps(four, 'pybullet') == 0
    assert map_substeps(one, 'mujoco') == 1  # its fingerprint leaves 1 out, as before substeps
    assert map_substeps(small_map, 'mujoco') == 0  # a PyBullet map: MuJoCo's default
    # measured on another engine at its converged step; a map that does not say is PyBullet's
    assert trial_substeps(four, 'mujoco') == 4
    assert (
        trial_substeps(four, 'pybullet')
        == SimConfig.converged('pybullet').engine_settings().substeps
    )
    assert (
        trial_substeps(small_map, 'mujoco')
        == SimConfig.converged('mujoco').engine_settings().substeps
    )
    assert trial_substeps(small_map, 'pybullet') == 0  # its own engine, at its default
    unsaid = Archive(four.centroids, four.fitness, four.descriptors, four.genotypes, {})
    assert engine_of_map(unsaid) == UNRECORDED_MAP_ENGINE == 'pybullet'
    assert trial_substeps(unsaid, 'pybullet') == 0
    assert (
        trial_substeps(unsaid, 'mujoco')
        == SimConfig.converged('mujoco').engine_settings().substeps
    )
    niches = four.elite_indices()[:3]
    with create_simulator(map_sim_config('mujoco', 4)) as sim:
        at_four = [
            evaluate_gait(four.genotypes[n], sim, collisions_fatal=False, failed_legs=[2]).speed
            for n in niches
        ]
    result = compute_ceiling(four, [2], 'mujoco', niches=niches)
    np.testing.assert_array_equal(result.speeds, at_four)
    at_one = compute_ceiling(one, [2], 'mujoco', niches=niches).speeds
    assert not np.array_equal(at_one, at_four)  # the steps made a difference to these gaits
    assert ceiling_key(four, [2], 'mujoco') != ceiling_key(one, [2], 'mujoco')


def test_a_cached_ceiling_is_reused_and_a_damaged_one_recomputed(small_map, tmp_path):
    first = ceiling(small_map, [2], 'mujoco', cache_dir=tmp_path)
    path = cache_path(tmp_path, ceiling_key(small_map, [2], 'mujoco'))
    assert path.is_file()
    stamp = path.stat().st_mtime_ns
    again = ceiling(small_map, [2], 'mujoco', cache_dir=tmp_path)
    np.testing.assert_array_equal(first.speeds, again.speeds)
    assert path.stat().st_mtime_ns == stamp  # read, not written again
    path.write_bytes(path.read_bytes()[:100])  # damaged on disk
    fixed = ceiling(small_map, [2], 'mujoco', cache_dir=tmp_path)
    np.testing.assert_array_equal(first.speeds, fixed.speeds)
    other = ceiling_key(small_map, [3], 'mujoco')
    assert cache_path(tmp_path, other) != path  # another damage, another file


def test_a_stopped_ceiling_takes_up_the_chunks_it_walked(small_map, tmp_path):
    """A session's end stops a case mid-way (17-30 min each on the default map): not lost."""
    legs = (2,)
    key = ceiling_key(small_map, legs, 'mujoco')
    walking = WalkingFile.beside(cache_path(tmp_path, key), key)
    walking = replace(walking, every=0.0)  # keep after every chunk
    full = compute_ceiling(small_map, legs, 'mujoco', chunk=3)

    def stop_at_the_third_chunk(done: int, total: int) -> None:
        if done >= 9:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        compute_ceiling(
            small_map, legs, 'mujoco', chunk=3, progress=stop_at_the_third_chunk, walking=walking
        )
    assert walking.path.is_file() and walking.path.name.startswith('walking_ceiling_')
    seen: list[int] = []
    again = compute_ceiling(
        small_map, legs, 'mujoco', chunk=3, progress=lambda d, t: seen.append(d), walking=walking
    )
    assert seen[0] == 9  # the two chunks kept were not walked again
    np.testing.assert_array_equal(again.speeds, full.speeds)
    assert len(walking.taken_up(3, 12)) == 4 and walking.taken_up(4, 12) == []  # chunks of 3
    # another damage's key, another chunk size, a damaged file: all walked again
    for other in (
        replace(walking, key=ceiling_key(small_map, (3,), 'mujoco')),
        replace(walking, path=tmp_path / 'damaged.npz'),
    ):
        other.path.write_bytes(
            walking.path.read_bytes()[:60]
            if 'damaged' in str(other.path)
            else walking.path.read_bytes()
        )
        seen.clear()
        compute_ceiling(
            small_map, legs, 'mujoco', chunk=3, progress=lambda d, t: seen.append(d), walking=other
        )
        assert seen[0] == 3, other.path
    # ceiling() caches the result and drops the walking file
    ceiling(small_map, legs, 'mujoco', cache_dir=tmp_path)
    assert cache_path(tmp_path, key).is_file() and not walking.path.exists()


@settings(
    max_examples=80, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    data=st.binary(max_size=400),
    cut=st.integers(0, 3000),
    chunk=st.sampled_from([1, 3, 64]),
    walked=st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=12),
)
def test_any_walking_file_is_taken_up_whole_or_not_at_all(tmp_path, data, cut, chunk, walked):
    key = {'engine': 'mujoco', 'failed_legs': [2]}
    walking = WalkingFile(tmp_path / 'walking.npz', key)
    parts = [np.array(walked[i : i + chunk]) for i in range(0, len(walked), chunk)]  # noqa: E203
    walking.keep(chunk, parts)
    kept = walking.path.read_bytes()
    walking.path.write_bytes(kept[:cut] + data)  # a real file cut short, and garbage
    taken = walking.taken_up(chunk, 12)
    assert isinstance(taken, list)
    if taken:  # only what was kept, in whole chunks of finite speeds
        assert all(np.isfinite(part).all() and len(part) <= chunk for part in taken)
        assert np.concatenate(taken).tolist() == walked[: sum(len(t) for t in taken)]


@pytest.mark.slow
def test_packed_ceilings_read_as_the_loose_files_did(small_map, tmp_path):
    from hexapod_sim.damage import Damage

    cases = [Damage.lifted([2]), Damage.lifted([3]), Damage.lifted([5]), Damage.of('locked', [2])]
    loose = {c: ceiling(small_map, c, 'mujoco', cache_dir=tmp_path) for c in cases}
    damaged = tmp_path / 'ceiling_mujoco_legs4_0000000000000000.npz'
    damaged.write_bytes(b'not a ceiling')
    packs = pack_ceilings(tmp_path, per_pack=2)
    assert sorted(p.name for p in packs) == [
        'ceilings_mujoco_lifted_0.zip',
        'ceilings_mujoco_lifted_1.zip',
        'ceilings_mujoco_locked_0.zip',
    ]
    assert [p.name for p in tmp_path.glob('*.npz')] == [damaged.name]  # left loose
    for case, before in loose.items():
        key = ceiling_key(small_map, case, 'mujoco')
        assert holds_ceiling(tmp_path, key) and not cache_path(tmp_path, key).is_file()
        after = cached_ceiling(small_map, case, 'mujoco', [tmp_path])
        assert after is not None and after.damage == case
        np.testing.assert_array_equal(after.speeds, before.speeds)
        np.testing.assert_array_equal(after.niches, before.niches)
    # packing again packs nothing new and keeps the packs' names
    assert pack_ceilings(tmp_path, per_pack=2) == []
    # a damaged pack holds nothing: its cases are computed again, loose, and read from there
    pack = tmp_path / 'ceilings_mujoco_locked_0.zip'
    pack.write_bytes(pack.read_bytes()[:200])
    assert cached_ceiling(small_map, cases[3], 'mujoco', [tmp_path]) is None
    assert not holds_ceiling(tmp_path, ceiling_key(small_map, cases[3], 'mujoco'))
    again = ceiling(small_map, cases[3], 'mujoco', cache_dir=tmp_path)
    np.testing.assert_array_equal(again.speeds, loose[cases[3]].speeds)
    assert cache_path(tmp_path, ceiling_key(small_map, cases[3], 'mujoco')).is_file()
    # a new loose case packs beside the old packs, under a free name
    packed = pack_ceilings(tmp_path, per_pack=2)
    assert [p.name for p in packed] == ['ceilings_mujoco_locked_1.zip']
    with pytest.raises(ValueError, match='per_pack'):
        pack_ceilings(tmp_path, per_pack=0)


def test_the_cli_packs_what_is_cached_and_computes_nothing(small_map, tmp_path, capsys):
    from hexapod_adapt.online.ceilings_cli import main

    archive = tmp_path / 'map.npz'
    small_map.save(archive)
    cache = tmp_path / 'cache'
    made = ceiling(small_map, [2], 'mujoco', cache_dir=cache)
    args = ['--archive', str(archive), '--engine', 'mujoco', '--cache-dir', str(cache)]
    assert main([*args, '--scenarios', 'S1', '--damage-kind', 'lifted', '--pack']) == 0
    assert 'into 1 packs' in capsys.readouterr().out
    assert [p.name for p in cache.iterdir()] == ['ceilings_mujoco_lifted_0.zip']
    # the five S1 cases not cached were not computed: they are still missing
    assert main([*args, '--scenarios', 'S1', '--damage-kind', 'lifted', '--missing']) == 0
    assert capsys.readouterr().out.strip() == '5'
    # the table: per kind, the cases held (in full) and each scenario's range; another damage
    # in a row of its own, last
    asked = ['--scenarios', 'S1', '--damage-kind', 'locked', 'lifted', '--damage', '3:locked']
    assert main([*args, *asked, '--summary']) == 0
    rows = capsys.readouterr().out.strip().splitlines()
    assert rows[0] == '| kind | cases cached (in full) | S1 | other |'
    speed = f'{made.best_speed:.3f}'
    assert rows[2:] == [
        '| locked | 0 of 6 (0) |  |  |',
        f'| lifted | 1 of 6 (1) | {speed}-{speed} |  |',
        '| other | 0 of 1 (0) |  |  |',
    ]
    assert [p.name for p in cache.iterdir()] == ['ceilings_mujoco_lifted_0.zip']  # none made
    # written into a file between its marks, the rest of the file kept
    readme = tmp_path / 'README.md'
    readme.write_text('# Ceilings\n<!-- ceilings-summary: start -->\nold\n'
                      '<!-- ceilings-summary: end -->\nmore\n')  # fmt: skip
    assert main([*args, *asked, '--summary', str(readme)]) == 0
    assert readme.read_text().splitlines() == [
        '# Ceilings', '<!-- ceilings-summary: start -->', *rows,
        '<!-- ceilings-summary: end -->', 'more',
    ]  # fmt: skip
    # a file without the marks is refused, unchanged
    readme.write_text('no marks\n')
    assert main([*args, *asked, '--summary', str(readme)]) == 1
    assert 'no <!-- ceilings-summary: start --> line' in capsys.readouterr().err
    assert readme.read_text() == 'no marks\n'


@pytest.mark.slow
def test_the_cli_lists_the_cases_a_cache_holds_loose_or_packed(small_map, tmp_path, capsys):
    from hexapod_adapt.online.ceilings_cli import main

    first = cache_path(tmp_path, ceiling_key(small_map, [2], 'mujoco'))
    ceiling(small_map, [2], 'mujoco', cache_dir=tmp_path)
    pack_ceilings(tmp_path)
    second = cache_path(tmp_path, ceiling_key(small_map, [3], 'mujoco'))
    ceiling(small_map, [3], 'mujoco', cache_dir=tmp_path)  # loose beside the pack
    (tmp_path / 'ceilings_mujoco_lifted_7.zip').write_bytes(b'not a zip')  # holds nothing
    assert cached_names(tmp_path) == {first.name, second.name}
    assert main(['--cache-dir', str(tmp_path), '--list']) == 0
    assert capsys.readouterr().out.split() == sorted([first.name, second.name])
    assert cached_names(tmp_path / 'none') == set()


@pytest.mark.parametrize(
    'two', [('--missing', '--pack'), ('--list', '--pack'), ('--summary', '--missing')]
)
def test_the_cli_refuses_two_things_that_compute_nothing(capsys, two):
    from hexapod_adapt.online.ceilings_cli import main

    with pytest.raises(SystemExit) as exit_:
        main(['--cache-dir', '/tmp', *two])
    assert exit_.value.code == 2
    assert 'give one of them' in capsys.readouterr().err


def test_a_ceiling_under_another_damage_type_is_keyed_and_cached_by_it(small_map, tmp_path):
    from hexapod_sim.damage import Damage

    lifted = ceiling_key(small_map, Damage.lifted([2]), 'mujoco')
    assert lifted == ceiling_key(small_map, [2], 'mujoco')  # the shipped cache stays valid
    assert 'damage' not in lifted
    locked = Damage.of('locked', [2])
    key = ceiling_key(small_map, locked, 'mujoco')
    assert key['damage'] == [[2, 'locked', 1.0]]
    assert cache_path(tmp_path, key) != cache_path(tmp_path, lifted)
    assert '_2locked_' in cache_path(tmp_path, key).name
    first = ceiling(small_map, locked, 'mujoco', cache_dir=tmp_path)
    assert first.damage == locked and first.failed_legs == (2,)
    again = ceiling(small_map, locked, 'mujoco', cache_dir=tmp_path)
    assert again.damage == locked  # read back from the file's key
    np.testing.assert_array_equal(first.speeds, again.speeds)
    with create_simulator(map_physics(small_map, 'mujoco')) as sim:
        n = int(small_map.elite_indices()[0])
        direct = evaluate_gait(
            small_map.genotypes[n], sim, collisions_fatal=False, failed_legs=locked
        )
    assert first.speeds[0] == direct.speed


def test_a_replayed_run_is_the_simulated_run(small_map):
    """A lookup in the ceiling answers each trial exactly as the simulator does."""
    from hexapod_adapt.online.adaptation import simulated_trial
    from hexapod_adapt.online.mboa import MboaConfig
    from hexapod_adapt.online.replay import lookup_trial, replay, score, summarise
    from hexapod_adapt.online.session import adapt
    from hexapod_sim.damage import Damage

    damage = Damage.of('weak', [1, 4])
    c = compute_ceiling(small_map, damage, 'mujoco')
    config = MboaConfig(max_trials=12, alpha=1.0)
    with create_simulator(map_physics(small_map, 'mujoco')) as sim:
        simulated = adapt(small_map, simulated_trial(small_map, damage, sim), config)
    replayed = replay(small_map, c, config)
    assert replayed.niches == simulated.niches
    assert [t.measured for t in replayed.trials] == [t.measured for t in simulated.trials]
    trial = lookup_trial(c)
    assert trial(int(c.niches[c.best_index])) == c.best_speed
    runs = score(small_map, [c], {damage: 10.0}, config)  # a floor no gait reaches
    floored = replay(small_map, c, config, control_speed=10.0)
    assert runs[0].ratio == pytest.approx(floored.best_speed / c.best_speed)
    assert len(floored.trials) == 12 > len(replayed.trials)  # below the floor it goes on
    assert not runs[0].success and summarise(runs).below_control == 1


def test_a_partial_ceiling_walks_the_intact_fastest_share_and_estimates_the_rest(
    small_map, tmp_path
):
    from hexapod_adapt.online.ceiling import estimate_unwalked, store_ceiling, TOP_FRACTION

    damage = Damage.of('locked', [2])
    full = compute_ceiling(small_map, damage, 'mujoco')
    part = ceiling(small_map, damage, 'mujoco', cache_dir=tmp_path, partial=True)
    elites = small_map.elite_indices()
    intact = small_map.speeds()[elites]
    top = np.argsort(-intact, kind='stable')[: math.ceil(TOP_FRACTION * len(elites))]
    assert part.walked is not None and sorted(np.flatnonzero(part.walked)) == sorted(top)
    np.testing.assert_array_equal(part.speeds[part.walked], full.speeds[part.walked])
    with_nan = np.where(part.walked, full.speeds, np.nan)
    np.testing.assert_array_equal(part.speeds, estimate_unwalked(intact, with_nan))
    assert part.walked_mask[part.best_index]  # the best is one walked, never an estimate
    assert part.best_speed == full.speeds[part.walked].max()
    assert part.beating(-1.0) == part.walked.sum()
    # on disk: only what was walked, under its own key; read back estimated as computed
    path = cache_path(tmp_path, ceiling_key(small_map, damage, 'mujoco', partial=True))
    assert path.is_file() and '_part' in path.name
    assert not cache_path(tmp_path, ceiling_key(small_map, damage, 'mujoco')).exists()
    with np.load(path) as data:
        assert np.isnan(data['speeds']).sum() == len(elites) - len(top)
    again = cached_ceiling(small_map, damage, 'mujoco', [tmp_path])
    np.testing.assert_array_equal(again.speeds, part.speeds)
    np.testing.assert_array_equal(again.walked, part.walked)
    # ceiling() takes the partial one as cached; a full one, once cached, is preferred
    assert ceiling(small_map, damage, 'mujoco', cache_dir=tmp_path).walked is not None
    store_ceiling(small_map, full, tmp_path)
    assert cached_ceiling(small_map, damage, 'mujoco', [tmp_path]).walked is None
    # a partial file that walked nothing is not trusted
    key = ceiling_key(small_map, damage, 'mujoco', partial=True)
    from hexapod_adapt.online.ceiling import _checked

    data = {
        'key': np.array(json.dumps(key, sort_keys=True)),
        'niches': elites,
        'speeds': np.full(len(elites), np.nan),
    }
    assert _checked(data, 'x', key) is None


def test_the_cli_makes_no_partial_case_once_a_full_one_lies_deeper_than_the_share(
    small_map, tmp_path, monkeypatch, capsys
):
    from hexapod_adapt.online import ceiling as ceiling_module
    from hexapod_adapt.online import ceilings_cli

    archive = small_map.save(tmp_path / 'map.npz')
    cache = tmp_path / 'cache'
    argv = ['--archive', str(archive), '--scenarios', 'S1', '--damage-kind', 'locked']
    argv += ['--partial', 'locked', '--damage', '2:locked,5:locked', '--cache-dir', str(cache)]
    # a share under any full case's depth (at least 1 of the 12 gaits): refused, said, nothing made
    for module in (ceiling_module, ceilings_cli):
        monkeypatch.setattr(module, 'TOP_FRACTION', 0.5 / 12)
    assert ceilings_cli.main(argv) == 1
    assert 'past the partial share 4%' in capsys.readouterr().err
    assert [p.name for p in cache.glob('*_part*')] == []
    assert len(list(cache.glob('ceiling_*.npz'))) == 1  # the full case, made first
    for module in (ceiling_module, ceilings_cli):  # a share that holds it: the 6 partial cases
        monkeypatch.setattr(module, 'TOP_FRACTION', 1.0)
    assert ceilings_cli.main(argv) == 0
    assert len(list(cache.glob('ceiling_*_part100_*.npz'))) == 6


@pytest.mark.slow
def test_an_approximate_ceiling_evaluates_the_guides_best_gaits_only(small_map, tmp_path):
    from hexapod_adapt.online.ceiling import approximate_ceiling, approximate_key

    guide = compute_ceiling(small_map, [3], 'mujoco')
    approx = approximate_ceiling(small_map, [3], 'pybullet', guide, top=4, cache_dir=tmp_path)
    order = np.argsort(-guide.speeds, kind='stable')[:4]
    assert sorted(approx.niches.tolist()) == sorted(guide.niches[order].tolist())
    with create_simulator(map_physics(small_map, 'pybullet')) as sim:  # its own engine
        for n, speed in zip(approx.niches, approx.speeds):
            assert (
                speed
                == evaluate_gait(
                    small_map.genotypes[n], sim, collisions_fatal=False, failed_legs=[3]
                ).speed
            )
    path = cache_path(tmp_path, approximate_key(small_map, [3], 'pybullet', 'mujoco', 4))
    assert path.is_file() and '_top4_' in path.name
    full_key = ceiling_key(small_map, [3], 'pybullet')
    assert cache_path(tmp_path, full_key) != path  # never mistaken for a full ceiling
    with pytest.raises(ValueError, match='guide ceiling is for leg 3 lifted, not leg 2'):
        approximate_ceiling(small_map, [2], 'pybullet', guide, top=4)


def test_a_damage_bank_is_the_cached_ceilings_and_says_what_is_missing(small_map, tmp_path):
    from hexapod_adapt.online.bank import load_bank
    from hexapod_adapt.online.mboa import MboaConfig
    from hexapod_adapt.online.replay import lookup_trial
    from hexapod_adapt.online.session import AdaptationSession, run_session, SessionStart
    from hexapod_sim.damage import Damage

    cases = [Damage.lifted([1]), Damage.lifted([2, 5]), Damage.lifted([3])]
    made = {d: ceiling(small_map, d, 'mujoco', cache_dir=tmp_path) for d in cases[:2]}
    bank = load_bank(small_map, 'mujoco', [tmp_path / 'absent', tmp_path], cases)
    assert bank.damages == tuple(cases[:2]) and bank.missing == (cases[2],)
    for row, d in zip(bank.speeds, bank.damages):
        np.testing.assert_array_equal(row, made[d].speeds)
    assert '2 damage hypotheses on mujoco (1 not cached: leg 3 lifted)' == bank.describe()
    left = bank.without(cases[1])
    assert left.damages == (cases[0],) and left.speeds.shape == (1, len(small_map.elite_indices()))
    # what a run weighs: nothing when the setting is off, the bank less its own damage if asked
    assert bank.hypotheses(False) is None
    np.testing.assert_array_equal(bank.hypotheses(True), bank.speeds)
    np.testing.assert_array_equal(bank.hypotheses(True, cases[1]), left.speeds)
    assert load_bank(small_map, 'pybullet', [tmp_path], cases).speeds.shape == (0, 12)
    # a run weighing the bank: the trials (legs 2+5) favour that hypothesis over the map's
    truth = made[cases[1]]
    weights: list = []
    config = MboaConfig(max_trials=4, alpha=1.0, signal_variance=0.01, length_scale=0.2)
    session = AdaptationSession(small_map, config, SessionStart(hypotheses=bank.speeds))
    result = run_session(
        session,
        lookup_trial(truth),
        on_trial=lambda t, n, s: weights.append(s.opt.weights.copy()),
    )
    assert len(result.trials) == len(weights) == 4
    assert int(np.argmax(weights[-1])) == 2  # map, leg 1, legs 2+5


def test_a_bank_may_weigh_a_damage_not_cached_and_re_score_it_when_named(small_map, tmp_path):
    # the wider bank before its ceilings are made: a damage not cached is a hypothesis whose row
    # is NaN; the run that names it re-scores the top of the map then, and the bank keeps it
    from hexapod_adapt.online.bank import load_bank
    from hexapod_adapt.online.ceiling import estimate_unwalked, intact_order, quick_rescore
    from hexapod_adapt.online.session import blended_prior, diagnosis_plan

    cases = [Damage.lifted([1]), Damage.of('locked', [3])]
    cached = ceiling(small_map, cases[0], 'mujoco', cache_dir=tmp_path)
    bank = load_bank(small_map, 'mujoco', [tmp_path], cases, rescore_missing=True)
    assert bank.damages == tuple(cases) and bank.missing == (cases[1],)
    np.testing.assert_array_equal(bank.speeds[0], cached.speeds)
    assert np.isnan(bank.speeds[1]).all()
    assert bank.describe() == (
        '2 damage hypotheses on mujoco (1 not cached: each re-scored when a run names it)'
    )
    # the re-score: the intact-fastest walked as a ceiling walks them, the rest estimated
    full = ceiling(small_map, cases[1], 'mujoco')
    intact = small_map.speeds()[small_map.elite_indices()]
    top = intact_order(small_map)[:4]
    part = np.full(len(intact), np.nan)
    part[top] = full.speeds[top]
    quick = quick_rescore(small_map, cases[1], 'mujoco', first=4)
    np.testing.assert_allclose(quick, estimate_unwalked(intact, part), atol=1e-12)
    # before it is named, a blind run expects the map's own speeds of it
    plan = diagnosis_plan(small_map, bank)
    p = plan.diagnosis.posterior().probabilities
    expected = p[0] * cached.speeds + (p[1] + p[2]) * intact
    np.testing.assert_allclose(blended_prior(plan, intact), expected, atol=1e-12)
    # named: re-scored (its 12 gaits are under the 256 walked: all of them), kept in the bank
    np.testing.assert_allclose(plan.prior_of((1,), p), full.speeds, atol=1e-12)
    np.testing.assert_allclose(bank.speeds[1], full.speeds, atol=1e-12)
    # a plan given no way to re-score refuses to name it
    bare = replace(plan, priors=np.full_like(bank.speeds, np.nan), rescore=None)
    with pytest.raises(ValueError, match='leg 3 locked has no re-score'):
        bare.prior_of((1,), p)


def test_a_re_score_stops_within_a_chunk_of_gaits_when_asked_and_keeps_nothing(small_map):
    # a cancel while a blind run re-scores the damage it named: the walking ends at the next
    # chunk, the bank's row stays as it was (not cached), and a later re-score makes it whole
    from hexapod_adapt.online.bank import load_bank
    from hexapod_adapt.online.ceiling import QUICK_CHUNK, quick_rescore, RescoreStopped
    from hexapod_adapt.online.session import diagnosis_plan

    damage = Damage.of('locked', [3])
    assert len(small_map.elite_indices()) > QUICK_CHUNK  # walked in two chunks at least
    bank = load_bank(small_map, 'mujoco', [], [damage], rescore_missing=True)
    plan = diagnosis_plan(small_map, bank)
    p = plan.diagnosis.posterior().probabilities
    looks: list[int] = []

    def stop() -> bool:  # true from its second look: after the first chunk was walked
        looks.append(len(looks))
        return len(looks) > 1

    with pytest.raises(RescoreStopped):
        plan.prior_of((0,), p, stop)
    assert len(looks) == 2 and np.isnan(bank.speeds[0]).all()
    whole = plan.prior_of((0,), p)
    np.testing.assert_allclose(whole, quick_rescore(small_map, damage, 'mujoco'), atol=1e-12)
    np.testing.assert_allclose(bank.speeds[0], whole, atol=1e-12)


def test_a_re_score_in_two_processes_walks_the_same_speeds_and_still_stops_when_asked(small_map):
    # adapt_node re-scores a named damage in its prior_workers processes: the speeds are the one
    # process's to the bit, and a stop ends it and its workers at once
    import multiprocessing
    import time

    from hexapod_adapt.online.ceiling import quick_rescore, RescoreStopped

    damage = Damage.of('locked', [3])
    one = quick_rescore(small_map, damage, 'mujoco')
    np.testing.assert_array_equal(quick_rescore(small_map, damage, 'mujoco', workers=2), one)
    before = set(multiprocessing.active_children())  # another test's may still be ending
    asked = time.monotonic()
    with pytest.raises(RescoreStopped, match='leg 3 locked was stopped'):
        quick_rescore(small_map, damage, 'mujoco', stop=lambda: True, workers=2)
    assert time.monotonic() - asked < 10.0  # not after the walks: the pool is ended
    assert set(multiprocessing.active_children()) <= before  # its processes are gone


def test_the_diagnosis_banks_adapt_node_may_be_given():
    from hexapod_adapt.online.bank import BANK_DAMAGES, diagnosis_damages
    from hexapod_sim.damage import EXPERIMENT_KINDS

    every, none = diagnosis_damages('every')
    assert diagnosis_damages('lifted') == (BANK_DAMAGES, None) and len(BANK_DAMAGES) == 21
    assert none is None and diagnosis_damages('lifted-then-every') == (BANK_DAMAGES, every)
    conditions = {d.legs[0].condition for d in every}  # 'locked', 'unpowered femur', ...
    assert len(set(every)) == 168 and len(conditions) == len(EXPERIMENT_KINDS) == 8
    assert {d.failed_legs for d in every} == {d.failed_legs for d in BANK_DAMAGES}
    with pytest.raises(
        ValueError, match="no diagnosis bank 'all': one of lifted, every, lifted-then-every"
    ):
        diagnosis_damages('all')


def test_a_blind_run_s_wider_bank_weighs_every_kind_before_its_ceilings_land(tmp_path):
    # adapt_node's source of priors: the lifted legs first, then all 168 damages, those the
    # cache lacks with no re-score until a run names one. A cache of the lifted and locked
    # packs alone plays a map whose other kinds' cases are not made yet.
    from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_ceilings
    from hexapod_adapt.online.bank import BANK_DAMAGES, diagnosis_damages
    from hexapod_adapt.online.ceiling import cached_ceiling
    from hexapod_adapt.online.streaming_prior import StreamingPriors

    for kind in ('lifted', 'locked'):
        for pack in shipped_ceilings().glob(f'ceilings_mujoco_{kind}_*.zip'):
            shutil.copy(pack, tmp_path / pack.name)
    every, _ = diagnosis_damages('every')
    archive = load_archive(shipped_map(DEFAULT_MAP))
    priors = StreamingPriors(None, [tmp_path], 1, print, bank=BANK_DAMAGES, wider=every)
    plan = priors.diagnosis(archive, math.pi)
    assert plan.damages == BANK_DAMAGES and not np.isnan(plan.priors).any()
    wider = plan.wider()
    assert wider.damages == every and wider.rescore is not None
    engine = engine_of_map(archive)
    missing = 0
    for damage, row in zip(every, wider.priors):
        cached = cached_ceiling(archive, damage, engine, [tmp_path])
        if cached is None:
            missing += 1
            assert np.isnan(row).all(), damage.label
        else:
            np.testing.assert_array_equal(row, cached.speeds)
    assert missing == 168 - 42
    # told not to, it weighs what is cached alone
    alone = StreamingPriors(
        None, [tmp_path], 1, print, bank=BANK_DAMAGES, wider=every, rescore_when_named=False
    )
    kept = alone.diagnosis(archive, math.pi).wider()
    assert len(kept.damages) == 42 and set(kept.damages) < set(every)
    assert not np.isnan(kept.priors).any()


def test_a_blind_run_weighs_every_kind_the_shipped_cache_holds():
    from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_ceilings
    from hexapod_adapt.online.bank import BANK_DAMAGES, diagnosis_damages, load_bank
    from hexapod_adapt.online.diagnosis import Weighing
    from hexapod_adapt.online.session import diagnosis_plan
    from hexapod_adapt.online.streaming_prior import StreamingPriors

    every, _ = diagnosis_damages('every')
    # the shipped default map's cache holds all 168: a blind run weighs them, none to re-score
    archive = load_archive(shipped_map(DEFAULT_MAP))
    for damages, n in ((BANK_DAMAGES, 21), (every, 168)):
        priors = StreamingPriors(None, [shipped_ceilings()], 1, print, bank=damages)
        plan = priors.diagnosis(archive, math.pi)
        assert plan is not None and plan.damages == damages and plan.priors.shape[0] == n
        assert plan.wider is None and not np.isnan(plan.priors).any()
    # lifted, then every kind: the wider plan weighs the 168
    priors = StreamingPriors(None, [shipped_ceilings()], 1, print, bank=BANK_DAMAGES, wider=every)
    plan = priors.diagnosis(archive, math.pi)
    wider = plan.wider()
    assert plan.damages == BANK_DAMAGES and wider.damages == every and wider.wider is None
    assert wider.priors.shape[0] == 168 and not np.isnan(wider.priors).any()
    # the wider bank weighs as the first does, but for its own fit floor
    default = Weighing()
    assert plan.diagnosis.weighing == default
    assert wider.diagnosis.weighing == replace(default, fit_floor=default.wider_fit_floor)
    engine = engine_of_map(archive)
    first, rest = (
        load_bank(archive, engine, [shipped_ceilings()], d) for d in (BANK_DAMAGES, every)
    )
    weighing = Weighing(fit_floor=-14.0, wider_fit_floor=-25.0)
    plan = diagnosis_plan(archive, first, math.pi, weighing=weighing, wider=rest)
    assert plan.diagnosis.weighing.fit_floor == -14.0
    assert plan.wider().diagnosis.weighing.fit_floor == -25.0
