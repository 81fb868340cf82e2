# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""MAP-Elites: reproducible whatever the parallelism, exact resume, the real simulator."""

import concurrent.futures as cf
import time

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.cvt import cached_cvt, compute_cvt
from hexapod_adapt.mapping.map_elites import load_checkpoint, MapElitesConfig, run_map_elites
from hexapod_adapt.mapping.simulation import SimulateGenotypes
from hexapod_sim import EvaluationResult
from hexapod_sim.sampling import random_reachable_genes
import numpy as np
import pytest


def toy_evaluate(genes):
    """Evaluate cheaply and deterministically: fitness and descriptor from the genes."""
    out = []
    for g in np.atleast_2d(genes):
        d = np.clip(np.abs(np.sin(7.0 * g[:6] + g[6:12])), 0, 1)
        out.append(
            EvaluationResult(
                float(np.sum(g[12:]) - 3 * np.abs(g[0] - 0.3)),
                d,
                bool(g[31] < 0.9),
                '',
                5.0,
                seconds=1e-4,
            )
        )
    return out


def toy_evaluate_jittered(genes):
    """Return the same results, finishing in a random order."""
    time.sleep(float(np.random.default_rng().uniform(0, 0.004)))
    return toy_evaluate(genes)


def _fresh(n=60):
    return Archive.empty(compute_cvt(n, samples=2000, seed=1))


def _same(a, b):
    for name in ('fitness', 'descriptors', 'genotypes'):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))


def test_cvt_is_seeded_cached_and_in_the_unit_cube(tmp_path):
    c1 = compute_cvt(30, samples=1500, seed=5)
    np.testing.assert_array_equal(c1, compute_cvt(30, samples=1500, seed=5))
    assert c1.shape == (30, 6) and c1.min() >= 0 and c1.max() <= 1
    assert not np.array_equal(c1, compute_cvt(30, samples=1500, seed=6))
    cached = cached_cvt(tmp_path, 30, samples=1500, seed=5)
    assert (tmp_path / 'centroids_30_6.dat').is_file()
    # read back, not recomputed
    np.testing.assert_allclose(cached_cvt(tmp_path, 30, seed=99), cached)


def test_same_seed_same_map_inline_pool_and_out_of_order_completion():
    cfg = MapElitesConfig(evaluations=600, seed=11, lag=8, random_init=0.2)
    inline = run_map_elites(_fresh(), cfg, toy_evaluate)
    assert inline.n_filled > 20 and inline.metadata['evaluations'] == 600
    with cf.ProcessPoolExecutor(2) as pool:
        pooled = run_map_elites(_fresh(), cfg, toy_evaluate_jittered, executor=pool, workers=2)
    with cf.ThreadPoolExecutor(4) as pool:
        chunked = run_map_elites(
            _fresh(),
            cfg.__class__(**{**cfg.__dict__, 'chunk': 3}),
            toy_evaluate_jittered,
            executor=pool,
            workers=4,
        )
    _same(inline, pooled)
    _same(inline, chunked)
    other = run_map_elites(
        _fresh(), MapElitesConfig(evaluations=600, seed=12, lag=8, random_init=0.2), toy_evaluate
    )
    assert not np.array_equal(inline.genotypes, other.genotypes, equal_nan=True)


def test_elites_only_improve_and_sit_in_their_nearest_niche():
    cfg = MapElitesConfig(evaluations=400, seed=3, lag=4, random_init=0.1)
    a = run_map_elites(_fresh(), cfg, toy_evaluate)
    idx = a.elite_indices()
    nearest = np.argmin(((a.descriptors[idx, None, :] - a.centroids[None]) ** 2).sum(-1), axis=1)
    np.testing.assert_array_equal(nearest, idx)
    for i in idx:
        r = toy_evaluate(a.genotypes[i])[0]
        assert r.fitness == a.fitness[i] and r.valid


