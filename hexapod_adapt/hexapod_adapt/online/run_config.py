# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
What a run of adapt_node is configured by, checked without ROS.

The six run settings (a request's fields, else the node's parameters) and what an archive must
match to be used for trials in a mode.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
import math
import os

from hexapod_adapt.mapping.archive import (
    Archive,
    ArchiveError,
    compatibility_problems,
    load_archive,
)
from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
from hexapod_adapt.mapping.simulation import archive_engine, simulation_fingerprint
from hexapod_adapt.online.adaptation import DEFAULT_TIP_GUARD
from hexapod_adapt.online.bank import DEFAULT_DIAGNOSIS_BANK
from hexapod_adapt.online.mboa import (
    ALPHA_RANGE,
    DEFAULT_PROFILE,
    KAPPA_RANGE,
    LENGTH_SCALE_RANGE,
    MAX_TRIALS_LIMIT,
    MboaConfig,
    MIN_SPEED_RANGE,
    NOISE_RANGE,
    profile,
    STOP_GAIN_RANGE,
    TRIAL_BUDGET,
    TRIAL_DURATION,
    TRIAL_SETTLE,
)

#: The Adapt request's fields that default to the node's parameter of the same name.
RUN_SETTINGS = (
    'max_trials',
    'trial_duration',
    'alpha',
    'kappa',
    'length_scale',
    'noise',
    'stop_gain',
    'no_gain_stop',
    'profile',
)
#: Settings that override the profile's value when given. A request field or a node parameter
#: of 0 is "not given": :func:`given` turns it into None, the one place that reads 0 so.
PROFILE_SETTINGS = ('alpha', 'kappa', 'length_scale', 'noise', 'stop_gain')

#: A trial must cover at least one gait cycle of the controller's default 1 s period.
TRIAL_DURATION_RANGE = (1.0, 120.0)
TRIAL_SETTLE_RANGE = (0.0, 10.0)


@dataclass(frozen=True)
class Setting:
    """One of adapt_node's parameters: its default, what it means (units) and its range."""

    name: str
    default: object
    description: str
    range: tuple[float, float] | None = None  # noqa: A003 (inclusive)
    read_only: bool = False


_MBOA = MboaConfig()

