# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""generate_map: the command, its files, backends that agree, resume, refusals."""

import json
from pathlib import Path
import subprocess
import sys

from hexapod_adapt.mapping.archive import ArchiveError, load_archive
from hexapod_adapt.mapping.generate import generate_map, GenerateConfig
from hexapod_adapt.mapping.simulation import simulation_fingerprint
from hexapod_util.processes import child_pids, is_running
import numpy as np
import pytest

SMALL = {
    'niches': 30,
    'evaluations': 120,
    'seed': 4,
    'lag': 16,
    'checkpoint_every': 1.0,
    'log_every': 0.5,
}


def _run_cli(*args):
    return subprocess.run(
        [sys.executable, '-m', 'hexapod_adapt.mapping.generate_map_cli', *args],
        capture_output=True,
        text=True,
        timeout=300,
    )


@pytest.mark.slow
def test_command_writes_archive_log_and_cvt_and_refuses_a_changed_resume(tmp_path):
    out = tmp_path / 'map.npz'
    small = ['--out', str(out), '--niches', '30', '--evaluations', '120', '--lag', '16']
    r = _run_cli(*small, '--seed', '4', '--workers', '2', '--log-every', '0.5', '--quiet')
    assert r.returncode == 0, r.stderr
    assert 'wrote' in r.stdout and 'of 30 niches' in r.stdout
    a = load_archive(out)
    assert a.metadata['evaluations'] == 120 and a.n_filled >= 1 and a.metadata['seed'] == 4
    for key, value in simulation_fingerprint().items():
        assert a.metadata[key] == value
    assert (tmp_path / 'centroids_30_6.dat').is_file()
    rows = [json.loads(line) for line in (tmp_path / 'map.npz.log.jsonl').read_text().splitlines()]
    assert rows[-1]['evaluations'] == 120
    keys = 'filled max mean median p5 qd_score coverage evals_per_s utilisation cpu_s'.split()
    assert set(keys) <= set(rows[-1])
    # the CPU the run used: 120 MuJoCo evaluations take some, and no more than its cores held
    last = rows[-1]
    assert 0.05 < last['cpu_s'] <= 1.05 * (last['workers'] + 1) * last['elapsed']
    # a finished run resumes to the same map
    same = _run_cli(*small, '--seed', '4', '--resume', '--quiet')
    assert same.returncode == 0, same.stderr
    np.testing.assert_array_equal(load_archive(out).fitness, a.fitness)
    bad = _run_cli(*small, '--seed', '5', '--resume')
    assert bad.returncode == 1 and 'resume with the same' in bad.stderr
    assert load_archive(out).metadata['seed'] == 4  # the good map is untouched


@pytest.mark.slow
def test_bad_arguments_are_refused_with_reasons(tmp_path):
    r = _run_cli('--out', str(tmp_path / 'm.npz'), '--niches', '1')
    assert r.returncode == 2 and 'argument --niches: must be in [2, ' in r.stderr
    r = _run_cli('--out', str(tmp_path / 'm.npz'), '--random-init', '2')
    assert r.returncode == 2 and 'argument --random-init: must be in [0, 1]' in r.stderr
    assert not (tmp_path / 'm.npz').exists()


@pytest.mark.slow
def test_local_pool_and_dask_cluster_make_the_same_map(tmp_path):
    local = generate_map(
        GenerateConfig(out=tmp_path / 'a' / 'map.npz', backend='local', workers=2, **SMALL)
    )
    dask = generate_map(
        GenerateConfig(out=tmp_path / 'b' / 'map.npz', backend='dask', workers=2, **SMALL)
    )
    np.testing.assert_array_equal(local.fitness, dask.fitness)
    np.testing.assert_array_equal(local.genotypes, dask.genotypes)


@pytest.mark.slow
def test_a_map_without_a_single_gait_is_not_a_success(tmp_path):
    # 3 evaluations of random genotypes: reachable ones are almost never feasible gaits
    r = _run_cli(
        '--out',
        str(tmp_path / 'm.npz'),
        '--niches',
        '5',
        '--evaluations',
        '3',
        '--seed',
        '1',
        '--backend',
        'inline',
        '--quiet',
    )
    assert r.returncode == 1 and 'no valid gait in 3 evaluations: no map written' in r.stderr
    assert not (tmp_path / 'm.npz').exists()


