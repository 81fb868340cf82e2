# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The damage bank of step tables: made, saved, refused, and fit to the repertoire."""

import functools

from hexapod_sim import create_simulator, SimConfig
import numpy as np


def test_a_step_bank_is_each_step_played_with_the_damage_and_refused_for_another_repertoire(
    repertoire, tmp_path
):
    from dataclasses import replace

    from hexapod_gait.parameters import from_omni_genotype
    from hexapod_navigation.core.step_bank import compute_step_bank, load_step_bank, save_step_bank
    from hexapod_sim.damage import Damage
    from hexapod_sim.evaluation import evaluate_displacements

    small = replace(
        repertoire,
        niches=repertoire.niches[:5],
        moves=repertoire.moves[:5],
        heading_error=repertoire.heading_error[:5],
        genotypes=repertoire.genotypes[:5],
    )
    damages = (Damage.lifted([1]), Damage.lifted([2, 5]))
    bank = compute_step_bank(small, 'mujoco', damages, workers=2, chunk=2)
    assert bank.steps.shape == (2, 5, 3)
    with create_simulator(SimConfig(engine='mujoco')) as sim:
        direct = evaluate_displacements(
            list(small.genotypes),
            sim,
            small.step_duration,
            collisions_fatal=False,
            failed_legs=damages[1],
            decode=from_omni_genotype,
        )
    np.testing.assert_array_equal(bank.steps[1], [(m.x, m.y, m.yaw) for m in direct])
    # the tripod's cycles: intact, every direction walks about its stride; a lifted leg shortens
    assert bank.tripod.shape == (2, 8, 3) and bank.intact_tripod.shape == (8, 3)
    stride = np.hypot(bank.intact_tripod[:, 0], bank.intact_tripod[:, 1])
    assert np.all(stride > 0.25) and np.all(stride < 0.35)  # commanded: 0.3 m per cycle
    lifted = np.hypot(bank.tripod[:, :, 0], bank.tripod[:, :, 1])
    assert np.all(lifted.max(axis=1) < stride.min())
    assert bank.tripods().shape == (3, 8, 3)
    path = tmp_path / 'bank.npz'
    save_step_bank(path, bank, small, 'mujoco')
    again, why = load_step_bank(path, small, 'mujoco', damages)
    assert why == '' and np.array_equal(again.steps, bank.steps)
    assert np.array_equal(again.tripods(), bank.tripods())
    assert bank.without(damages[0]).damages == (damages[1],)
    np.testing.assert_array_equal(bank.without(damages[0]).tripods()[1], bank.tripod[1])
    other = replace(small, genotypes=small.genotypes[::-1].copy())
    refused, why = load_step_bank(path, other, 'mujoco', damages)
    assert refused is None and 'made for another genotypes_sha256' in why
    _, why = load_step_bank(path, small, 'pybullet', damages)
    assert 'another engine' in why
    path.write_bytes(path.read_bytes()[:50])
    _, why = load_step_bank(path, small, 'mujoco', damages)
    assert 'not a readable step bank' in why
    _, why = load_step_bank(tmp_path / 'absent.npz', small, 'mujoco', damages)
    assert why.startswith('no step bank at')


def test_a_bank_file_says_which_damages_it_holds_and_a_bad_list_is_refused(repertoire, tmp_path):
    import json
    import zipfile

    from hexapod_navigation.core.step_bank import load_step_bank, save_step_bank, StepBank
    from hexapod_sim.damage import Damage, parse_damage

    damages = (
        Damage.of('locked', [1, 4]),
        parse_damage('2:unpowered:femur+tibia,5:shortened:0.4'),
        Damage.of('weak', [3], 0.25),
    )
    rng = np.random.default_rng(0)
    bank = StepBank(
        damages,
        rng.normal(size=(3, len(repertoire), 3)),
        rng.normal(size=(3, 8, 3)),
        rng.normal(size=(8, 3)),
    )
    path = tmp_path / 'bank.npz'
    save_step_bank(path, bank, repertoire, 'mujoco')
    again, why = load_step_bank(path, repertoire, 'mujoco')  # the damages come from the file
    assert why == '' and again.damages == damages
    np.testing.assert_array_equal(again.steps, bank.steps)
    _, why = load_step_bank(path, repertoire, 'mujoco', damages[:2])
    assert 'made for another damages' in why
    # a key whose damages are not damages: refused, saying why
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    key = json.loads(str(arrays['key']))
    for bad in ([[[9, 'lifted', 1.0, []]]], [[[1, 'melted', 1.0, []]]], [[1]], 'legs'):
        arrays['key'] = np.array(json.dumps({**key, 'damages': bad}))
        with zipfile.ZipFile(path, 'w') as z:
            for k, v in arrays.items():
                with z.open(f'{k}.npy', 'w') as f:
                    np.lib.format.write_array(f, v)
        refused, why = load_step_bank(path, repertoire, 'mujoco')
        assert refused is None and 'names no damages a bank can hold' in why, why


