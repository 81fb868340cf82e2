# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""run_experiment: thesis experiment 5.2 on the shipped demo map."""

import ast
import csv
import math
from pathlib import Path
import subprocess
import sys

from hexapod_adapt.online.mboa import TRIAL_BUDGET
import pytest

DEMO_MAP = Path(__file__).resolve().parents[2] / 'maps' / 'demo_map.npz'


@pytest.fixture(scope='module')
def demo_cut(tmp_path_factory) -> Path:
    """Return the demo map's 40 fastest gaits alone (a ceiling walks every gait of its map)."""
    from hexapod_adapt.mapping.archive import Archive, load_archive
    import numpy as np

    demo = load_archive(DEMO_MAP)
    elites = demo.elite_indices()
    drop = elites[np.argsort(-demo.fitness[elites])][40:]
    fitness, descriptors, genotypes = (
        demo.fitness.copy(),
        demo.descriptors.copy(),
        demo.genotypes.copy(),
    )
    fitness[drop], descriptors[drop], genotypes[drop] = np.nan, np.nan, np.nan
    cut = Archive(demo.centroids, fitness, descriptors, genotypes, dict(demo.metadata))
    return cut.save(tmp_path_factory.mktemp('demo_cut') / 'demo_cut.npz')


def _run(*args):
    return subprocess.run(
        [sys.executable, '-m', 'hexapod_adapt.online.run_experiment_cli', *args],
        capture_output=True,
        text=True,
        timeout=300,
    )


@pytest.mark.slow
def test_scenario_s2_runs_in_every_orientation_and_writes_csv(tmp_path):
    out = tmp_path / 'runs.csv'
    r = _run('--archive', str(DEMO_MAP), '--scenarios', 'S2', '--out', str(out))
    assert r.returncode == 0, r.stderr
    rows = list(csv.DictReader(out.open()))
    assert [row['failed_legs'] for row in rows] == ['1 4', '2 5', '3 6']
    for row in rows:
        assert 1 <= int(row['trials']) <= TRIAL_BUDGET  # the budget users get
        # two opposite legs stop the control tripod; the map has gaits that still walk forwards
        assert float(row['best_speed']) > float(row['control_speed'])


@pytest.mark.slow
def test_the_experiment_runs_on_another_damage_kind(tmp_path):
    out = tmp_path / 'runs.csv'
    common = ('--archive', str(DEMO_MAP), '--scenarios', 'S1', '--max-trials', '3')
    r = _run(*common, '--damage-kind', 'unpowered_femur', '--out', str(out))
    assert r.returncode == 0, r.stderr
    rows = list(csv.DictReader(out.open()))
    assert len(rows) == 6 and {row['damage_kind'] for row in rows} == {'unpowered_femur'}
    lifted = tmp_path / 'lifted.csv'
    assert _run(*common, '--out', str(lifted)).returncode == 0
    # the damaged tripod is measured under the kind asked for, not the lifted leg
    controls = [float(row['control_speed']) for row in rows]
    assert controls != [float(row['control_speed']) for row in csv.DictReader(lifted.open())]
    r = _run(*common, '--damage-kind', 'broken')
    assert r.returncode == 2 and "damage kind 'broken' is none of lifted," in r.stderr
    r = _run(*common, '--damage-kind', 'locked+weak')  # S1 fails one leg
    assert r.returncode == 2 and 'two kinds at once, one for each of two legs' in r.stderr


@pytest.mark.slow
def test_bad_inputs_are_refused(tmp_path):
    r = _run('--archive', str(tmp_path / 'missing.npz'))
    assert r.returncode == 2 and 'missing.npz: no such file' in r.stderr
    r = _run('--archive', str(DEMO_MAP), '--alpha', '0')
    assert r.returncode == 2 and 'alpha' in r.stderr


PNG = b'\x89PNG\r\n\x1a\n'