#: adapt_node's parameters (the run settings default to M-BOA's own defaults).
SETTINGS = (
    Setting(
        'archive',
        '',
        "Archive file (.npz from generate_map; '' = the shipped default map); may be changed at "
        'run time, a file that fails to load is refused and the last good one kept',
    ),
    Setting('mode', 'sim', 'Trials on: sim | robot | manual', read_only=True),
    Setting(
        'max_trials',
        TRIAL_BUDGET,
        'Default maximum trials per run (24: 2 minutes of 5 s trials)',
        (1, MAX_TRIALS_LIMIT),
    ),
    Setting(
        'trial_duration',
        TRIAL_DURATION,
        "Default timed seconds of a sim-mode trial (robot and manual modes: bridge_node's"
        ' trial_duration) [s]',
        TRIAL_DURATION_RANGE,
    ),
    Setting(
        'trial_settle',
        TRIAL_SETTLE,
        'Sim mode: seconds a trial walks untimed before it is timed (0 = timed from standing,'
        " the thesis's trial and the default; robot and manual modes: bridge_node's"
        ' trial_settle) [s]',
        TRIAL_SETTLE_RANGE,
    ),
    Setting(
        'profile',
        DEFAULT_PROFILE,
        "M-BOA settings: 'default' (chosen on a tuning set) or 'thesis' (thesis 5.2.2); alpha, "
        'kappa, length_scale, noise and stop_gain override it when given (not 0)',
    ),
    Setting(
        'alpha',
        0.0,
        'Stop ratio: stop when the best measured speed reaches alpha x the highest predicted one '
        "(0 = the profile's; thesis 0.9)",
        (0.0, ALPHA_RANGE[1]),
    ),
    Setting(
        'kappa', 0.0, "UCB weight on the posterior std (0 = the profile's)", (0.0, KAPPA_RANGE[1])
    ),
    Setting(
        'length_scale',
        0.0,
        "Matern length scale rho [descriptor units] (0 = the profile's)",
        (0.0, LENGTH_SCALE_RANGE[1]),
    ),
    Setting(
        'noise',
        0.0,
        "Observation noise variance [(m/s)^2] (0 = the profile's)",
        (0.0, NOISE_RANGE[1]),
    ),
    Setting(
        'stop_gain',
        0.0,
        "Blind runs: success also needs the next trial's expected gain below this [m/s] (0 = the"
        " profile's: 0.002 in 'default', none in 'thesis')",
        (0.0, STOP_GAIN_RANGE[1]),
    ),
    Setting(
        'no_gain_stop',
        False,
        'true: no expected-gain stop, whatever the profile or stop_gain say (alpha and max_trials'
        ' alone, as in the thesis)',
    ),
    Setting(
        'min_speed',
        _MBOA.min_speed,
        'Success floor [m/s]: a run succeeds only if its best gait walks at least this fast (0 ='
        ' the thesis rule); below it the run goes on, or ends unsuccessful saying so',
        MIN_SPEED_RANGE,
    ),
    Setting(
        'prior_cache_dir',
        '~/.cache/hexapod_adapt/ceilings',
        'Damage-informed prior: where maps re-scored under a damage are cached (the shipped '
        "default map's S1-S4 are read from the package first)",
    ),
    Setting(
        'prior_workers',
        2,
        'Damage-informed prior, and a blind run naming a damage not cached: processes that'
        " re-score the map (one per core); a blind run's hypotheses are walked in as many",
        (1, 256),
    ),
    Setting(
        'record_dir',
        'adaptation_runs',
        "MCAP files go here; a relative path lies under ROS_HOME (~/.ros), as ROS 2's logs do"
        " ('' = no recording)",
    ),
    Setting('sim_node', 'sim_node', 'Name of the simulator node (mode sim)', read_only=True),
    Setting(
        'bridge_node',
        'bridge_node',
        'Name of the bridge node (modes robot, manual)',
        read_only=True,
    ),
    Setting('trial_timeout', 120.0, 'Wall-clock limit for one trial [s]', (1.0, 3600.0)),
    Setting(
        'tip_guard',
        DEFAULT_TIP_GUARD,
        'A sim or robot trial whose body tilts (roll or pitch) past this is stopped, the robot'
        ' stands, and the trial counts as 0 m/s; that gait is never tried again (3.1416 = off)'
        ' [rad]',
        (0.05, math.pi),
    ),
    Setting(
        'diagnose',
        True,
        'A run whose damage nobody told (robot mode: no servo report; sim mode: a blind'
        " request) names it from the trials among the map's cached damage bank, and goes on as"
        ' the prior of the damage named',
    ),
    Setting(
        'diagnosis_bank',
        DEFAULT_DIAGNOSIS_BANK,
        "What a blind run names its damage among: 'lifted' (each one- and two-leg set of S1-S4"
        " lifted, 21), 'every' (the 8 damage kinds on those legs, 168: names locked and"
        " unpowered joints too) or 'lifted-then-every' (every kind once no lifted leg fits the"
        ' trials); the cached ones of the map',
        read_only=True,
    ),
    Setting(
        'gap_calibration',
        '',
        "The robot's gap to the map's engine, taken out of blind runs' hypotheses: a file that"
        " ~/calibrate writes after a short run on the intact robot ('' = none); a file that is"
        " not a calibration of the map's engine is refused, the last good one kept",
    ),
    Setting(
        'stand_still',
        1.0,
        'Robot modes: seconds the robot stands still after an upload, before the trial: the '
        "robot's 0.5 s move to the gait's first pose plus the bridge's IMU rest window [s]",
        (0.0, 60.0),
    ),
)