def test_a_damaged_bank_file_is_refused_saying_so_never_raised(repertoire, tmp_path):
    from hexapod_navigation.core.step_bank import load_step_bank, save_step_bank, StepBank
    from hexapod_sim.damage import Damage

    rng = np.random.default_rng(1)
    bank = StepBank(
        (Damage.of('locked', [1, 4]),),
        rng.normal(size=(1, len(repertoire), 3)),
        rng.normal(size=(1, 8, 3)),
        rng.normal(size=(8, 3)),
    )
    path = tmp_path / 'bank.npz'
    save_step_bank(path, bank, repertoire, 'mujoco')
    blob = path.read_bytes()
    bad = tmp_path / 'bad.npz'
    outcomes = {'loaded': 0, 'refused': 0}
    for length in range(0, len(blob), max(1, len(blob) // 100)):  # every cut is refused
        bad.write_bytes(blob[:length])
        refused, why = load_step_bank(bad, repertoire, 'mujoco')
        assert refused is None and str(bad) in why, why
    for _ in range(1000):  # bit flips: a bank or a refusal naming the file (zlib's errors too)
        data = bytearray(blob)
        for _ in range(int(rng.integers(1, 4))):
            bit = int(rng.integers(0, 8 * len(data)))
            data[bit // 8] ^= 1 << (bit % 8)
        bad.write_bytes(bytes(data))
        loaded, why = load_step_bank(bad, repertoire, 'mujoco')
        assert (loaded is None) == bool(why) and (loaded is not None or str(bad) in why)
        outcomes['loaded' if loaded is not None else 'refused'] += 1
    assert outcomes['refused'] > 900, outcomes


def test_the_shipped_bank_fits_the_shipped_repertoire_and_re_measures_identically(repertoire):
    from dataclasses import replace

    from hexapod_navigation.core.step_bank import (
        compute_step_bank,
        load_step_bank,
        navigation_bank_damages,
        shipped_step_bank,
    )

    damages = navigation_bank_damages()
    assert len(damages) == 63  # 21 leg sets x lifted, locked, unpowered_femur
    bank, why = load_step_bank(shipped_step_bank(), repertoire, 'mujoco', damages)
    assert why == '' and bank.steps.shape == (63, len(repertoire), 3)
    rng = np.random.default_rng(3)
    h, rows = int(rng.integers(63)), np.sort(rng.choice(len(repertoire), 3, replace=False))
    few = replace(repertoire, genotypes=repertoire.genotypes[rows], niches=repertoire.niches[rows])
    again = compute_step_bank(few, 'mujoco', (bank.damages[h],))
    # bit for bit on the machine that made the bank; another processor's floating point moves the
    # last bits (1.1e-15 m on an AMD EPYC, 2026-11-25), far below any change of the model
    same = functools.partial(np.testing.assert_allclose, rtol=1e-9, atol=1e-12)
    same(again.steps[0], bank.steps[h, rows])
    same(again.tripod[0], bank.tripod[h])
    same(again.intact_tripod, bank.intact_tripod)


def test_run_navigation_refuses_a_bank_it_was_told_to_use_and_goes_on_without_a_default_one(
    tmp_path, capsys
):
    from hexapod_navigation.offline.run_navigation_cli import main

    garbage = tmp_path / 'bank.npz'
    garbage.write_bytes(b'not a bank')
    quick = ['--scenarios', 'S0', '--goals', '1', '--methods', 'tripod', '--workers', '1']
    assert main([*quick, '--bank', 'on', '--bank-file', str(garbage)]) == 2
    assert 'the damage bank cannot be used' in capsys.readouterr().err
    # the default: say so, learn without it (on trials of another engine than the bank's too)
    assert main([*quick, '--bank-file', str(garbage), '--engine', 'pybullet']) == 0
    out = capsys.readouterr().out
    assert 'no damage bank, the GP learns alone' in out and 'S0' in out
    assert main([*quick, '--engine', 'pybullet']) == 0  # the shipped (MuJoCo) bank fits
    assert 'no damage bank' not in capsys.readouterr().out