@pytest.mark.slow
def test_cross_engine_experiment_writes_csv_and_box_plots(tmp_path):
    r = _run(
        '--archive',
        str(DEMO_MAP),
        '--scenarios',
        'S2',
        '--cross-engine',
        '--max-trials',
        '4',
        '--out-dir',
        str(tmp_path),
    )
    assert r.returncode == 0, r.stderr
    rows = list(csv.DictReader((tmp_path / 'runs.csv').open()))
    assert sorted(row['trial_engine'] for row in rows) == (
        ['dart'] * 3 + ['mujoco'] * 3 + ['pybullet'] * 3
    )
    assert {row['map_engine'] for row in rows} == {'pybullet'}  # the demo map is a PyBullet map
    for row in rows:
        assert 1 <= int(row['trials']) <= 4 and float(row['intact_control_speed']) > 0.25
        assert 0 <= int(row['tipped_trials']) <= int(row['trials'])  # adapt_node's tip guard
        # each trial's gait and whether it tipped, in order, the best among the gaits
        niches = ast.literal_eval(row['trial_niches'])
        tipped = ast.literal_eval(row['trial_tipped'])
        assert len(niches) == len(tipped) == int(row['trials'])
        assert sum(tipped) == int(row['tipped_trials'])
        assert int(row['best_niche']) in (*niches, -1)  # -1: no trial walked
    for name in ('adapted_speed.png', 'trials.png'):
        assert (tmp_path / name).read_bytes().startswith(PNG)
    assert 'trials on  scenario' in r.stdout


