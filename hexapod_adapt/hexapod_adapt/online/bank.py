# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A damage bank: the map re-scored in simulation under each damage M-BOA should consider.

When the damage is not known, M-BOA can still weigh hypotheses about it: the map's gaits
evaluated, offline, under every one- and two-leg failure (:data:`BANK_DAMAGES`, 21 cases), each a
prior mean the trials confirm or rule out (:class:`hexapod_adapt.online.mboa.Mboa`'s
``hypotheses``). A blind run's diagnosis weighs them, or every damage kind on those legs
(:data:`DIAGNOSIS_BANKS`). A bank is a set of cached ceilings
(:mod:`hexapod_adapt.online.ceiling`): for the default map they ship in ``maps/ceilings``
(``maps/make_ceilings.sh`` makes them); for another map ``python -m
hexapod_adapt.online.ceilings_cli --archive MAP --cache-dir DIR`` does. Nothing here computes: a
case that is not cached is listed as missing, and the bank is what is there, or, with
``rescore_missing``, a hypothesis all the same whose row is NaN until a run names it: the
diagnosis walks each hypothesis's gaits when it needs them, and a run that names such a damage
re-scores the top of the map under it then (:func:`~hexapod_adapt.online.ceiling.quick_rescore`).

A bank only helps where its hypotheses resemble the real damage. The tuning set measures the case
where they do not (locked legs, weak servos, lost tibias: none is in the lifted bank).
"""

from __future__ import annotations

from dataclasses import dataclass
import os
from typing import Sequence

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.online.ceiling import cached_ceiling
from hexapod_sim.damage import Damage, EXPERIMENT_KINDS
from hexapod_sim.scenarios import scenario
import numpy as np

#: Every one- and two-leg failure (the failed legs lifted): the orientations of S1-S4.
BANK_DAMAGES: tuple[Damage, ...] = tuple(
    Damage.lifted(legs) for name in ('S1', 'S2', 'S3', 'S4') for legs in scenario(name)
)
#: Every damage kind on each of those leg sets (168 cases).
EVERY_KIND_DAMAGES: tuple[Damage, ...] = tuple(
    Damage.of(kind, d.failed_legs) for kind in EXPERIMENT_KINDS for d in BANK_DAMAGES
)
#: The banks a blind run may name its damage among, by adapt_node's ``diagnosis_bank``: the
#: damages it weighs first, and those it weighs once none of them fits its trials (None: it
#: falls back to blind M-BOA then). Every kind from the start names locked legs far better than
#: the lifted legs, but lifted ones later, and tipped once more on a tuning set; weighing every
#: kind only once no lifted leg fits kept the lifted runs and beat both elsewhere
#: (studies/diagnosis/README.md, "The product's bank", "Widening the bank").
DIAGNOSIS_BANKS: dict[str, tuple[tuple[Damage, ...], tuple[Damage, ...] | None]] = {
    'lifted': (BANK_DAMAGES, None),
    'every': (EVERY_KIND_DAMAGES, None),
    'lifted-then-every': (BANK_DAMAGES, EVERY_KIND_DAMAGES),
}


#: adapt_node's bank and the benchmarks'.
DEFAULT_DIAGNOSIS_BANK = 'lifted-then-every'
#: Whether the wider bank weighs the damages not cached too, each re-scored when named
#: (:func:`load_diagnosis_banks`): it won on a tuning set (studies/diagnosis/README.md,
#: "Weighing the kinds not cached yet").
RESCORE_WHEN_NAMED = True


def diagnosis_damages(bank: str) -> tuple[tuple[Damage, ...], tuple[Damage, ...] | None]:
    """Return the damages of the diagnosis bank ``bank``: first, and wider (ValueError: none)."""
    if bank not in DIAGNOSIS_BANKS:
        raise ValueError(f'no diagnosis bank {bank!r}: one of {", ".join(DIAGNOSIS_BANKS)}')
    return DIAGNOSIS_BANKS[bank]


@dataclass(frozen=True)
class DamageBank:
    """The map's gaits re-scored under each of ``damages`` (rows of ``speeds``) on ``engine``."""

    engine: str
    damages: tuple[Damage, ...]
    # (len(damages), elites) m/s, elites in archive.elite_indices() order; a row of NaN: a damage
    # not cached, re-scored when a run names it (load_bank's rescore_missing)
    speeds: np.ndarray
    missing: tuple[Damage, ...] = ()  # asked for but not cached

    def __len__(self) -> int:
        return len(self.damages)

    def without(self, damage: Damage) -> DamageBank:
        """Return the bank less ``damage`` (an experiment's damage left out of its hypotheses)."""
        keep = [i for i, d in enumerate(self.damages) if d != damage]
        return DamageBank(
            self.engine,
            tuple(self.damages[i] for i in keep),
            self.speeds[keep],
            self.missing,
        )

    def hypotheses(self, use: bool, leave_out: Damage | None = None) -> np.ndarray | None:
        """
        Return the speeds a run weighs (None when ``use``, MboaConfig.use_bank, is off).

        ``leave_out``: a damage dropped from them (the run's own, as damage the bank lacks).
        """
        if not use:
            return None
        return (self if leave_out is None else self.without(leave_out)).speeds

    def explain(self) -> str:
        """Say what a run weighs, or how to make a bank if there is none."""
        if len(self) == 0:
            return (
                'no damage bank is cached for this map (python -m'
                ' hexapod_adapt.online.ceilings_cli --archive MAP --cache-dir DIR makes one; DIR:'
                ' the prior cache)'
            )
        return f'weighing {self.describe()}'

    def describe(self) -> str:
        """Say what the bank holds, e.g. ``21 damage hypotheses on mujoco``."""
        text = f'{len(self)} damage hypotheses on {self.engine}'
        pending = [d for d, row in zip(self.damages, self.speeds) if np.isnan(row).any()]
        if pending:
            text += f' ({len(pending)} not cached: each re-scored when a run names it)'
        elif self.missing:
            named = ', '.join(d.label for d in self.missing[:3])
            more = f' and {len(self.missing) - 3} more' if len(self.missing) > 3 else ''
            text += f' ({len(self.missing)} not cached: {named}{more})'
        return text


