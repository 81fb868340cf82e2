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
Services: ``~/report_distance``, ``~/forget``.
"""

from __future__ import annotations

from dataclasses import replace
import math
import os
import sys
import traceback

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.maps import shipped_ceilings
from hexapod_adapt.online import session
from hexapod_adapt.online.adaptation import adapt, TrialAborted
from hexapod_adapt.online.prior import damage_of_request, simulated_tilts, TipScreen
from hexapod_adapt.online.run_config import (
    ArchiveSlot,
    engine_note,
    RUN_SETTINGS,
    run_settings,
    SETTINGS,
    settings_problem,
)
from hexapod_adapt.online.streaming_prior import StreamingPrior
from hexapod_adapt.online.trials import MODES, OdomLog, TrialTiming, Waiter
from hexapod_adapt.ros.adapt_action import AdaptAction
from hexapod_adapt.ros.damage_reports import DamageReports
from hexapod_adapt.ros.graph_port import (
    duplicate_peers,
    GraphPort,
    qualified,
    RECORDED_TYPES,
    RecordedTopics,
    trial_msg,
)
from hexapod_adapt.ros.run_recording import RunRecording
from hexapod_gait import from_genotype
from hexapod_gait.ros_conversions import gait_to_msg
from hexapod_msgs.action import Adapt
from hexapod_msgs.msg import AdaptationTrial
from hexapod_msgs.srv import GetServoFailures, ReportDistance
from hexapod_util.diagnostics import DiagnosticsPublisher
from hexapod_util.health import ERROR, Health, OK, WARN
from hexapod_util.ros_glue import (
    declare,
    param_specs,
    run_node,
    TRIALS,
    unless_closing,
    watch_for_duplicates,
)
from rcl_interfaces.msg import SetParametersResult
import rclpy
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.node import Node

PARAMETERS = param_specs(SETTINGS)
#: How long a robot run waits for bridge_node's start-up check of every servo [s].
SERVO_CHECK_WAIT_S = 10.0


class AdaptNode(AdaptAction, DamageReports, Node):
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

        self.trials: session.TrialProcedure | None = None
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
        self.port = GraphPort(self, sim_name, bridge_name, self.odom, self.recording)
        self.port.wait = self.waiter.until
        self.recorded = RecordedTopics(self, self.recording)
        self.trial_pub = self.create_publisher(AdaptationTrial, 'adapt/trials', TRIALS)
        self.stream: StreamingPrior | None = None  # the last run's re-score (may still stream)
        work = ReentrantCallbackGroup()
        self.listen_for_damage(work)
        self.serve_adapt(work)
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
        self.end_goals()
        self.recording.stop()
        if self.stream is not None:
            self.stream.close()

    def _stream_for(self, archive, damage) -> StreamingPrior:
        """Return the re-score under ``damage``: the one still streaming, or a new one."""
        s = self.stream
        if s is None or s.archive is not archive or s.damage != damage or s.error or s.stopped:
            if s is not None:
                s.close()
            cache = os.path.expanduser(str(self._param('prior_cache_dir'))) or None
            workers, log = int(self._param('prior_workers')), self.get_logger().info
            self.stream = session.streaming_prior(
                archive, damage, cache, [shipped_ceilings()], workers, log
            )
        return self.stream

    # -- archive and parameters -------------------------------------------------------------
    def _on_set_parameters(self, params) -> SetParametersResult:
        for param in (p for p in params if p.name == 'archive'):
            busy = self.busy.locked() and self.slot.usable
            problem = 'an adaptation is running' if busy else self.slot.load(param.value)
            if problem:  # the old archive stays
                return SetParametersResult(successful=False, reason=problem)
        # the run defaults are checked by the same rules as a request's fields
        values = {name: self._param(name) for name in RUN_SETTINGS}
        values.update({param.name: param.value for param in params if param.name in RUN_SETTINGS})
        problem = settings_problem(values)
        return SetParametersResult(successful=not problem, reason=problem)

    # -- services ---------------------------------------------------------------------------
    def _on_report(self, request: ReportDistance.Request, response: ReportDistance.Response):
        problem = session.report_distance(self.trials, request.distance)
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
        try:  # a zero field means "the node's parameter"
            config, duration = run_settings(
                {n: getattr(request, n) or self._param(n) for n in RUN_SETTINGS}
            )
            config = replace(config, min_speed=float(self._param('min_speed')))
            named = damage_of_request(request)
            damage, source = self.known.for_run(named, bool(request.blind))
        except ValueError as exc:
            problem = problem or f'bad request: {exc}'
        problem = problem or self._duplicates()
        if problem:
            response.success, response.message = False, problem
            return
        auto = named is None and not request.blind  # the damage as reported
        run = session.RunRequest(config, duration, damage, source, auto)
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

    def _tell(self, handle, text: str) -> None:
        """Tell the operator: the log (a warning) and the goal's feedback (its ``note``)."""
        self.get_logger().warning(text)
        unless_closing(self, handle.publish_feedback, Adapt.Feedback(note=text))

    def _servo_check(self, tell) -> str:
        """
        Wait (bounded) for bridge_node's check of every servo; take its reports; say how it went.

        Before a run chooses blind or the prior on the robot, so that a servo dead at start-up is
        known before the first trial.
        """
        reports = self.servo_reports
        goal = self.goal

        def alive() -> bool:
            return rclpy.ok(context=self.context) and not goal.is_cancel_requested

        check, status, failures = reports.await_check(1.0, alive)
        if check == GetServoFailures.Response.CHECK_PENDING:
            tell(
                f"waiting for bridge_node's check of every servo ({status}; up to"
                f' {SERVO_CHECK_WAIT_S:g} s)'
            )
            check, status, failures = reports.await_check(SERVO_CHECK_WAIT_S, alive)
        for msg in failures:  # the bridge's own answer: confirmed
            self._on_servo_failure(msg)
        dead = ', '.join(f'servo {f.servo_id} (leg {f.leg} {f.joint})' for f in failures)
        if check == GetServoFailures.Response.CHECK_DONE:
            return f'servo check: {status}; ' + (f'dead: {dead}' if dead else 'none dead')
        return f'no servo check ({status}): a dead servo may be unknown' + (
            f'; reported dead: {dead}' if dead else ''
        )

    # -- a run ------------------------------------------------------------------------------
    def _run(
        self, archive: Archive, run: session.RunRequest, response: Adapt.Result, handle
    ) -> None:
        """
        Run one adaptation, M-BOA starting from the map re-scored under ``run.damage``.

        ``run.auto``: the damage is whatever is reported. In sim mode the simulator reports it at
        start-up (latched), and a request can come before that arrives: the run then waits for it
        as it waits for /clock, and takes the prior from it.
        """
        config, duration, damage, source = run.config, run.duration, run.damage, run.source
        record_dir = self._param('record_dir')
        timeout = float(self._param('trial_timeout'))
        warn = self.get_logger().warning
        settle = float(self._param('trial_settle'))
        bridge = self.port.bridge_trial() if self.mode != 'sim' else None
        duration, settle = session.trial_walk(self.mode, duration, settle, bridge, warn)
        timing = TrialTiming(duration, timeout, float(self._param('stand_still')), settle)
        self.port.gait_of = lambda niche: from_genotype(archive.genotypes[niche]).replace(
            archive_index=int(niche)
        )
        tell = lambda text: self._tell(handle, text)  # noqa: E731
        check = ''
        try:
            if run.auto and self.mode != 'sim':  # the robot's servo reports decide blind or prior
                check = self._servo_check(tell)
                damage, source = self.known.for_run(None, False)
            if self._param('use_sim_time'):
                # one time base: nothing is stamped or recorded before the first /clock arrives
                self.waiter.until(
                    lambda: self.get_clock().now().nanoseconds > 0,
                    timeout,
                    '/clock (is sim_node running?)',
                )
            if run.auto and self.mode == 'sim':
                # what the simulator holds now: a SetLegFailure just before this request may not
                # have reached us on sim/damage yet
                now = self.port.sim_damage(timeout)
                if now is None:
                    raise TrialAborted(
                        f'sim_node did not say its damage (get_damage) in {timeout:g} s'
                        ' (is sim_node running?)'
                    )
                self._on_sim_damage(now)
                damage, source = self.known.for_run(None, False)
        except TrialAborted as exc:
            response.success, response.message = False, f'run not started: {exc}'
            return
        if record_dir:
            path = self.recorded.start(record_dir, RECORDED_TYPES, warn)
            response.mcap_path = str(path.resolve()) if path else ''
        tip_guard = float(self._param('tip_guard'))
        self.trials = session.trial_procedure(
            self.mode, self.port, self.port.logs, self.waiter, timing, tell, tip_guard
        )
        note = engine_note(
            archive, self.port.sim_engine() if self.mode == 'sim' else 'the real robot'
        )
        self.get_logger().info(session.start_message(archive, config, timing, note))
        niches = archive.elite_indices()  # M-BOA's candidate index -> niche
        prior, prior_update, screen, response.prior = None, None, None, source
        if damage is not None:  # re-scored best gaits first; the rest streams in between trials
            stream = self._stream_for(archive, damage)
            prior, response.prior = session.first_prior(stream, source)
            prior_update = stream.update if prior is not None else None
        if prior is not None and tip_guard < math.pi:  # each gait walked again before its trial,
            # tilt recorded: one that tips there is never tried (a guard at pi is off)
            screen = TipScreen(simulated_tilts(archive, damage, stream.engine), tip_guard)
            response.prior += session.screen_note(screen)
        unless_closing(
            self, handle.publish_feedback,
            Adapt.Feedback(note=session.start_note(response.prior, check)),
        )  # fmt: skip
        self.get_logger().info(session.start_note(response.prior, check))

        def on_trial(trial, niche, opt) -> None:
            best = opt.best()  # None while every trial so far tipped
            best_niche, best_speed = (niches[best.index], best.measured) if best else (-1, 0.0)
            msg = trial_msg(trial, niche, best_niche, best_speed, archive)
            msg.header.stamp = self.get_clock().now().to_msg()
            msg.gait = gait_to_msg(self.port.gait_of(niche))
            msg.recording = self.recording.problem
            # a node shutting down publishes nothing more: the recording still takes the trial
            unless_closing(self, self.trial_pub.publish, msg)
            left = max(0, config.max_trials - trial.number)
            unless_closing(
                self, handle.publish_feedback, Adapt.Feedback(trial=msg, trials_left=left)
            )
            self.recording.record('adapt/trials', msg)
            self.recording.checkpoint()  # a completed trial survives a kill or power loss
            if trial.tipped:  # rclpy fixes a call site's severity: one call per severity
                self.get_logger().warning(session.trial_message(trial, niche))
            else:
                self.get_logger().info(session.trial_message(trial, niche))

        try:
            stop = lambda: handle.is_cancel_requested  # noqa: E731 - read at every trial
            extra = {'prior': prior, 'prior_update': prior_update, 'screen': screen}
            extra['on_veto'] = lambda niche, tilt: self.get_logger().info(
                session.veto_message(niche, tilt, tip_guard)
            )
            result = adapt(archive, self.trials, config, on_trial, stop, **extra)
        finally:
            self.recording.stop()
        response.success = result.success
        response.message = session.result_message(result, note, self.recording.problem)
        response.trials, response.elapsed = len(result.trials), result.elapsed
        if not rclpy.ok(context=self.context):  # Ctrl-C or SIGTERM mid-run: one line, no more
            line = session.shutdown_message(result)
            response.message = f'adapt_node shut down mid-run: {response.message}'
            # not the ROS logger: its /rosout publisher is gone, and rcl would add a line saying so
            print(f'{self.get_name()}: {line}', file=sys.stderr, flush=True)
            return
        if result.best_niche >= 0:
            response.best_archive_index = result.best_niche
            response.best_speed = result.best_speed
            response.best_gait = gait_to_msg(self.port.gait_of(result.best_niche))
            # leave the robot (or the simulator) walking the best gait found
            problem = self.port.leave_on(response.best_gait, timeout, upload=self.mode != 'sim')
            if problem:
                self.get_logger().error(f'could not upload the best gait: {problem}')
        self.get_logger().info(session.finish_message(result))


def main(args: list[str] | None = None) -> int:
    """Entry point of ``ros2 run hexapod_adapt adapt_node``."""
    return run_node(AdaptNode, args, num_threads=4, parameters=PARAMETERS)


if __name__ == '__main__':
    sys.exit(main())
