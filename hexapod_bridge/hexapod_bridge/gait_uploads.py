# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""bridge_node's gait uploads: each ``gait/parameters`` (latched), and ``~/upload_gait``."""

from __future__ import annotations

import math
import threading
import time

from diagnostic_msgs.msg import DiagnosticStatus
from hexapod_bridge.link import Operation
from hexapod_bridge.station import LINK_LOST_S
from hexapod_gait.parameters import GaitParameterError
from hexapod_gait.ros_conversions import gait_from_msg
from hexapod_msgs.msg import GaitParameters as GaitParametersMsg
from hexapod_msgs.srv import UploadGait


class GaitUploads:
    """Mixed into bridge_node: it has ``station`` (None unconfigured), ``_status``, ``_alive``."""

    def _on_gait(self, msg: GaitParametersMsg) -> None:
        try:
            gait = gait_from_msg(msg)
        except GaitParameterError as exc:
            self._status(DiagnosticStatus.ERROR, f'gait not uploaded: {exc}')
            return
        station = self.station
        if station is None:  # kept: uploaded once the node is configured
            self.pending_gait = msg
            self._status(DiagnosticStatus.WARN, 'gait kept; it is uploaded once configured')
            return
        op = station.upload(gait)
        if op.done and not op.ok:
            self._status(DiagnosticStatus.ERROR, f'gait not uploaded: {op.message}')
            return
        if not station.armed:
            self._status(
                DiagnosticStatus.WARN, 'gait queued; it is uploaded once the bridge is armed'
            )
        threading.Thread(target=self._finish_upload, args=(station, op, gait), daemon=True).start()

    def upload_pending(self) -> None:
        """Upload the gait that came before the node was configured (if one did)."""
        msg, self.pending_gait = self.pending_gait, None
        if msg is not None:
            self._on_gait(msg)

    def _finish_upload(self, station, op: Operation, gait) -> None:
        station.wait(op, math.inf, lambda: self.station is station)  # until its link closes
        if op.ok:
            station.uploaded(op, gait)
            self.commanded.set_gait(gait)
            self._status(
                DiagnosticStatus.OK,
                f'gait uploaded (archive index {gait.archive_index})',
                gait_id=op.result['gait_id'],
                archive_index=gait.archive_index,
            )
        elif op.done:
            self._status(DiagnosticStatus.ERROR, f'gait upload failed: {op.message}')

    def _on_upload_gait(self, request: UploadGait.Request, response: UploadGait.Response):
        """Upload and answer once the robot acknowledged (or refused) it: the typed contract."""
        response.archive_index = request.gait.archive_index
        timeout = request.timeout if 0 < request.timeout <= 600 else 30.0  # NaN: the default
        try:
            gait = gait_from_msg(request.gait)
        except GaitParameterError as exc:
            response.success, response.message = False, f'gait not uploaded: {exc}'
            return response
        if self.station is None:
            response.success, response.message = False, 'not configured: configure it first'
            return response
        if not self.station.armed:
            response.success, response.message = False, 'not armed: call ~/arm first'
            return response
        station, began = self.station, time.monotonic()
        op = station.upload(gait)

        def link_works() -> bool:  # a lost link ends the wait once it was given LINK_LOST_S
            now = time.monotonic()
            return now - began < LINK_LOST_S or not station.link_problem(now)

        if not station.wait(op, timeout, lambda: self._alive() and link_works()):
            problem = station.link_problem(time.monotonic())
            waited = time.monotonic() - began
            response.success, response.message = (
                False,
                f'gait not uploaded: no answer in {waited:.1f} s'
                + (f' ({problem})' if problem else ''),
            )
            station.abandon(op, response.message)  # not sent later, behind a newer upload
            return response
        response.answered = not op.unanswered  # a refusal, or retries that ran out unheard
        if not op.ok:
            response.success, response.message = False, f'gait not uploaded: {op.message}'
            self._status(DiagnosticStatus.ERROR, response.message)
            return response
        self.station.uploaded(op, gait)
        self.commanded.set_gait(gait)
        response.success, response.gait_id = True, int(op.result['gait_id'])
        response.message = f'gait uploaded as robot gait {response.gait_id}'
        self._status(
            DiagnosticStatus.OK,
            f'{response.message} (archive index {gait.archive_index})',
            gait_id=response.gait_id,
            archive_index=gait.archive_index,
        )
        return response
