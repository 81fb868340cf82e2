# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Gaits made for a damage as navigation steps (hexapod_navigation.core.specialists; issue 31)."""

import math
from pathlib import Path

from hexapod_adapt.mapping.archive import load_archive
from hexapod_adapt.mapping.maps import shipped_ceilings, shipped_map
from hexapod_adapt.mapping.steps import gait_min_stance
from hexapod_adapt.online.ceiling import cached_ceiling
from hexapod_gait.parameters import from_genotype
from hexapod_navigation.core.loading import load_navigation
from hexapod_navigation.core.repertoire import shipped_repertoire
from hexapod_navigation.core.specialists import (
    load_specialists,
    save_specialists,
    shipped_specialists,
    source_gaits,
    Specialists,
)
from hexapod_navigation.core.step_bank import shipped_step_bank, step_table
from hexapod_sim.damage import Damage
import numpy as np
import pytest


@pytest.fixture(scope='module')
def shipped():
    """Load the shipped repertoire and bank without and with the specialists."""
    base = load_navigation(shipped_repertoire(), shipped_step_bank())
    both = load_navigation(shipped_repertoire(), shipped_step_bank(), shipped_specialists())
    return base, both


def test_the_shipped_specialists_extend_the_repertoire_and_its_bank_row_for_row(shipped):
    base, both = shipped
    assert both.no_specialists == '' and both.specialists > 0
    k = both.specialists
    assert len(both.repertoire) == len(base.repertoire) + k
    assert both.bank.steps.shape == (len(base.bank), len(both.repertoire), 3)
    # the repertoire's own rows are untouched; the specialists come after them
    np.testing.assert_array_equal(both.bank.steps[:, :-k], base.bank.steps)
    np.testing.assert_array_equal(both.repertoire.moves[:-k], base.repertoire.moves)
    assert both.bank.damages == base.bank.damages
    # every specialist keeps 3 feet down, as the planner's repertoire steps must
    assert (both.repertoire.min_stance()[-k:] >= 3).all()


def test_on_every_lifted_case_a_specialist_outwalks_the_repertoire_its_way(shipped):
    """
    Gaits made for a damage beat the repertoire's steps their way.

    The margin is the map's (studies/navigation/results/navigation_bound.txt): the CMA-MAE
    map's specialists went 1.5-3x further; the transfer map's, slower on MuJoCo, 1.36-2.87x.
    """
    base, both = shipped
    k = both.specialists
    allowed = base.repertoire.min_stance() >= 3
    lifted = [h for h, d in enumerate(base.bank.damages) if d.legs[0].kind == 'lifted']
    assert len(lifted) == 21
    for h in lifted:
        own = both.bank.steps[h, -k:, :2]  # each specialist's step under the damage
        length = np.hypot(*own.T)
        unit = own / np.maximum(length[:, None], 1e-9)
        # the repertoire's most progress in each specialist's direction, under the same damage
        best = np.max(base.bank.steps[h][allowed, :2] @ unit.T, axis=0)
        ratio = float(np.max(length / np.maximum(best, 1e-3)))
        assert ratio > 1.0, (base.bank.damages[h].label, ratio)


def test_the_shipped_steps_are_what_the_specialists_walk(shipped):
    _, both = shipped
    k = both.specialists
    genes = both.repertoire.genotypes[-k:][:3]
    damage = Damage.lifted((2,))
    h = both.bank.damages.index(damage)
    walked = step_table((both.repertoire.engine, damage, both.repertoire.step_duration, genes))
    np.testing.assert_allclose(walked, both.bank.steps[h, -k:][:3], atol=1e-3)


def test_the_specialist_for_a_damage_is_the_maps_fastest_3_feet_gait_under_it():
    archive = load_archive(shipped_map())
    damage = Damage.lifted((1, 4))
    niches = source_gaits(archive, [damage], 'mujoco', [shipped_ceilings()], 3)
    ceiling = cached_ceiling(archive, damage, 'mujoco', [shipped_ceilings()])
    stable = [
        (s, int(n))
        for s, n in zip(ceiling.speeds, ceiling.niches)
        if gait_min_stance(from_genotype(archive.genotypes[n])) >= 3
    ]
    assert niches[1] == max(stable)[1]
    assert max(stable)[0] < ceiling.best_speed  # the fastest of all has fewer feet down


