# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
MAP-Elites map generation and M-BOA adaptation for the hexapod.

ROS-free library; the nodes and commands are adapt_node, adapt_client, generate_map and
run_experiment.
"""

from hexapod_adapt.mapping.archive import Archive, ArchiveError, import_thesis_map, load_archive
from hexapod_adapt.mapping.map_elites import Evaluation, MapElitesConfig, run_map_elites
from hexapod_adapt.online.adaptation import (
    adapt,
    AdaptationResult,
    run_experiment,
    simulated_trial,
    TrialAborted,
)
from hexapod_adapt.online.mboa import Mboa, MboaConfig

__all__ = [
    'AdaptationResult',
    'Archive',
    'ArchiveError',
    'Evaluation',
    'MapElitesConfig',
    'Mboa',
    'MboaConfig',
    'TrialAborted',
    'adapt',
    'import_thesis_map',
    'load_archive',
    'run_experiment',
    'run_map_elites',
    'simulated_trial',
]