def load_bank(
    archive: Archive,
    engine: str,
    dirs: Sequence[str | os.PathLike],
    damages: Sequence[Damage] = BANK_DAMAGES,
    rescore_missing: bool = False,
) -> DamageBank:
    """
    Return the bank of ``archive`` on ``engine``: each of ``damages`` cached in ``dirs``.

    ``rescore_missing``: a damage not cached is a hypothesis too, its row NaN (re-scored when a
    run names it); else it is left out. Either way it is listed in ``missing``.
    """
    found, speeds, missing = [], [], []
    n = len(archive.elite_indices())
    for damage in damages:
        c = cached_ceiling(archive, damage, engine, dirs)
        if c is None:
            missing.append(damage)
            if not rescore_missing:
                continue
        found.append(damage)
        # in elite order: the key's map digest covers the niches
        speeds.append(np.full(n, np.nan) if c is None else c.speeds)
    return DamageBank(
        engine,
        tuple(found),
        np.array(speeds, dtype=float).reshape(len(found), n),
        tuple(missing),
    )


def load_diagnosis_banks(
    archive: Archive,
    engine: str,
    dirs: Sequence[str | os.PathLike],
    bank: str = DEFAULT_DIAGNOSIS_BANK,
    rescore_when_named: bool = RESCORE_WHEN_NAMED,
) -> tuple[DamageBank, DamageBank | None]:
    """Return the diagnosis bank ``bank`` of ``archive`` and its wider one (:func:`load_banks`)."""
    first, wider = diagnosis_damages(bank)
    return load_banks(archive, engine, dirs, first, wider, rescore_when_named)


def load_banks(
    archive: Archive,
    engine: str,
    dirs: Sequence[str | os.PathLike],
    first: Sequence[Damage],
    wider: Sequence[Damage] | None,
    rescore_when_named: bool = RESCORE_WHEN_NAMED,
) -> tuple[DamageBank, DamageBank | None]:
    """
    Return the banks of ``first`` and ``wider`` damages of ``archive`` (:func:`load_bank`).

    ``rescore_when_named``: both weigh their damages not cached too, each re-scored when a run
    names it, so a map with no ceilings cached is diagnosed all the same (its first gait is then
    chosen by the map's own speeds where a hypothesis has no row).
    """
    return load_bank(archive, engine, dirs, first, rescore_when_named), (
        None if wider is None else load_bank(archive, engine, dirs, wider, rescore_when_named)
    )