def test_interrupted_run_resumes_exactly_from_its_checkpoint(tmp_path):
    cfg = MapElitesConfig(evaluations=500, seed=7, lag=6, random_init=0.1)
    whole = run_map_elites(_fresh(), cfg, toy_evaluate)
    calls = {'n': 0}

    def dies_after_200(genes):
        calls['n'] += 1
        if calls['n'] > 200:
            raise RuntimeError('node died')
        return toy_evaluate(genes)

    ckpt = tmp_path / 'run.ckpt.npz'
    with pytest.raises(RuntimeError, match='node died'):
        run_map_elites(_fresh(), cfg, dies_after_200, checkpoint=ckpt, checkpoint_every=0.0)
    archive, pending = load_checkpoint(ckpt)
    assert 150 < archive.metadata['evaluations'] <= 200 and pending
    resumed = run_map_elites(archive, cfg, toy_evaluate, pending=pending, checkpoint=ckpt)
    _same(whole, resumed)
    final, left = load_checkpoint(ckpt)
    assert final.metadata['evaluations'] == 500 and left == {}


def test_progress_rows_carry_the_log_figures():
    rows = []
    run_map_elites(
        _fresh(),
        MapElitesConfig(evaluations=100, seed=1, random_init=0.1),
        toy_evaluate,
        on_progress=rows.append,
        progress_every=0.0,
    )
    last = rows[-1]
    assert (
        last.evaluations == 100 and 0 < last.coverage <= 1 and last.max >= last.median >= last.p5
    )
    assert last.evals_per_s > 0 and 0 <= last.utilisation and '"qd_score"' in last.log_row()


@pytest.mark.slow
def test_real_simulator_map_is_reproducible_by_re_evaluation():
    # ~1 in 80 reachable random genotypes is a feasible gait
    cfg = MapElitesConfig(evaluations=400, seed=5, lag=16, random_init=1.0, chunk=4)
    simulate_genotypes = SimulateGenotypes('mujoco')
    with cf.ProcessPoolExecutor(2) as pool:
        a = run_map_elites(
            Archive.empty(compute_cvt(20, samples=1000, seed=2)),
            cfg,
            simulate_genotypes,
            executor=pool,
            workers=2,
            random_genes=random_reachable_genes,
        )
    idx = a.elite_indices()
    assert len(idx) >= 1
    for i in idx[:3]:
        r = simulate_genotypes(a.genotypes[i])[0]
        assert r.valid and r.fitness == a.fitness[i]
        np.testing.assert_array_equal(r.descriptor, a.descriptors[i])


def test_initial_genotypes_are_the_first_candidates():
    start = tuple(tuple(float(x) for x in np.linspace(0, 1, 32) * f) for f in (0.5, 1.0))
    cfg = MapElitesConfig(evaluations=50, seed=2, lag=4, random_init=0.1, initial=start)
    tried = []

    def record(genes):
        tried.extend(np.atleast_2d(genes).tolist())
        return toy_evaluate(genes)

    run_map_elites(_fresh(), cfg, record)
    assert [tuple(g) for g in tried[:2]] == list(start)
    with pytest.raises(ValueError, match='initial genotypes'):
        MapElitesConfig(evaluations=5, initial=((2.0,) * 32,))


def test_a_finished_run_extended_to_more_evaluations_equals_one_long_run(tmp_path):
    long = run_map_elites(
        _fresh(), MapElitesConfig(evaluations=400, seed=9, lag=5, random_init=0.1), toy_evaluate
    )
    ckpt = tmp_path / 'c.npz'
    run_map_elites(
        _fresh(),
        MapElitesConfig(evaluations=250, seed=9, lag=5, random_init=0.1),
        toy_evaluate,
        checkpoint=ckpt,
    )
    archive, pending = load_checkpoint(ckpt)
    assert pending == {}
    extended = run_map_elites(
        archive, MapElitesConfig(evaluations=400, seed=9, lag=5, random_init=0.1), toy_evaluate
    )
    _same(long, extended)


# -- pyribs emitter sets (issue 30) ------------------------------------------------------------
EMITTER_CONFIGS = {
    name: MapElitesConfig(
        evaluations=700,
        seed=5,
        lag=40,
        random_init=0.1,
        emitters=name,
        emitter=(('count', 2), ('batch', 10)),
    )
    for name in ('cma_me', 'cma_mae', 'bandit')
}


