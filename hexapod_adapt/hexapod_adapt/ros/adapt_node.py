# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
"""
``ros2 run hexapod_adapt adapt_node``: Intelligent Trial & Error on the simulator or the robot.

Loads an archive (``archive`` parameter, by default the shipped default map; refused, with the
reason, if its genotype mapping -- and in ``sim`` mode its URDF and trial duration -- differ from
this installation's) and runs M-BOA when its ``adapt`` service is called. Each trial publishes the
gait on ``gait/parameters`` and measures its speed along the walking direction, through
gait_node + sim_node (mode ``sim``), through bridge_node's IMU odometry (``robot``) or by the
operator's tape measure (``manual``): :mod:`hexapod_adapt.trials` says how.

When the damage is known -- the request's ``failed_legs``, the simulator's ``sim/damage`` (mode
``sim``) or the bridge's ``servo_failures`` (robot modes) -- the map is first re-scored in
simulation under it, and M-BOA starts from that prior (:mod:`hexapod_adapt.prior`; the request's
``blind`` skips it).

Publishes ``adapt/trials`` (AdaptationTrial) per trial and records each run (trials, gaits,
odometry) to an MCAP file in ``record_dir`` (:mod:`hexapod_adapt.run_recording`: a recording
problem never stops a run). Services: ``adapt`` (hexapod_msgs/Adapt), ``~/report_distance``
(hexapod_msgs/ReportDistance), ``~/cancel`` (std_srvs/Trigger).
"""

from __future__ import annotations

from dataclasses import replace
import os
import sys
import threading
import time
import traceback

from hexapod_adapt.adaptation import adapt, TrialAborted
from hexapod_adapt.archive import Archive
from hexapod_adapt.graph_port import (
    GraphPort,
    qualified,
    RECORDED_TYPES,
    RecordedTopics,
    trial_msg,
)
from hexapod_adapt.maps import shipped_ceilings
from hexapod_adapt.mboa import MboaConfig
from hexapod_adapt.prior import damage_prior, KnownDamage
from hexapod_adapt.run_config import (
    engine_note,
    load_for_mode,
    RUN_SETTINGS,
    run_settings,
    SETTINGS,
)
from hexapod_adapt.run_recording import RunRecording
from hexapod_adapt.simulation import archive_engine
from hexapod_adapt.trials import (
    ManualTrials,
    MODES,
    OdomLog,
    reported_distance_problem,
    RobotTrials,
    SimTrials,
    TrialTiming,
    Waiter,
)
from hexapod_gait import from_genotype
from hexapod_gait.ros_conversions import gait_to_msg
from hexapod_gait.ros_glue import (
    declare,
    EVENTS,
    LATCHED,
    nodes_named,
    ParamSpec,
    run_node,
    watch_for_duplicates,
)
from hexapod_msgs.msg import AdaptationTrial, LegDamage, ServoFailure
from hexapod_msgs.srv import Adapt, ReportDistance
from hexapod_sim.damage import Damage
from rcl_interfaces.msg import SetParametersResult
import rclpy
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.node import Node
from std_srvs.srv import Trigger

#: How long a recorded run waits at its start for the URDF and static frames (latched topics).
LATCHED_GRACE_S = 5.0

PARAMETERS = tuple(
    ParamSpec(x.name, x.default, x.description, read_only=x.read_only, range=x.range)
    for x in SETTINGS
)


