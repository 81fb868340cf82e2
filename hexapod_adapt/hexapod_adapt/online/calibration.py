# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A robot's gap to the map's engine, measured on the intact robot and kept in a file (ROS-free).

Before a mission an operator walks a few gaits on the intact robot (a short run); the diagnosis
of later blind runs then takes that robot's bias out of every simulated walk
(:class:`~hexapod_adapt.online.diagnosis.GapCalibration`). This module makes the calibration
from a run's recorded trials (:func:`gap_from_trials`) and writes and reads its file
(:func:`save_gap`, :func:`load_gap`): an ``.npz`` written atomically, keyed by the engine the
hypotheses are walked on, so a file made against another engine or robot model is refused.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Sequence

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.simulation import trial_walk_key
from hexapod_adapt.online.diagnosis import (
    calibrate_gap,
    feature_names,
    GapCalibration,
    HypothesisWalks,
    TrialRecord,
)
from hexapod_sim.damage import Damage
from hexapod_util.npz import float_array, json_array, read_npz, UnreadableFile, write_npz
import numpy as np

#: The file's layout; a file of another is refused.
FORMAT = 1


def gap_key(archive: Archive, engine: str) -> dict:
    """Return what a calibration against ``engine``'s walks of ``archive``'s gaits depends on."""
    return {'format': FORMAT, **trial_walk_key(archive, engine)}


def gap_from_trials(
    walks: HypothesisWalks, trials: Sequence[tuple[int, TrialRecord]]
) -> tuple[GapCalibration, int]:
    """
    Return the gap of ``trials`` (niche, record), walked by the intact robot, to ``walks``.

    Each gait is simulated intact on ``walks``' engine (the hypotheses' walks); a gait the
    engine cannot walk is left out. With the gaits it was measured on; ValueError when fewer
    than two remain.
    """
    observed, simulated = [], []
    for niche, record in trials:
        expected = walks(int(niche), Damage.lifted(()))
        if expected is not None:
            observed.append(record)
            simulated.append(expected)
    return calibrate_gap(observed, simulated), len(observed)


def save_gap(calibration: GapCalibration, path: str | os.PathLike, key: dict, gaits: int) -> Path:
    """Write ``calibration`` (measured on ``gaits`` gaits) to ``path`` atomically."""
    arrays = {
        'key': np.array(json.dumps(key, sort_keys=True)),
        'offset': calibration.offset,
        'noise': calibration.noise,
        'contacts': np.array(int(calibration.contacts)),
        'gaits': np.array(int(gaits)),
    }
    write_npz(path, arrays)
    return Path(path)


def load_gap(path: str | os.PathLike, key: dict) -> tuple[GapCalibration, int]:
    """
    Return the calibration in ``path`` and the gaits it was measured on.

    FileNotFoundError when there is none; ValueError (UnreadableFile for damaged bytes), saying
    what is wrong, for a file that is not a calibration or was made against another engine.
    """
    data = read_npz(path, ('key', 'offset', 'noise', 'contacts', 'gaits'))
    found = json_array(data['key'], f'{path}: key')
    if not isinstance(found, dict) or found.get('format') != FORMAT:
        raise UnreadableFile(f'{path}: not a gap calibration of format {FORMAT}')
    differ = sorted(k for k in key if found.get(k) != key[k])
    if differ:
        raise ValueError(
            f'{path} was measured against other walks ({", ".join(differ)} differ: made against'
            f' {found.get("engine")!r}, the map walks its hypotheses on {key["engine"]!r});'
            ' calibrate again'
        )
    if data['contacts'].shape != () or data['gaits'].shape != ():
        raise UnreadableFile(f'{path}: contacts and gaits must be single values')
    contacts = bool(float_array(data['contacts'], f'{path}: contacts'))
    gaits = float_array(data['gaits'], f'{path}: gaits')
    if not (np.isfinite(gaits) and gaits >= 2):
        raise UnreadableFile(f'{path}: a calibration is measured on two gaits or more')
    n = len(feature_names(contacts))
    offset = float_array(data['offset'], f'{path}: offset')
    noise = float_array(data['noise'], f'{path}: noise')
    try:
        calibration = GapCalibration(offset, noise, contacts)
    except ValueError as exc:
        raise UnreadableFile(f'{path}: {exc} ({n} features)') from None
    return calibration, int(gaits)
