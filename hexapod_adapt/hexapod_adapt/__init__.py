# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
MAP-Elites map generation and M-BOA adaptation for the hexapod: the public, ROS-free API.

What other packages (navigation, the studies) use is exported here; the ROS side the nodes share
is exported by :mod:`hexapod_adapt.ros`. The nodes and commands are adapt_node, adapt_client,
generate_map and run_experiment.
"""

from hexapod_adapt.mapping.archive import Archive, ArchiveError, import_thesis_map, load_archive
from hexapod_adapt.mapping.map_elites import Evaluation, MapElitesConfig, run_map_elites
from hexapod_adapt.mapping.maps import shipped_ceilings, shipped_map
from hexapod_adapt.mapping.simulation import (
    archive_engine,
    DEFAULT_MAP_ENGINE,
    engine_of_map,
    worker_simulator,
)
from hexapod_adapt.mapping.steps import (
    from_descriptor,
    gait_min_stance,
    REACH,
    repertoire_fingerprint,
)
from hexapod_adapt.online.adaptation import AdaptationResult, simulated_trial, TrialAborted
from hexapod_adapt.online.bank import BANK_DAMAGES
from hexapod_adapt.online.ceiling import cached_ceiling, map_digest
from hexapod_adapt.online.experiment import run_experiment
from hexapod_adapt.online.mboa import Mboa, MboaConfig, mixture
from hexapod_adapt.online.prior import damage_of_request, KnownDamage
from hexapod_adapt.online.run_config import Setting
from hexapod_adapt.online.session import adapt, AdaptationSession, SessionStart
from hexapod_adapt.online.trials import OdomLog, SampleLog, Waiter

__all__ = [
    'AdaptationResult',
    'AdaptationSession',
    'Archive',
    'ArchiveError',
    'BANK_DAMAGES',
    'DEFAULT_MAP_ENGINE',
    'Evaluation',
    'KnownDamage',
    'MapElitesConfig',
    'Mboa',
    'MboaConfig',
    'OdomLog',
    'REACH',
    'SampleLog',
    'SessionStart',
    'Setting',
    'TrialAborted',
    'Waiter',
    'adapt',
    'archive_engine',
    'cached_ceiling',
    'damage_of_request',
    'engine_of_map',
    'from_descriptor',
    'gait_min_stance',
    'import_thesis_map',
    'load_archive',
    'map_digest',
    'mixture',
    'repertoire_fingerprint',
    'run_experiment',
    'run_map_elites',
    'shipped_ceilings',
    'shipped_map',
    'simulated_trial',
    'worker_simulator',
]