class AdaptNode(Node):
    """Run M-BOA over an archive when its ``adapt`` service is called."""

    def __init__(self) -> None:
        super().__init__('adapt_node')
        declare(self, PARAMETERS)
        self.mode = self.get_parameter('mode').value
        self.archive: Archive | None = None
        self.archive_problem = "no archive loaded: set the 'archive' parameter"
        if self.mode not in MODES:
            # read-only parameter: the node runs, refusing every request with the reason
            self.archive_problem = (
                f'parameter mode must be one of {", ".join(MODES)}, got {self.mode!r}; restart the'
                ' node'
            )
            self.get_logger().error(self.archive_problem)
        else:
            self._load_archive(self.get_parameter('archive').value)
        self.add_on_set_parameters_callback(self._on_set_parameters)

        self.busy = threading.Lock()
        self.cancel_requested = False
        self.trials: ManualTrials | SimTrials | RobotTrials | None = None
        self.odom = OdomLog()
        self.recording = RunRecording(
            self.resolve_topic_name,
            lambda: self.get_clock().now().nanoseconds,
            self.get_logger().error,
        )
        sim_name = self.get_parameter('sim_node').value
        bridge_name = self.get_parameter('bridge_node').value
        self.peer = qualified(self, sim_name if self.mode == 'sim' else bridge_name)
        self.waiter = Waiter(lambda: rclpy.ok(context=self.context), self._duplicate_peers)
        self.port = GraphPort(self, sim_name, bridge_name, self.odom, self.recording)
        self.port.wait = self.waiter.until
        self.recorded = RecordedTopics(self, self.recording)
        self.trial_pub = self.create_publisher(AdaptationTrial, 'adapt/trials', 10)
        self.known = KnownDamage()
        if self.mode == 'sim':
            self.create_subscription(LegDamage, 'sim/damage', self._on_sim_damage, LATCHED)
        else:
            self.create_subscription(
                ServoFailure, 'servo_failures', self._on_servo_failure, EVENTS
            )
        work = ReentrantCallbackGroup()
        self.create_service(Adapt, 'adapt', self._on_adapt, callback_group=work)
        self.create_service(
            ReportDistance, '~/report_distance', self._on_report, callback_group=work
        )
        self.create_service(Trigger, '~/cancel', self._on_cancel, callback_group=work)
        watch_for_duplicates(self, self.get_logger().error)
        self.get_logger().info(
            f'adapt_node ready: mode {self.mode}; '
            + (f'archive {self.archive.n_filled} gaits' if self.archive else self.archive_problem)
        )

    def shutdown(self) -> None:
        """Ctrl-C / SIGTERM mid-run: finish the MCAP file (called by run_node)."""
        self.recording.stop()

    # -- archive and parameters -------------------------------------------------------------
    def _load_archive(self, value: str) -> None:
        archive, problem = load_for_mode(value, self.mode)
        if archive is None:
            self.archive_problem = problem
            self.get_logger().error(problem)
        else:
            self.archive, self.archive_problem = archive, ''
            self.get_logger().info(
                f'archive: {archive.n_filled} gaits in {archive.n_niches} niches'
            )

    def _on_set_parameters(self, params) -> SetParametersResult:
        for param in params:
            if param.name == 'archive':
                if self.mode not in MODES:
                    return SetParametersResult(successful=False, reason=self.archive_problem)
                if self.busy.locked():
                    return SetParametersResult(successful=False, reason='an adaptation is running')
                archive, problem = load_for_mode(param.value, self.mode)
                if archive is None:  # the old archive stays
                    return SetParametersResult(successful=False, reason=problem)
                self.archive, self.archive_problem = archive, ''
        # the run defaults are checked by the same rules as a request's fields
        values = {name: self.get_parameter(name).value for name in RUN_SETTINGS}
        values.update({param.name: param.value for param in params if param.name in RUN_SETTINGS})
        try:
            run_settings(values)
        except (TypeError, ValueError) as exc:
            return SetParametersResult(successful=False, reason=str(exc))
        return SetParametersResult(successful=True)

    # -- services ---------------------------------------------------------------------------
    def _on_report(self, request: ReportDistance.Request, response: ReportDistance.Response):
        trials = self.trials
        if isinstance(trials, ManualTrials):
            problem = trials.report(request.distance)
        else:
            problem = reported_distance_problem(request.distance) or (
                'no manual trial is waiting for a distance'
            )
        response.accepted = not problem
        response.message = problem or f'{request.distance:.3f} m recorded'
        return response

    def _on_sim_damage(self, msg: LegDamage) -> None:
        self.get_logger().info(
            self.known.from_sim(list(msg.failed_legs), list(msg.kinds), list(msg.strengths))
        )

    def _on_servo_failure(self, msg: ServoFailure) -> None:
        self.get_logger().warning(self.known.from_servo(int(msg.servo_id), int(msg.leg)))

    def _on_cancel(self, request, response):
        running = self.busy.locked()
        self.cancel_requested = running
        response.success = running
        response.message = (
            'cancelling after the current trial' if running else 'no adaptation is running'
        )
        return response

    def _duplicate_peers(self) -> str:
        """Say why a run must stop: this node's or its peer's name is taken twice ('' if not)."""
        for name in (self.get_fully_qualified_name(), self.peer):
            count = nodes_named(self, name)
            if count > 1:
                return (
                    f'{count} nodes named {name} are in the graph: trials would be ambiguous; stop'
                    ' the extra one (or rename it with --ros-args -r __node:=NAME) and call adapt'
                    ' again'
                )
        return ''

    def _on_adapt(self, request: Adapt.Request, response: Adapt.Response):
        response.best_archive_index = -1
        if self.archive is None:
            response.success, response.message = False, self.archive_problem
            return response
        try:  # a zero field means "the node's parameter"
            config, duration = run_settings(
                {n: getattr(request, n) or self.get_parameter(n).value for n in RUN_SETTINGS}
            )
            config = replace(config, min_speed=float(self.get_parameter('min_speed').value))
            damage, source = self.known.for_run(list(request.failed_legs), bool(request.blind))
        except ValueError as exc:
            response.success, response.message = False, f'bad request: {exc}'
            return response
        duplicates = self._duplicate_peers()
        if duplicates:
            response.success, response.message = False, duplicates
            return response
        if not self.busy.acquire(blocking=False):
            response.success, response.message = False, 'an adaptation is already running'
            return response
        auto = not request.failed_legs and not request.blind  # the damage as reported
        try:
            return self._run(self.archive, config, duration, response, damage, source, auto)
        except Exception as exc:  # noqa: BLE001 - the service must answer and the node stay up
            self.get_logger().error(
                f'adaptation failed unexpectedly: {type(exc).__name__}: {exc}\n'
                f'{traceback.format_exc()}'
            )
            response.success = False
            response.message = f'internal error, run stopped: {type(exc).__name__}: {exc}'
            return response
        finally:
            self.cancel_requested = False
            self.busy.release()

    # -- a run ------------------------------------------------------------------------------
    def _trial_function(self, timing: TrialTiming):
        warn = self.get_logger().warning
        if self.mode == 'sim':
            return SimTrials(self.port, self.odom, self.waiter, timing, warn)
        if self.mode == 'robot':
            return RobotTrials(self.port, self.odom, self.waiter, timing)
        return ManualTrials(self.port, self.waiter, timing, warn)

    def _trial_walk(self, duration: float) -> tuple[float, float]:
        """
        Return (timed, settling) seconds of this run's trials.

        Sim mode: ``duration`` and ``trial_settle``. On the robot, what bridge_node is set to
        walk (one home for it); ``duration`` from standing if it does not say.
        """
        if self.mode == 'sim':
            return duration, float(self.get_parameter('trial_settle').value)
        bridge = self.port.bridge_trial()
        log = self.get_logger().warning
        if bridge is None:
            log(
                'bridge_node did not say how it walks a trial (its trial_duration and'
                f' trial_settle): assuming {duration:g} s from standing'
            )
            return duration, 0.0
        if abs(bridge[0] - duration) > 1e-6:
            log(
                f'trials of {duration:g} s were asked for, but bridge_node walks {bridge[0]:g} s'
                ' timed: its trial_duration is used (set it on bridge_node to change a robot'
                ' trial)'
            )
        return bridge

    def _prior(self, archive: Archive, damage: Damage | None, source: str):
        """Re-score the map under ``damage`` (None: the map as it is); return (speeds, text)."""
        if damage is None:
            return None, source
        engine = archive_engine(archive.metadata) or 'mujoco'
        log = self.get_logger().info
        log(
            f'damage-informed prior from {source}: re-scoring {archive.n_filled} gaits on {engine}'
        )
        t0, shown = time.monotonic(), [0.0]

        def progress(done: int, total: int) -> None:
            if time.monotonic() - shown[0] >= 5.0 or done == total:
                shown[0] = time.monotonic()
                log(
                    f're-scoring the map: {done}/{total} gaits ({100 * done / total:.0f} %),'
                    f' {time.monotonic() - t0:.0f} s'
                )

        prior = damage_prior(
            archive,
            damage,
            engine,
            os.path.expanduser(str(self.get_parameter('prior_cache_dir').value)) or None,
            read_dirs=[shipped_ceilings()],
            workers=int(self.get_parameter('prior_workers').value),
            progress=progress,
        )
        return prior.speeds, f'{prior.describe()}, from {source}'

    def _run(
        self,
        archive: Archive,
        config: MboaConfig,
        duration: float,
        response: Adapt.Response,
        damage: Damage | None = None,
        source: str = '',
        auto: bool = False,
    ) -> Adapt.Response:
        """
        Run one adaptation; ``damage`` and ``source``: its prior (see :meth:`_prior`).

        ``auto``: the damage is whatever is reported. In sim mode the simulator reports it at
        start-up (latched), and a request can come before that arrives: the run then waits for it
        as it waits for /clock, and takes the prior from it.
        """
        record_dir = self.get_parameter('record_dir').value
        timeout = float(self.get_parameter('trial_timeout').value)
        duration, settle = self._trial_walk(duration)
        timing = TrialTiming(
            duration, timeout, float(self.get_parameter('stand_still').value), settle
        )
        self.port.gait_of = lambda niche: from_genotype(archive.genotypes[niche]).replace(
            archive_index=int(niche)
        )
        if self.get_parameter('use_sim_time').value:
            # one time base: nothing is stamped or recorded before the first /clock arrives
            try:
                self.waiter.until(
                    lambda: self.get_clock().now().nanoseconds > 0,
                    timeout,
                    '/clock (is sim_node running?)',
                )
            except TrialAborted as exc:
                response.success, response.message = False, f'run not started: {exc}'
                return response
        if auto and self.mode == 'sim':
            # what the simulator holds now: a SetLegFailure just before this request may not
            # have reached us on sim/damage yet (an older sim_node: wait for the topic instead)
            now = self.port.sim_damage(timeout)
            if now is not None:
                self._on_sim_damage(now)
            try:
                self.waiter.until(
                    lambda: self.known.sim is not None,
                    timeout,
                    "the simulator's damage report, sim/damage (is sim_node running?)",
                )
            except TrialAborted as exc:
                response.success, response.message = False, f'run not started: {exc}'
                return response
            damage, source = self.known.for_run([], False)
        if record_dir:
            left = self.recorded.await_latched(LATCHED_GRACE_S)
            if left:
                self.get_logger().warning(
                    f'recording starts without {", ".join(left)}: nothing received in '
                    f'{LATCHED_GRACE_S:g} s (is a state publisher running?); it is recorded if it '
                    'comes during the run'
                )
            path = self.recording.start(record_dir, RECORDED_TYPES)
            response.mcap_path = str(path.resolve()) if path else ''
        self.trials = self._trial_function(timing)
        note = engine_note(
            archive, self.port.sim_engine() if self.mode == 'sim' else 'the real robot'
        )
        self.get_logger().info(
            f'adaptation started: {archive.n_filled} gaits, at most {config.max_trials} trials '
            f'of {timing.duration:g} s'
            + (f' after {timing.settle:g} s of settling' if timing.settle else '')
            + f', alpha {config.alpha:g}, kappa {config.kappa:g}'
            + (f'; {note}' if note else '')
        )
        niches = archive.elite_indices()  # M-BOA's candidate index -> niche
        prior, response.prior = self._prior(archive, damage, source)
        self.get_logger().info(f'M-BOA starts from {response.prior}')

        def on_trial(trial, niche, opt) -> None:
            msg = trial_msg(trial, niche, niches[opt.best().index], opt.best().measured, archive)
            msg.header.stamp = self.get_clock().now().to_msg()
            msg.gait = gait_to_msg(self.port.gait_of(niche))
            msg.recording = self.recording.problem
            self.trial_pub.publish(msg)
            self.recording.record('adapt/trials', msg)
            self.recording.checkpoint()  # a completed trial survives a kill or power loss
            self.get_logger().info(
                f'trial {trial.number}: gait {niche} walked {trial.measured:.3f} m/s '
                f'(map {trial.predicted:.3f}, GP {trial.gp_mean:.3f} +/- {trial.gp_std:.3f})'
            )

        try:
            result = adapt(
                archive,
                self.trials,
                config,
                on_trial,
                lambda: self.cancel_requested,
                prior=prior,
            )
        finally:
            self.recording.stop()
        response.success, response.message = result.success, result.message
        if note:
            response.message += f' ({note})'
        if self.recording.problem:
            response.message += f'; recording: {self.recording.problem}'
        response.trials, response.elapsed = len(result.trials), result.elapsed
        if result.best_niche >= 0:
            response.best_archive_index = result.best_niche
            response.best_speed = result.best_speed
            response.best_gait = gait_to_msg(self.port.gait_of(result.best_niche))
            self._leave_on_best_gait(response.best_gait, timeout)
        self.get_logger().info(
            f'adaptation finished: {result.message}; {len(result.trials)} trials, best gait '
            f'{result.best_niche} at {result.best_speed:.3f} m/s'
        )
        return response

    def _leave_on_best_gait(self, msg, timeout: float) -> None:
        """Leave the robot (or the simulator) walking the best gait found."""
        problem = self.port.leave_on(msg, timeout, upload=self.mode != 'sim')
        if problem:
            self.get_logger().error(f'could not upload the best gait: {problem}')


def main(args: list[str] | None = None) -> int:
    """Entry point of ``ros2 run hexapod_adapt adapt_node``."""
    return run_node(AdaptNode, args, num_threads=4, parameters=PARAMETERS)


if __name__ == '__main__':
    sys.exit(main())