@pytest.mark.slow
def test_orphaned_temporaries_are_removed_on_start_and_resume(tmp_path):
    from hexapod_adapt.mapping.generate import remove_orphaned_temporaries

    out = tmp_path / 'map.npz'
    left = [tmp_path / '.map.npz.abc123.tmp', tmp_path / '.map.npz.ckpt.npz.x9.tmp']
    unrelated = tmp_path / '.other.npz.zz.tmp'
    for path in left + [unrelated]:
        path.write_bytes(b'partial')
    assert sorted(remove_orphaned_temporaries(out)) == sorted(left)
    assert unrelated.exists() and not any(p.exists() for p in left)
    r = _run_cli(
        '--out',
        str(out),
        '--niches',
        '5',
        '--evaluations',
        '3',
        '--seed',
        '1',
        '--backend',
        'inline',
        '--quiet',
        '--resume',
    )
    assert not any(p.exists() for p in left)
    assert r.returncode in (0, 1)


@pytest.mark.slow
def test_a_finished_map_without_its_checkpoint_continues_with_more_evaluations(tmp_path):
    out = tmp_path / 'map.npz'
    first = generate_map(GenerateConfig(out=out, workers=1, **SMALL))
    Path(f'{out}.ckpt.npz').unlink()
    more = generate_map(
        GenerateConfig(out=out, workers=1, resume=True, **{**SMALL, 'evaluations': 200})
    )
    assert more.metadata['evaluations'] == 200
    np.testing.assert_array_equal(more.centroids, first.centroids)
    # an elite is only ever replaced by a fitter gait
    kept = first.filled
    assert np.all(more.filled[kept])
    assert np.all(more.fitness[kept] >= first.fitness[kept])
    with pytest.raises(ArchiveError, match='more than the 120 asked for'):
        Path(f'{out}.ckpt.npz').unlink()
        generate_map(GenerateConfig(out=out, workers=1, resume=True, **SMALL))


