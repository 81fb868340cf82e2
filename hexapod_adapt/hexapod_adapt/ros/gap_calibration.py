# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
adapt_node's gap calibration: the ``gap_calibration`` file and the ``~/calibrate`` service.

An operator walks a short run on the intact robot, then calls ``~/calibrate``: the trials of
that run, against the same gaits walked intact on the map's engine, measure the robot's gap to
the engine (:mod:`hexapod_adapt.online.calibration`). It is written to ``gap_calibration`` and
every later blind run's diagnosis takes it out of its hypotheses. The file is read at start-up
and when the parameter changes; a file that is not a calibration of the map's engine is refused
with the reason and the last good one kept.
"""

from __future__ import annotations

import os
from pathlib import Path
import threading
from typing import Callable

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.simulation import engine_of_map
from hexapod_adapt.online.calibration import gap_from_trials, gap_key, load_gap, save_gap
from hexapod_adapt.online.diagnosis import GapCalibration, TrialRecord
from hexapod_adapt.online.session import AdaptationSession
from hexapod_adapt.online.streaming_prior import StreamingPriors
from rclpy.callback_groups import CallbackGroup
from rclpy.node import Node
from std_srvs.srv import Trigger


def _path(value: str) -> Path | None:
    return Path(os.path.expanduser(value)) if value else None


class GapCalibrationService:
    """
    The calibration ``priors``' blind runs use, kept in the file ``gap_calibration`` names.

    ``archive()`` is the node's map (None: none loaded), ``last_session()`` its last run, and
    ``busy`` the lock a run holds: ``~/calibrate`` is refused while a run holds it, and holds it
    while it calibrates (a goal then is refused as busy).
    """

    def __init__(
        self,
        node: Node,
        priors: StreamingPriors,
        archive: Callable[[], Archive | None],
        last_session: Callable[[], AdaptationSession | None],
        busy: threading.Lock,
        work: CallbackGroup,
    ) -> None:
        self.node, self.priors, self.archive = node, priors, archive
        self.last_session, self.busy = last_session, busy
        self.path: Path | None = None
        self.loaded: tuple[GapCalibration, dict, int] | None = None  # calibration, key, gaits
        node.create_service(Trigger, '~/calibrate', self._on_calibrate, callback_group=work)
        problem = self.load(str(node.get_parameter('gap_calibration').value))
        if problem:  # the node runs: blind runs go uncalibrated
            node.get_logger().error(f'{problem}; blind runs go uncalibrated')

    def on_parameters(self, params) -> str:
        """Take a new ``gap_calibration`` among ``params``; return the problem ('' if none)."""
        for param in (p for p in params if p.name == 'gap_calibration'):
            return self.load(str(param.value))
        return ''

    def load(self, value: str) -> str:
        """Take the file ``value`` names ('' = none); return the problem ('' if none)."""
        path, archive = _path(value), self.archive()
        if path is None or archive is None or not path.exists():
            self.path, self.loaded = path, None  # a file yet to be made by ~/calibrate
            return ''
        key = gap_key(archive, engine_of_map(archive))
        try:
            calibration, gaits = load_gap(path, key)
        except (OSError, ValueError) as exc:
            return f'gap_calibration: {exc}'
        self.path, self.loaded = path, (calibration, key, gaits)
        return ''

    def for_run(self, archive: Archive) -> str:
        """Set the calibration a run on ``archive`` uses; return what to tell ('' if none)."""
        self.priors.calibration = None
        if self.loaded is None and self.path is not None and self.path.exists():
            problem = self.load(str(self.path))  # made since, or the map came later
            if problem:
                return f'{problem}: not used'
        if self.loaded is None:
            return ''
        calibration, key, gaits = self.loaded
        if key != gap_key(archive, engine_of_map(archive)):
            return f"the gap calibration {self.path} is not of this map's engine: not used"
        self.priors.calibration = calibration
        return f'the diagnosis takes out the gap calibrated on {gaits} intact gaits ({self.path})'

    def _on_calibrate(self, _request, response: Trigger.Response) -> Trigger.Response:
        response.success = False
        if not self.busy.acquire(blocking=False):
            response.message = 'an adaptation is running: calibrate after it'
            return response
        try:
            session = self.last_session()
            trials = session.recorded_trials() if session is not None else []
            response.message = self._refusal(session, trials)
            if not response.message:
                self._calibrate(response, trials)
        finally:
            self.busy.release()
        return response

    def _calibrate(
        self, response: Trigger.Response, trials: list[tuple[int, TrialRecord]]
    ) -> None:
        archive = self.archive()
        try:
            calibration, used = gap_from_trials(self.priors.walks(archive), trials)
        except ValueError as exc:
            response.message = f'cannot calibrate from the last run: {exc}'
            return
        key = gap_key(archive, engine_of_map(archive))
        try:
            save_gap(calibration, self.path, key, used)
        except OSError as exc:
            response.message = f'cannot write {self.path}: {exc}'
            return
        self.loaded = (calibration, key, used)
        speed = float(calibration.offset[0])
        response.success = True
        response.message = (
            f'calibrated on {used} gaits of the last run, taken as walks of the intact'
            f' robot: written to {self.path} (speed offset {speed:+.3f} m/s); blind runs take it'
            ' out of their hypotheses'
        )
        self.node.get_logger().info(response.message)

    def _refusal(
        self, session: AdaptationSession | None, trials: list[tuple[int, TrialRecord]]
    ) -> str:
        """Return why ``~/calibrate`` cannot run on ``session``'s ``trials`` ('' if it can)."""
        if self.path is None:
            return "set the parameter gap_calibration to the file to write (it is '')"
        if self.archive() is None:
            return 'no map is loaded'
        if session is None or session.archive is not self.archive():
            return 'no run on this map yet: walk a short run on the intact robot first'
        if len(trials) < 2:
            return (
                f'the last run recorded {len(trials)} trial(s) that did not tip'
                ' (manual trials record none): a calibration needs two or more'
            )
        return ''