@pytest.mark.slow
@pytest.mark.parametrize('name', sorted(EMITTER_CONFIGS))
def test_each_emitter_set_makes_the_same_map_from_a_seed_whatever_the_workers(name):
    cfg = EMITTER_CONFIGS[name]
    inline = run_map_elites(_fresh(), cfg, toy_evaluate)
    assert inline.n_filled > 10 and inline.metadata['evaluations'] == 700
    assert inline.metadata['map_elites']['emitters'] == name
    with cf.ProcessPoolExecutor(2) as pool:
        two = run_map_elites(_fresh(), cfg, toy_evaluate_jittered, executor=pool, workers=2)
    with cf.ThreadPoolExecutor(4) as pool:
        four = run_map_elites(
            _fresh(),
            MapElitesConfig(**{**cfg.__dict__, 'chunk': 3}),
            toy_evaluate_jittered,
            executor=pool,
            workers=4,
        )
    _same(inline, two)
    _same(inline, four)
    other = run_map_elites(_fresh(), MapElitesConfig(**{**cfg.__dict__, 'seed': 6}), toy_evaluate)
    assert not np.array_equal(inline.genotypes, other.genotypes, equal_nan=True)


def test_an_emitter_set_proposes_other_gaits_than_iso_line():
    iso = run_map_elites(_fresh(), MapElitesConfig(evaluations=700, seed=5, lag=40), toy_evaluate)
    cma = run_map_elites(_fresh(), EMITTER_CONFIGS['cma_me'], toy_evaluate)
    assert not np.array_equal(iso.genotypes, cma.genotypes, equal_nan=True)
    assert 'emitters' not in iso.metadata['map_elites']  # older maps keep their identity


@pytest.mark.parametrize('name', ['cma_me', 'bandit'])
def test_an_emitter_run_resumes_exactly_from_its_checkpoint(name, tmp_path):
    from hexapod_adapt.mapping.map_elites import load_checkpoint_state

    cfg = EMITTER_CONFIGS[name]
    whole = run_map_elites(_fresh(), cfg, toy_evaluate)
    calls = {'n': 0}

    def dies_after_430(genes):  # mid-batch, with batches of other lanes in flight
        calls['n'] += 1
        if calls['n'] > 430:
            raise RuntimeError('node died')
        return toy_evaluate(genes)

    ckpt = tmp_path / 'run.ckpt.npz'
    with pytest.raises(RuntimeError, match='node died'):
        run_map_elites(_fresh(), cfg, dies_after_430, checkpoint=ckpt, checkpoint_every=0.0)
    archive, pending, proposer = load_checkpoint_state(ckpt)
    assert proposer is not None and pending
    resumed = run_map_elites(
        archive, cfg, toy_evaluate, pending=pending, proposer=proposer, checkpoint=ckpt
    )
    _same(whole, resumed)


def test_a_damaged_emitter_state_is_refused_with_the_file_named(tmp_path):
    from hexapod_adapt.mapping.archive import ArchiveError
    from hexapod_adapt.mapping.map_elites import load_checkpoint_state

    ckpt = tmp_path / 'run.ckpt.npz'
    run_map_elites(
        _fresh(), EMITTER_CONFIGS['cma_me'], toy_evaluate, checkpoint=ckpt, checkpoint_every=0.0
    )
    with np.load(ckpt) as data:
        arrays = {k: data[k] for k in data.files}
    arrays['emitter_state'] = arrays['emitter_state'][: len(arrays['emitter_state']) // 2]
    np.savez(ckpt, **arrays)
    with pytest.raises(ArchiveError, match='emitter state cannot be read'):
        load_checkpoint_state(ckpt)


def test_bad_emitter_settings_are_refused():
    with pytest.raises(ValueError, match='emitters must be one of'):
        MapElitesConfig(evaluations=10, emitters='genetic')
    with pytest.raises(ValueError, match='apply to a pyribs emitter set'):
        MapElitesConfig(evaluations=10, emitter=(('count', 3),))
    with pytest.raises(ValueError, match='must be >= 1'):
        MapElitesConfig(evaluations=10, emitters='cma_me', emitter=(('batch', 0),))