def _kill_midway(args: list, out: Path, evaluations: int, emitters: bool = True) -> None:
    """
    Run generate_map on one worker; SIGKILL it once a checkpoint holds ``evaluations``.

    ``emitters``: the run's checkpoints hold a pyribs proposer (iso+line's hold none).
    """
    import signal
    import time

    from hexapod_adapt.mapping.map_elites import load_checkpoint_state

    proc = subprocess.Popen(
        [sys.executable, '-m', 'hexapod_adapt.mapping.generate_map_cli', *args]
        + ['--workers', '1'],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    ckpt = Path(f'{out}.ckpt.npz')
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        try:
            archive, pending, proposer = load_checkpoint_state(ckpt)
        except (OSError, ArchiveError, ValueError, KeyError):
            time.sleep(0.05)
            continue
        if (proposer is not None or not emitters) and archive.metadata[
            'evaluations'
        ] >= evaluations:
            break
        time.sleep(0.05)
    workers = child_pids(proc.pid)
    assert workers  # the pool's worker
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert not out.exists() and (proposer is not None or not emitters) and pending  # mid-run
    # the workers die with it (CI once found one still evaluating after this test)
    deadline = time.monotonic() + 20
    while any(Path(f'/proc/{pid}').exists() for pid in workers) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not [pid for pid in workers if is_running(pid)], 'a worker outlived generate_map'


@pytest.mark.slow
def test_an_emitter_map_killed_and_resumed_equals_one_run_and_loads_in_adapt_node(tmp_path):
    from hexapod_adapt.online.run_config import ArchiveSlot
    from hexapod_adapt.online.trials import MODES

    def args(out):
        return [
            '--out', str(out), '--niches', '30', '--evaluations', '400', '--seed', '2',
            '--emitters', 'cma_me', '--emitter-count', '2', '--emitter-batch', '10',
            '--checkpoint-every', '0.2', '--quiet',
        ]  # fmt: skip

    whole = tmp_path / 'whole' / 'map.npz'
    assert _run_cli(*args(whole), '--workers', '2').returncode == 0
    killed = tmp_path / 'killed' / 'map.npz'
    _kill_midway(args(killed), killed, 150)
    resumed = _run_cli(*args(killed), '--workers', '2', '--resume')  # other workers, too
    assert resumed.returncode == 0, resumed.stderr
    a, b = load_archive(whole), load_archive(killed)
    np.testing.assert_array_equal(a.fitness, b.fitness)
    np.testing.assert_array_equal(a.genotypes, b.genotypes)
    assert b.metadata['map_elites']['emitters'] == 'cma_me'
    slot = ArchiveSlot('sim', MODES)  # what adapt_node runs on
    assert slot.load(str(killed)) == '' and slot.archive.n_filled == b.n_filled


def test_the_runs_of_a_resumed_log_are_told_apart_in_the_order_written(tmp_path):
    import json

    from hexapod_adapt.mapping.plots import log_runs, read_log

    # a run logged to 3,000 evaluations, killed; resumed from its checkpoint at 2,000: the new
    # run logs 2,500 and 3,000 again, then goes on (and a torn last line)
    rows = [(1000, 100.0), (2000, 200.0), (2500, 250.0), (3000, 300.0)]
    rows += [(2500, 40.0), (3000, 90.0), (4000, 190.0)]
    log = tmp_path / 'map.npz.log.jsonl'
    log.write_text(
        ''.join(
            json.dumps({'evaluations': e, 'elapsed': s, 'workers': 2, 'cpu_s': 1.5 * s}) + '\n'
            for e, s in rows
        )
        + '{"evaluations": 41'
    )
    runs = log_runs(log)
    assert [(r.evaluations, r.elapsed, r.cpu_s) for r in runs] == [
        (3000, 300.0, 450.0),
        (4000, 190.0, 285.0),
    ]
    assert sum(r.core_seconds for r in runs) == 2 * (300.0 + 190.0)
    assert [r['evaluations'] for r in read_log(log)] == [1000, 2000, 2500, 2500, 3000, 3000, 4000]


@pytest.mark.slow
def test_a_walk_guarded_map_is_made_from_its_seed_and_resumes_exactly_after_sigkill(tmp_path):
    def args(out):
        return [
            '--out', str(out), '--niches', '30', '--evaluations', '300', '--seed', '3',
            '--emitters', 'cma_mae', '--emitter-count', '2', '--emitter-batch', '10',
            '--with-presets', '--min-feet', '3', '--max-tilt', '0.52',
            '--checkpoint-every', '0.2', '--quiet',
        ]  # fmt: skip

    first, second = tmp_path / 'a' / 'map.npz', tmp_path / 'b' / 'map.npz'
    assert _run_cli(*args(first), '--workers', '2').returncode == 0
    assert _run_cli(*args(second), '--workers', '1').returncode == 0
    killed = tmp_path / 'killed' / 'map.npz'
    _kill_midway(args(killed), killed, 100)
    assert _run_cli(*args(killed), '--workers', '2', '--resume').returncode == 0
    a, b, k = load_archive(first), load_archive(second), load_archive(killed)
    for other in (b, k):
        np.testing.assert_array_equal(a.fitness, other.fitness)
        np.testing.assert_array_equal(a.genotypes, other.genotypes)
    assert a.metadata['walk_guards'] == {'min_feet': 3.0, 'max_tilt': 0.52}
    elites = a.elite_indices()
    assert len(elites) > 0
    # every elite keeps three feet down on average (its descriptor is its duty factors)
    assert (a.descriptors[elites].sum(axis=1) >= 3.0).all()


def _made_twice_and_resumed(tmp_path, args, kill_at: int, other):
    """
    Make the map ``args(out)`` says on 2 workers and on 1, and on 1 killed at ``kill_at``.

    The killed run resumed with ``other(out)`` is refused (another simulator);
    resumed as it was, on 2 workers, it ends as the others, bit for bit. Returns the map.
    """
    first, second = tmp_path / 'a' / 'map.npz', tmp_path / 'b' / 'map.npz'
    assert _run_cli(*args(first), '--workers', '2').returncode == 0
    assert _run_cli(*args(second), '--workers', '1').returncode == 0
    killed = tmp_path / 'killed' / 'map.npz'
    _kill_midway(args(killed), killed, kill_at, emitters=False)
    refused = _run_cli(*other(killed), '--resume')
    assert refused.returncode != 0 and 'another simulator' in refused.stderr
    assert _run_cli(*args(killed), '--workers', '2', '--resume').returncode == 0
    a, b, k = load_archive(first), load_archive(second), load_archive(killed)
    for o in (b, k):
        np.testing.assert_array_equal(a.fitness, o.fitness)
        np.testing.assert_array_equal(a.genotypes, o.genotypes)
        np.testing.assert_array_equal(a.peak_tilt, o.peak_tilt)
    return a


@pytest.mark.slow
def test_a_map_at_4_substeps_is_made_from_its_seed_and_resumes_exactly_after_sigkill(tmp_path):
    """The default map's option: MuJoCo at 4 physics steps per row, recorded, never mixed."""

    def args(out, substeps='4'):
        return [
            '--out', str(out), '--niches', '30', '--evaluations', '300', '--seed', '4',
            '--with-presets', '--substeps', substeps, '--checkpoint-every', '0.2', '--quiet',
        ]  # fmt: skip

    # resumed on the engine's default (1 step per row): refused, the checkpoint kept
    a = _made_twice_and_resumed(tmp_path, args, 100, lambda out: args(out, substeps='0'))
    assert a.metadata['simulator']['settings']['substeps'] == 4
    assert a.n_filled > 0
    # the map's stored speeds are MuJoCo's at 4 substeps: one re-walked there gives it again
    from hexapod_adapt.mapping.simulation import SimulateGenotypes

    best = a.elite_indices()[np.argmax(a.fitness[a.elite_indices()])]
    again = SimulateGenotypes('mujoco', substeps=4)(a.genotypes[best][None])[0]
    assert again.fitness == a.fitness[best]


def test_walk_guards_refuse_nonsense_and_say_why_a_gait_fails():
    from hexapod_adapt.mapping.simulation import WalkGuards
    from hexapod_sim.evaluation import EvaluationResult

    for bad in ({'min_feet': -1.0}, {'min_feet': 7.0}, {'max_tilt': 0.0}, {'max_tilt': 4.0}):
        with pytest.raises(ValueError, match=next(iter(bad))):
            WalkGuards(**bad)
    assert not WalkGuards().active and WalkGuards(min_feet=3).active
    runs = EvaluationResult(1.0, np.full(6, 0.4), True, '', 5.0)  # 2.4 feet down
    walks = EvaluationResult(1.0, np.full(6, 0.6), True, '', 5.0, peak_tilt=0.7)
    guards = WalkGuards(min_feet=3.0, max_tilt=0.5)
    assert 'fewer than 3' in guards.problem(runs)
    assert 'tilted 40 deg' in guards.problem(walks)
    assert WalkGuards(min_feet=3.0).problem(walks) == ''
    assert 'walk_guards' not in simulation_fingerprint('mujoco', WalkGuards())


@pytest.mark.slow
def test_a_robust_map_is_made_from_its_seed_and_resumes_exactly_after_sigkill(tmp_path):
    """Issue 66: each gait walked in 3 physics variants, stored by their minimum, tilt kept."""
    from hexapod_adapt.mapping.robust import RobustScore
    from hexapod_adapt.mapping.simulation import SimulateGenotypes

    def args(out, statistic='min'):
        return [
            '--out', str(out), '--niches', '30', '--evaluations', '120', '--seed', '5',
            '--with-presets', '--variants', '3', '--statistic', statistic,
            '--variant-seed', '7', '--checkpoint-every', '0.2', '--quiet',
        ]  # fmt: skip

    # resumed with another statistic: refused, the checkpoint kept
    a = _made_twice_and_resumed(tmp_path, args, 40, lambda out: args(out, statistic='q25'))
    score = a.metadata['robust_score']
    assert (score['variants'], score['statistic'], score['seed']) == (3, 'min', 7)
    assert len(score['physics']) == 3
    elites = a.elite_indices()
    assert len(elites) > 0
    assert (
        np.isfinite(a.peak_tilt[elites]).all() and np.isnan(np.delete(a.peak_tilt, elites)).all()
    )
    # the stored distance is the least of the gait's walks in its variants, each walked alone
    best = elites[np.argmax(a.fitness[elites])]
    genes = a.genotypes[best][None]
    robust = RobustScore(3, 'min', 7)
    walks = [
        SimulateGenotypes('mujoco', robust=RobustScore(1, 'min', 0))(genes)[0],  # another one
        SimulateGenotypes('mujoco', robust=robust)(genes)[0],
    ]
    assert walks[1].fitness == a.fitness[best] and walks[1].peak_tilt == a.peak_tilt[best]
    assert walks[0].fitness != a.fitness[best]


def test_a_robust_score_refuses_nonsense_and_combines_walks_as_it_says():
    from hexapod_adapt.mapping.robust import RobustScore
    from hexapod_sim.evaluation import EvaluationResult, failure

    for bad, match in (
        ({'variants': -1}, r'variants must be in \[0, 256\]'),
        ({'variants': 2.0}, 'variants must be an integer'),
        ({'variants': 2, 'statistic': 'median'}, 'statistic must be one of min, q25, mean-std'),
        ({'variants': 2, 'seed': -3}, 'variant seed must be in'),
    ):
        with pytest.raises(ValueError, match=match):
            RobustScore(**bad)

    def walk(distance, duty, tilt):
        return EvaluationResult(distance, np.full(6, duty), True, '', 5.0, peak_tilt=tilt)

    walks = [walk(1.0, 0.5, 0.1), walk(0.6, 0.7, 0.3), walk(0.8, 0.6, 0.2), walk(1.4, 0.4, 0.1)]
    d = np.array([1.0, 0.6, 0.8, 1.4])
    for statistic, expected in (
        ('min', 0.6),
        ('q25', np.quantile(d, 0.25)),
        ('mean-std', d.mean() - d.std()),
    ):
        r = RobustScore(4, statistic).combine(walks)
        assert r.valid and r.fitness == pytest.approx(expected)
        np.testing.assert_allclose(r.descriptor, np.full(6, 0.55))
        assert r.peak_tilt == 0.3
    broken = RobustScore(4).combine([*walks[:2], failure('self-collision a / b', 5.0), walks[3]])
    assert not broken.valid and broken.reason == 'in physics variant 2: self-collision a / b'
    with pytest.raises(ValueError, match='gait maps on MuJoCo only'):
        GenerateConfig(out=Path('m.npz'), engine='pybullet', robust=RobustScore(2))
