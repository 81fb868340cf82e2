# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Loading what navigate plans over: the repertoire, its damage bank and the specialists (ROS-free).

One place that says, never raises, why a file is not used: navigate_node and run_navigation
both load through :func:`load_navigation`.
"""

from __future__ import annotations

from dataclasses import dataclass
import os

from hexapod_adapt import ArchiveError, load_archive
from hexapod_navigation.core.repertoire import Repertoire
from hexapod_navigation.core.specialists import with_specialists
from hexapod_navigation.core.step_bank import load_step_bank, StepBank
import numpy as np


@dataclass(frozen=True)
class NavigationData:
    """A repertoire and its damage bank as loaded, with why either is missing."""

    repertoire: Repertoire | None
    bank: StepBank | None
    problem: str  # why there is no repertoire ('' if there is one)
    no_bank: str  # why there is no bank ('' if there is one)
    specialists: int = 0  # steps of gaits made for a damage, appended to both
    no_specialists: str = ''  # why there are none, when they were asked for

    def notes(self, use_bank: bool, use_specialists: bool) -> list[tuple[bool, str]]:
        """Return what a node logs of this (each: whether it is a warning, the text)."""
        found = self.repertoire is not None
        notes = []
        if self.bank is not None:
            notes.append((False, f'damage bank: {len(self.bank)} damage hypotheses'))
        elif found and use_bank:
            notes.append((True, f'no damage bank, the GP learns alone: {self.no_bank}'))
        if self.specialists:
            notes.append((False, f'{self.specialists} steps of gaits made for a damage'))
        elif found and use_specialists:
            notes.append((True, f'no gaits made for a damage: {self.no_specialists}'))
        return notes


def load_navigation(
    repertoire_path: str | os.PathLike,
    bank_path: str | os.PathLike,
    specialists_path: str | os.PathLike | None = None,
    max_tilt: float = np.pi,
) -> NavigationData:
    """
    Load a repertoire and the damage bank made for it; a bad file is said, never raised.

    ``specialists_path``: gaits made for the bank's damages
    (:mod:`hexapod_navigation.core.specialists`), appended to the repertoire and the bank when they
    were measured under the bank's damages (those whose step never tilts the body more than
    ``max_tilt`` rad under any); otherwise left out, and ``no_specialists`` says why.
    """
    try:
        repertoire = Repertoire.from_archive(load_archive(repertoire_path))
    except ArchiveError as exc:
        return NavigationData(None, None, f'no navigation repertoire: {exc}', '')
    bank, why = load_step_bank(bank_path, repertoire, repertoire.engine)
    if specialists_path is None:
        return NavigationData(repertoire, bank, '', why)
    if bank is None:
        return NavigationData(repertoire, bank, '', why, 0, 'no damage bank to weigh them with')
    repertoire, bank, count, no = with_specialists(repertoire, bank, specialists_path, max_tilt)
    return NavigationData(repertoire, bank, '', why, count, no)
