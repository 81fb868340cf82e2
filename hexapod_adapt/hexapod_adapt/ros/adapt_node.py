# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_adapt adapt_node``: Intelligent Trial & Error on the simulator or the robot.

Loads an archive (``archive``, by default the shipped default map; refused with the reason if it
does not fit) and runs M-BOA for each goal of its ``adapt`` action (one at a time). Each
trial's gait goes to gait_node + sim_node (mode ``sim``), bridge_node (``robot``) or the
operator's tape measure (``manual``):
:mod:`hexapod_adapt.online.trials`. A known damage (the request's, ``sim/damage`` or the bridge's
``servo_failures``) starts M-BOA from the map re-scored under it (``blind`` skips it). Publishes
``adapt/trials`` (also each goal's feedback) and records each run to MCAP in ``record_dir``.
Services: ``~/report_distance``, ``~/forget``, ``~/calibrate`` (:mod:`.gap_calibration`).
"""

from __future__ import annotations

from dataclasses import replace
import os
import sys
import traceback

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.maps import shipped_ceilings
from hexapod_adapt.online import run_messages as say
from hexapod_adapt.online.adaptation import AdaptationResult, TrialAborted
from hexapod_adapt.online.bank import DEFAULT_DIAGNOSIS_BANK, diagnosis_damages
from hexapod_adapt.online.prior import damage_of_request
from hexapod_adapt.online.run_config import (
    ArchiveSlot,
    engine_note,
    RUN_SETTINGS,
    run_settings,
    SETTINGS,
    settings_problem,
    with_defaults,
)
from hexapod_adapt.online.session import AdaptationSession, informed_start, run_session
from hexapod_adapt.online.streaming_prior import StreamingPriors
from hexapod_adapt.online.trials import GaitOf, MODES, OdomLog, TrialTiming, Waiter
from hexapod_adapt.ros.adapt_action import AdaptServer
from hexapod_adapt.ros.damage_reports import DamageReports
from hexapod_adapt.ros.gap_calibration import GapCalibrationService
from hexapod_adapt.ros.graph_port import (
    duplicate_peers,
    GraphPort,
    qualified,
    RECORDED_TYPES,
    RecordedTopics,
)
from hexapod_adapt.ros.run_recording import RunRecording
from hexapod_adapt.ros.trial_feed import TrialFeed
from hexapod_gait.ros_conversions import gait_to_msg
from hexapod_msgs.action import Adapt
from hexapod_msgs.srv import ReportDistance
from hexapod_util.diagnostics import DiagnosticsPublisher
from hexapod_util.guarded_logging import GuardedLogging
from hexapod_util.health import ERROR, Health, OK, WARN
from hexapod_util.ros_glue import (
    declare,
    param_specs,
    run_node,
    unless_closing,
    watch_for_duplicates,
)
from rcl_interfaces.msg import SetParametersResult
import rclpy
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.node import Node

PARAMETERS = param_specs(SETTINGS)


class AdaptNode(GuardedLogging, Node):
    """Run M-BOA over an archive for each goal of its ``adapt`` action."""

    def __init__(self) -> None:
        super().__init__('adapt_node')
        declare(self, PARAMETERS)
        self.mode = self._param('mode')
        # a bad mode or archive: the node runs, refusing every request with the reason
        self.slot = ArchiveSlot(self.mode, MODES)
        problem = self.slot.load(self._param('archive'))
        (self.get_logger().error if problem else self.get_logger().info)(self.slot.describe())
        self.add_on_set_parameters_callback(self._on_set_parameters)

        self.trials: say.TrialProcedure | None = None
        self.odom = OdomLog()
        self.recording = RunRecording(
            self.resolve_topic_name,
            lambda: self.get_clock().now().nanoseconds,
            self.get_logger().error,
        )
        sim_name = self._param('sim_node')
        bridge_name = self._param('bridge_node')
        self.peer = qualified(self, sim_name if self.mode == 'sim' else bridge_name)
        self.goal = None  # the goal being run (its cancel ends any wait within a poll)
        self.waiter = Waiter(
            lambda: rclpy.ok(context=self.context),
            self._duplicates,
            cancelled=lambda: self.goal is not None and self.goal.is_cancel_requested,
        )
        peers = (sim_name, bridge_name)
        self.port = GraphPort(self, peers, self.waiter.until, self.odom, self.recording)
        self.recorded = RecordedTopics(self, self.recording)
        self.feed = TrialFeed(self, self.recording, lambda s: self._say_vetoes(s, self._guard()))
        cache = os.path.expanduser(str(self._param('prior_cache_dir'))) or None
        try:
            bank, wider = diagnosis_damages(str(self._param('diagnosis_bank')))
        except ValueError as error:  # the node runs: blind runs weigh the default bank
            self.get_logger().error(
                f'diagnosis_bank: {error}; blind runs weigh the default, {DEFAULT_DIAGNOSIS_BANK}'
            )
            bank, wider = diagnosis_damages(DEFAULT_DIAGNOSIS_BANK)
        self.priors = StreamingPriors(
            cache,
            [shipped_ceilings()],
            int(self._param('prior_workers')),
            self.get_logger().info,
            bank=bank,
            wider=wider,
        )
        work = ReentrantCallbackGroup()
        self.action = AdaptServer(self, self._adapt, work)
        self.damage = DamageReports(self, self.mode, bridge_name, self.action.busy.locked, work)
        self.session: AdaptationSession | None = None  # the last run's
        self.gap = GapCalibrationService(
            self, self.priors, lambda: self.slot.archive, lambda: self.session,
            self.action.busy, work,
        )  # fmt: skip
        self.create_service(
            ReportDistance, '~/report_distance', self._on_report, callback_group=work
        )
        watch_for_duplicates(self, self.get_logger().error)
        self.run_status = (OK, 'idle')
        self.diagnostics = DiagnosticsPublisher(self, self._health)
        self.get_logger().info(f'adapt_node ready: mode {self.mode}; {self.slot.describe()}')

    def _param(self, name: str):
        return self.get_parameter(name).value

    def shutdown(self) -> None:
        """Ctrl-C / SIGTERM mid-run: finish the MCAP file (called by run_node)."""
        self.action.end_goals()
        self.recording.stop()
        self.priors.close()

    # -- archive and parameters -------------------------------------------------------------
    def _on_set_parameters(self, params) -> SetParametersResult:
        problem = ''  # a refused archive or calibration: the loaded one stays
        for param in (p for p in params if p.name == 'archive'):
            busy = self.action.busy.locked() and self.slot.usable
            problem = 'an adaptation is running' if busy else self.slot.load(param.value)
        problem = problem or self.gap.on_parameters(params)
        # the run defaults are checked by the same rules as a request's fields
        values = {name: self._param(name) for name in RUN_SETTINGS}
        values.update({param.name: param.value for param in params if param.name in RUN_SETTINGS})
        problem = problem or settings_problem(values)
        return SetParametersResult(successful=not problem, reason=problem)

    # -- services ---------------------------------------------------------------------------
    def _on_report(self, request: ReportDistance.Request, response: ReportDistance.Response):
        problem = say.report_distance(self.trials, request.distance)
        response.accepted = not problem
        response.message = problem or f'{request.distance:.3f} m recorded'
        return response

    def _duplicates(self) -> str:
        return duplicate_peers(self, self.peer)

    def _health(self) -> list[Health]:
        usable = OK if self.slot.archive is not None else ERROR
        hardware = f'adapt_node, {self.mode} mode'
        return [
            Health('map', usable, self.slot.describe(), 'behaviour-performance map'),
            Health('adaptation', *self.run_status, hardware),
        ]

    def _run_status(self, level: int, message: str) -> None:
        self.run_status = (level, message)
        self.diagnostics.publish_now()

    # -- a goal ------------------------------------------------------------------------------
    def _adapt(self, handle, response: Adapt.Result) -> None:
        """Check the goal, run it, and fill ``response``."""
        request = handle.request
        problem = self.slot.problem if self.slot.archive is None else ''
        try:
            fields = {n: getattr(request, n) for n in RUN_SETTINGS}
            config, duration = run_settings(
                with_defaults(fields, {n: self._param(n) for n in RUN_SETTINGS})
            )
            config = replace(config, min_speed=float(self._param('min_speed')))
            named = damage_of_request(request)
            damage, source = self.damage.known.for_run(named, bool(request.blind))
        except ValueError as exc:
            problem = problem or f'bad request: {exc}'
        problem = problem or self._duplicates()
        if problem:
            response.success, response.message = False, problem
            return
        auto = named is None and not request.blind  # the damage as reported
        run = say.RunRequest(config, duration, damage, source, auto)
        self._run_status(OK, f'adapting ({source or "blind"})')
        self.goal = handle
        try:
            self._run(self.slot.archive, run, response, handle)
        except Exception as exc:  # noqa: BLE001 - the goal must end and the node stay up
            self.get_logger().error(
                f'adaptation failed unexpectedly: {type(exc).__name__}: {exc}\n'
                f'{traceback.format_exc()}'
            )
            response.success = False
            response.message = f'internal error, run stopped: {type(exc).__name__}: {exc}'
        finally:
            self.goal = None
            self._run_status(OK if response.success else WARN, f'last run: {response.message}')

    def _tell(self, handle, text: str, warn: bool = True) -> None:
        """Tell the operator: the log (a warning, or info) and the goal's feedback (``note``)."""
        if warn:  # rclpy fixes a call site's severity: one call per severity
            self.get_logger().warning(text)
        else:
            self.get_logger().info(text)
        unless_closing(self, handle.publish_feedback, Adapt.Feedback(note=text))

    # -- a run ------------------------------------------------------------------------------
    def _run(self, archive: Archive, run: say.RunRequest, response: Adapt.Result, handle) -> None:
        """Run one adaptation: a session driven by trials through the graph, fed back."""
        timing = self._timing(run)
        tell = lambda text: self._tell(handle, text)  # noqa: E731
        try:
            check, damage, source = self._damage_now(run, timing.timeout, tell)
        except TrialAborted as exc:
            response.success, response.message = False, f'run not started: {exc}'
            return
        if record := self._param('record_dir'):
            path = self.recorded.start(record, RECORDED_TYPES, self.get_logger().warning)
            response.mcap_path = str(path.resolve()) if path else ''
        gaits, guard = say.archive_gaits(archive), self._guard()
        self.trials = say.trial_procedure(
            self.mode, gaits, self.port, self.port.logs, self.waiter, timing, tell, guard
        )
        engine = self.port.sim_engine() if self.mode == 'sim' else 'the real robot'
        note = engine_note(archive, engine)
        self.get_logger().info(say.start_message(archive, run.config, timing, note))
        # damage nobody told is named from the trials (in sim mode an auto run asks sim_node;
        # manual trials record nothing)
        diagnose = self._param('diagnose') and {'sim': not run.auto, 'robot': True}.get(self.mode)
        gap = self.gap.for_run(archive)  # what a diagnosis takes out of its hypotheses
        start = informed_start(archive, damage, source, self.priors, guard, diagnose=diagnose)
        response.prior = start.note
        gap = f'; {gap}' if gap and start.diagnosis is not None else ''
        self._tell(handle, say.start_note(start.note, check) + gap, warn=False)
        session = self.session = AdaptationSession(archive, run.config, start)
        try:
            result = run_session(
                session,
                self.trials,
                lambda trial, niche, _: self.feed(handle, session, gaits, trial, niche),
                lambda: handle.is_cancel_requested or not rclpy.ok(context=self.context),
            )
        finally:
            self._say_vetoes(session, guard)
            self.recording.stop()
        self._finish(result, note, gaits, response, timing.timeout)

    def _timing(self, run: say.RunRequest) -> TrialTiming:
        """Return how a run's trials walk and wait (a robot's: as bridge_node walks them)."""
        bridge = self.port.bridge_trial() if self.mode != 'sim' else None
        warn = self.get_logger().warning
        duration, settle = say.trial_walk(
            self.mode, run.duration, float(self._param('trial_settle')), bridge, warn
        )
        timeout = float(self._param('trial_timeout'))
        return TrialTiming(duration, timeout, float(self._param('stand_still')), settle)

    def _damage_now(self, run: say.RunRequest, timeout: float, tell) -> tuple:
        """Return (servo check, damage, its source) as the run starts; TrialAborted if not."""
        if self._param('use_sim_time'):
            # one time base: nothing is stamped or recorded before the first /clock arrives
            self.waiter.until(
                lambda: self.get_clock().now().nanoseconds > 0,
                timeout,
                '/clock (is sim_node running?)',
            )
        goal = self.goal

        def alive() -> bool:
            return rclpy.ok(context=self.context) and not goal.is_cancel_requested

        return self.damage.at_start(run, alive, tell, self.port.sim_damage, timeout)

    def _guard(self) -> float:
        return float(self._param('tip_guard'))

    def _say_vetoes(self, session: AdaptationSession, guard: float) -> None:
        said = rclpy.ok(context=self.context)  # shutting down mid-run: its one line says all
        for veto in session.new_vetoes() if said else ():
            self.get_logger().info(say.veto_message(veto.niche, veto.tilt, guard, veto.risk))

    def _finish(
        self, result: AdaptationResult, note: str, gaits: GaitOf, response, timeout: float
    ) -> None:
        """Fill the goal's result and leave the robot (or the simulator) on the best gait."""
        response.success = result.success
        response.message = say.result_message(result, note, self.recording.problem)
        response.trials, response.elapsed = len(result.trials), result.elapsed
        if not rclpy.ok(context=self.context):  # Ctrl-C or SIGTERM mid-run: one line, no more
            response.message = f'adapt_node shut down mid-run: {response.message}'
            self.get_logger().info(say.shutdown_message(result))  # on stderr: /rosout is gone
            return
        if result.best_niche >= 0:
            response.best_archive_index = result.best_niche
            response.best_speed = result.best_speed
            response.best_gait = gait_to_msg(gaits(result.best_niche))
            problem = self.port.leave_on(response.best_gait, timeout, upload=self.mode != 'sim')
            if problem:
                self.get_logger().error(f'could not upload the best gait: {problem}')
        self.get_logger().info(say.finish_message(result))


def main(args: list[str] | None = None) -> int:
    """Entry point of ``ros2 run hexapod_adapt adapt_node``."""
    return run_node(AdaptNode, args, num_threads=4, parameters=PARAMETERS)


if __name__ == '__main__':
    sys.exit(main())