def run_settings(values: dict) -> tuple[MboaConfig, float]:
    """
    (M-BOA configuration, trial duration [s]) from the run settings.

    The named ``profile`` gives every M-BOA setting; alpha, kappa, length_scale, noise and
    stop_gain replace its values when given (:func:`given`); ``no_gain_stop`` turns the
    expected-gain stop off. ValueError says which is out of range and what the range is.
    """
    duration = float(values['trial_duration'])
    low, high = TRIAL_DURATION_RANGE
    if not (math.isfinite(duration) and low <= duration <= high):
        raise ValueError(f'trial_duration must be in [{low:g}, {high:g}] s, got {duration!r}')
    base = profile(str(values.get('profile') or DEFAULT_PROFILE))
    chosen = {name: float(values[name]) for name in PROFILE_SETTINGS if given(values.get(name))}
    if values.get('no_gain_stop'):
        chosen['stop_gain'] = None
    config = replace(base, max_trials=int(values['max_trials']), **chosen)
    return config, duration


def with_defaults(request: dict, defaults: dict) -> dict:
    """Return the request's settings; each not given (:func:`given`) comes from ``defaults``."""
    return {name: value if given(value) else defaults[name] for name, value in request.items()}


def given(value: object) -> bool:
    """Whether a request field or node parameter was given: 0, '' and None mean "not given"."""
    return value not in (None, 0, 0.0, '')


def expected_metadata(mode: str) -> dict:
    """
    Return what an archive must match to be used in ``mode``: the gait mapping always.

    The URDF and trial duration too when trials run on the simulator. The engine that made the map
    need not be the trials' engine: that is a reality gap, which M-BOA exists to cross (see
    :func:`engine_note`).
    """
    fp = simulation_fingerprint()
    if mode != 'sim':
        return {'genotype_mapping': fp['genotype_mapping']}
    return {key: fp[key] for key in ('genotype_mapping', 'urdf_sha256', 'trial_duration')}


def engine_note(archive: Archive, trial_engine: str | None) -> str:
    """Say when the map was made on another engine than the trials run on ('' if not)."""
    made_on = archive_engine(archive.metadata) or 'an unrecorded engine'
    if trial_engine is None or made_on == trial_engine:
        return ''
    return f'map made on {made_on}, trials on {trial_engine}: adapting across that gap'


def archive_path(value: str) -> str:
    """Return the file an ``archive`` parameter names ('' = the shipped default map)."""
    return os.path.expanduser(value) if value else str(shipped_map(DEFAULT_MAP))


def load_for_mode(value: str, mode: str) -> tuple[Archive | None, str]:
    """Load what an ``archive`` parameter names: (archive, '') or (None, why it cannot be used)."""
    path = archive_path(value)
    try:
        archive = load_archive(path)
    except ArchiveError as exc:
        return None, str(exc)
    problems = compatibility_problems(archive, expected_metadata(mode))
    if problems:
        return None, f'{path} does not fit this installation: ' + '; '.join(problems)
    if archive.n_filled == 0:
        return None, f'{path} has no gaits'
    return archive, ''


class ArchiveSlot:
    """
    The archive a node adapts on, and why there is none; a bad new one leaves the last good one.

    ``mode`` is the node's (read-only) mode: an unknown one leaves the slot empty for good, with
    the reason, so that every request is refused and the node stays up.
    """

    def __init__(self, mode: str, modes: tuple[str, ...]) -> None:
        self.mode = mode
        self.archive: Archive | None = None
        self.problem = "no archive loaded: set the 'archive' parameter"
        self.usable = mode in modes
        if not self.usable:
            self.problem = (
                f'parameter mode must be one of {", ".join(modes)}, got {mode!r}; restart the node'
            )

    def load(self, value: str) -> str:
        """Load what an ``archive`` parameter names; return '' or why it was not taken."""
        if not self.usable:
            return self.problem
        archive, problem = load_for_mode(value, self.mode)
        if archive is None:
            if self.archive is None:
                self.problem = problem
            return problem
        self.archive, self.problem = archive, ''
        return ''

    def describe(self) -> str:
        """Return the archive's size, or why there is none."""
        if self.archive is None:
            return self.problem
        return f'archive: {self.archive.n_filled} gaits in {self.archive.n_niches} niches'


def settings_problem(values: dict) -> str:
    """Return why run settings (parameter values by name) are refused ('' if they are fine)."""
    try:
        run_settings(values)
    except (TypeError, ValueError) as exc:
        return str(exc)
    return ''