@pytest.mark.slow
def test_plot_map_draws_a_map_and_a_log_in_progress(tmp_path):
    import json

    log = tmp_path / 'demo.log.jsonl'
    rows = [
        {
            'evaluations': 100 * k,
            'filled': 10 * k,
            'max': 0.1 * k,
            'mean': 0.05 * k,
            'median': 0.04 * k,
            'p5': 0.01 * k,
            'qd_score': float(k * k),
        }
        for k in range(1, 6)
    ]
    # torn last line
    log.write_text('\n'.join(json.dumps(r) for r in rows) + '\n{"evaluations": 6')
    r = subprocess.run(
        [
            sys.executable,
            '-m',
            'hexapod_adapt.mapping.plot_map_cli',
            '--archive',
            str(DEMO_MAP),
            '--log',
            str(log),
            '--out-dir',
            str(tmp_path),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert r.returncode == 0, r.stderr
    for name in ('demo_map_projections.png', 'demo_map_progress.png'):
        assert (tmp_path / name).read_bytes().startswith(PNG)
    bad = subprocess.run(
        [
            sys.executable,
            '-m',
            'hexapod_adapt.mapping.plot_map_cli',
            '--archive',
            str(tmp_path / 'no.npz'),
        ],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert bad.returncode == 2 and ': no such file' in bad.stderr


@pytest.mark.slow
def test_each_run_is_measured_against_the_maps_ceiling_under_its_damage(tmp_path, demo_cut):
    # the command line: ceilings computed into a cache, ratios in the CSV, a ratio plot
    r = _run(
        '--archive',
        str(demo_cut),
        '--scenarios',
        'S2',
        '--trial-engine',
        'mujoco',
        '--max-trials',
        '4',
        '--settle',
        '1',
        '--trial-duration',
        '2',
        '--ceilings',
        str(tmp_path / 'ceilings'),
        '--out-dir',
        str(tmp_path / 'out'),
    )
    assert r.returncode == 0, r.stderr
    rows = list(csv.DictReader((tmp_path / 'out' / 'runs.csv').open()))
    assert len(list((tmp_path / 'ceilings').glob('ceiling_mujoco_legs*.npz'))) == 3
    for row in rows:
        best, ceiling = float(row['best_speed']), float(row['ceiling_speed'])
        # same engine, and the adapted gait judged as the ceiling's gaits are (5 s from
        # standing), though its trials settled 1 s and timed 2 s: one of the gaits it ranks
        assert 0 < best <= ceiling and float(row['ratio']) == pytest.approx(best / ceiling)
        assert float(row['walking_time']) == (1.0 + 2.0) * int(row['trials'])
        assert math.isfinite(float(row['trial_speed']))
        assert int(row['gaits_beating_intact_control']) >= 0
    assert (tmp_path / 'out' / 'ceiling_ratio.png').is_file()
    assert 'adapted/ceiling med/min' in r.stdout


@pytest.mark.slow
def test_the_ceilings_command_caches_every_kind_of_damage_asked_for(tmp_path, capsys, demo_cut):
    from hexapod_adapt.online.ceilings_cli import main

    cache = tmp_path / 'ceilings'
    args = ['--archive', str(demo_cut), '--scenarios', 'S2', '--cache-dir', str(cache)]
    kinds = ['--damage-kind', 'locked', 'unpowered_femur']
    assert main([*args, *kinds, '--missing']) == 0  # computes nothing
    assert capsys.readouterr().out.split() == ['6'] and not list(cache.glob('*.npz'))
    assert main([*args, *kinds, '--workers', '2']) == 0
    capsys.readouterr()
    assert main([*args, *kinds, '--missing']) == 0
    assert capsys.readouterr().out.split() == ['0']
    # a damaged file is a lacking case
    next(cache.glob('ceiling_mujoco_legs*.npz')).write_bytes(b'not a ceiling')
    assert main([*args, *kinds, '--missing']) == 0
    assert capsys.readouterr().out.split() == ['1']
    files = sorted(p.name for p in cache.glob('ceiling_mujoco_legs*.npz'))
    assert len(files) == 6  # S2's three leg pairs, two kinds
    assert sum('locked' in f for f in files) == 3 and sum('unpowered' in f for f in files) == 3
    with pytest.raises(SystemExit):  # argparse: an unknown kind is refused, naming the choices
        main([*args, '--damage-kind', 'melted'])
    with pytest.raises(SystemExit):  # an approximation is never counted as a cached ceiling
        main([*args, '--missing', '--top', '10'])


def test_trials_run_on_the_engine_settings_asked_for():
    """trial_config: another engine's trials at another step; a contradiction is refused."""
    from hexapod_adapt.mapping.archive import load_archive
    from hexapod_adapt.online.experiment import ExperimentSetup, run_experiment
    from hexapod_adapt.online.mboa import MboaConfig
    from hexapod_gait import preset
    from hexapod_sim import create_simulator, evaluate_gait, SimConfig
    from hexapod_sim.damage import Damage

    archive = load_archive(DEMO_MAP)  # made on PyBullet
    four = SimConfig.converged('mujoco')
    rows = run_experiment(
        archive, ExperimentSetup(('S2',), MboaConfig(max_trials=2), trial_config=four)
    )
    with create_simulator(four) as sim:
        damaged = evaluate_gait(
            preset('control'), sim, collisions_fatal=False, failed_legs=Damage.lifted([1, 4])
        ).speed
    assert rows[0].trial_engine == 'mujoco'
    assert rows[0].control_speed == damaged  # the tripod walked on MuJoCo at 4 substeps
    with pytest.raises(ValueError, match='disagree'):
        run_experiment(archive, ExperimentSetup(('S2',), trial_engine='dart', trial_config=four))


@pytest.mark.slow
def test_trials_on_the_maps_engine_run_at_the_maps_steps_per_row():
    """A map made at 4 MuJoCo steps per row is adapted at 4 by default (map_substeps)."""
    from hexapod_adapt.mapping.archive import Archive, load_archive
    from hexapod_adapt.mapping.simulation import map_sim_config
    from hexapod_adapt.online.experiment import ExperimentSetup, run_experiment
    from hexapod_adapt.online.mboa import MboaConfig
    from hexapod_gait import preset
    from hexapod_sim import create_simulator, evaluate_gait
    from hexapod_sim.damage import Damage

    demo = load_archive(DEMO_MAP)
    four = map_sim_config('mujoco', 4)
    archive = Archive(
        demo.centroids,
        demo.fitness,
        demo.descriptors,
        demo.genotypes,
        {**demo.metadata, 'simulator': four.fingerprint()},
    )
    rows = run_experiment(archive, ExperimentSetup(('S2',), MboaConfig(max_trials=2)))
    with create_simulator(four) as sim:
        damaged = evaluate_gait(
            preset('control'), sim, collisions_fatal=False, failed_legs=Damage.lifted([1, 4])
        ).speed
    assert rows[0].map_engine == rows[0].trial_engine == 'mujoco'
    assert rows[0].control_speed == damaged