def test_specialists_made_for_other_damages_are_refused_with_the_reason(shipped, tmp_path: Path):
    base, both = shipped
    k = both.specialists
    sp = Specialists(
        both.repertoire.genotypes[-k:],
        np.zeros((k, 3)),
        both.bank.steps[:3, -k:],
        base.bank.damages[:3],
        base.repertoire.step_duration,
        np.zeros((3, k)),
    )
    path = tmp_path / 'few.npz'
    save_specialists(path, sp, 'mujoco', load_archive(shipped_map()), 3)
    loaded, why = load_specialists(path, 'mujoco', base.bank.damages, 2.0)
    assert loaded is None and f'for {len(base.bank)} damages' in why
    again, why = load_specialists(path, 'mujoco', base.bank.damages[:3], 2.0)
    assert again is not None and why == ''
    other, why = load_specialists(path, 'pybullet', base.bank.damages[:3], 2.0)
    assert other is None and 'engine' in why


def test_a_damaged_specialists_file_is_said_and_navigation_goes_on_without(tmp_path: Path):
    broken = tmp_path / 'broken.npz'
    broken.write_bytes(b'PK\x03\x04 not a zip at all')
    data = load_navigation(shipped_repertoire(), shipped_step_bank(), broken)
    assert data.repertoire is not None and data.bank is not None
    assert data.specialists == 0 and 'not a readable specialists file' in data.no_specialists
    missing = load_navigation(shipped_repertoire(), shipped_step_bank(), tmp_path / 'none.npz')
    assert missing.specialists == 0 and 'no specialists at' in missing.no_specialists
    no_bank = load_navigation(shipped_repertoire(), tmp_path / 'none.npz', shipped_specialists())
    assert no_bank.specialists == 0 and 'no damage bank' in no_bank.no_specialists


def test_tampered_specialist_genes_are_refused(shipped, tmp_path: Path):
    _, both = shipped
    with np.load(shipped_specialists()) as data:
        arrays = {name: data[name] for name in data.files}
    arrays['genotypes'] = arrays['genotypes'].copy()
    arrays['genotypes'][0, 0] = 1.0 - arrays['genotypes'][0, 0]
    path = tmp_path / 'tampered.npz'
    np.savez(path, **arrays)
    sp, why = load_specialists(path, 'mujoco', both.bank.damages, 2.0)
    assert sp is None and 'genotypes_sha256' in why


def test_reverse_and_arcs_are_the_same_gait_in_other_directions(shipped):
    """Each kept variant walks its own way: the reverse crab angle goes the other way intact."""
    _, both = shipped
    k = both.specialists
    intact = both.repertoire.moves[-k:]
    genes = both.repertoire.genotypes[-k:]
    gaits = [both.repertoire.gait(len(both.repertoire) - k + i) for i in range(k)]
    straight = [i for i, g in enumerate(gaits) if g.turn_rate == 0.0]
    pairs = 0
    for i in straight:
        twin = [
            j
            for j in straight
            if j != i
            and np.allclose(genes[j][:32], genes[i][:32])
            and math.isclose(abs(gaits[j].crab_angle - gaits[i].crab_angle), math.pi, abs_tol=1e-6)
        ]
        for j in twin:  # opposite directions, intact
            assert float(intact[i] @ intact[j]) < 0.0
            pairs += 1
    assert pairs > 0


def test_run_navigation_refuses_specialists_it_was_told_to_use_and_says_when_it_goes_without(
    tmp_path: Path, capsys
):
    from hexapod_navigation.offline.run_navigation_cli import main

    garbage = tmp_path / 'specialists.npz'
    garbage.write_bytes(b'not specialists')
    quick = ['--scenarios', 'S0', '--goals', '1', '--methods', 'tripod', '--workers', '1']
    assert main([*quick, '--specialists', 'on', '--specialists-file', str(garbage)]) == 2
    assert 'the specialists cannot be used' in capsys.readouterr().err
    assert main([*quick, '--specialists', 'off', '--specialists-file', str(garbage)]) == 0
    assert 'specialists' not in capsys.readouterr().out


def test_a_tilt_limit_keeps_the_specialists_that_stay_upright_under_every_damage(shipped):
    _, both = shipped
    with np.load(shipped_specialists()) as data:
        tilt = data['tilt']
    upright = np.all(tilt <= 0.5, axis=0)
    assert 0 < upright.sum() < len(upright)  # the limit bites, and leaves some
    kept = load_navigation(shipped_repertoire(), shipped_step_bank(), shipped_specialists(), 0.5)
    assert kept.specialists == int(upright.sum())
    few, every = len(kept.repertoire) - kept.specialists, len(both.repertoire) - both.specialists
    np.testing.assert_array_equal(
        kept.repertoire.genotypes[few:], both.repertoire.genotypes[every:][upright]
    )
