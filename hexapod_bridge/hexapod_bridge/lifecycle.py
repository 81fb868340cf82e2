# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
bridge_node as a managed (lifecycle) node, as nav2's and transport_drivers' hardware nodes are.

- configure: open the radio (and IMU) port; a port that cannot be opened fails the transition
  with the reason, and the node stays unconfigured, ready to be configured again;
- activate: arm (the bridge transmits);
- deactivate: stop the trial in progress and disarm (the robot stops, the bridge is silent);
- cleanup: close the ports; shutdown: the same from any state; an error: the same, to
  unconfigured.

A port that vanishes while the node is active (a radio unplugged) is not a transition: the node
stays active, says so on /diagnostics, and reopens the port when it comes back.
``autostart`` configures the node at start-up (retrying every ``AUTOSTART_RETRY_S`` s while the
port cannot be opened), and ``arm_on_start`` activates it then; with ``autostart`` false a
lifecycle manager (or ``ros2 lifecycle set``) drives it.
"""

from __future__ import annotations

from dataclasses import fields, replace
import time

from diagnostic_msgs.msg import DiagnosticStatus
from hexapod_bridge.station import BaseStation, StationConfig
from rclpy.lifecycle import State, TransitionCallbackReturn

#: s between configure attempts while autostart waits for the port.
AUTOSTART_RETRY_S = 1.0
#: Lifecycle state ids (lifecycle_msgs/State) the node's services look at.
UNCONFIGURED, INACTIVE, ACTIVE = 1, 2, 3


class BridgeLifecycle:
    """Mixed into bridge_node: it has ``values`` (its parameters) and the station's callbacks."""

    station: BaseStation | None = None

    def start_lifecycle(self) -> None:
        """Configure (and activate) at start-up as ``autostart`` and ``arm_on_start`` say."""
        self._autostart_timer = None
        if self.values['autostart']:
            self._try_autostart()

    def _try_autostart(self) -> None:
        if self._state_id() == UNCONFIGURED:
            self.trigger_configure()
        if self._state_id() == UNCONFIGURED:  # the port is not there yet: try again
            if self._autostart_timer is None:
                self._autostart_timer = self.create_timer(AUTOSTART_RETRY_S, self._try_autostart)
            return
        if self._autostart_timer is not None:
            self._autostart_timer.cancel()
            self._autostart_timer = None
        if self.values['arm_on_start'] and self._state_id() == INACTIVE:
            self.trigger_activate()

    def _state_id(self) -> int:
        # rclpy (Jazzy) has no public getter: its own trigger_shutdown reads this the same way
        return self._state_machine.current_state[0]

    def state_label(self) -> str:
        """Return the lifecycle state's name, e.g. 'unconfigured'."""
        return self._state_machine.current_state[1]

    def on_configure(self, state: State) -> TransitionCallbackReturn:
        v = self.values
        config = StationConfig(**{f.name: v[f.name] for f in fields(StationConfig)})
        try:  # armed only by activate
            station = BaseStation(
                replace(config, arm_on_start=False),
                on_imu=self._publish_imu,
                on_attitude=self._publish_attitude,
                on_connection=self._on_connection,
                log_error=self.get_logger().error,
            )
        except ValueError as exc:
            self.get_logger().error(f'configure failed: {exc}')
            return TransitionCallbackReturn.FAILURE
        ports = [(station.radio, 'radio')] + (
            [(station.imu_port, 'IMU')] if station.imu_port else []
        )
        for port, what in ports:
            if not port.ensure_open(time.monotonic()):
                self.get_logger().error(
                    f'configure failed: the {what} port: {port.last_error}; the node stays'
                    ' unconfigured (configure it again once the port is there)'
                )
                for opened, _ in ports:
                    opened.close()
                self.link_problem = f'{what} port: {port.last_error}'
                self.diagnostics.publish_now()
                return TransitionCallbackReturn.FAILURE
        self.station, self.link_problem = station, ''
        station.start()
        self.get_logger().info(
            f'configured: radio on {v["port"]} at {v["baud"]} baud, firmware {v["firmware"]},'
            f' IMU {"on " + str(v["imu_port"]) if v["imu_port"] else "from robot telemetry"};'
            ' disarmed until activated'
        )
        self.upload_pending()
        self.diagnostics.publish_now()
        # bridge/status holds a line from the start (a recording opens with the latest one)
        self._status(DiagnosticStatus.OK, f'configured: radio on {v["port"]}, disarmed')
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state: State) -> TransitionCallbackReturn:
        self.station.arm(True)
        self.get_logger().info('active: armed, transmitting; the robot checks its servos')
        self.check_servos_soon()  # before the first trial: a dead servo is known at once
        self.diagnostics.publish_now()
        return super().on_activate(state)

    def on_deactivate(self, state: State) -> TransitionCallbackReturn:
        self._halt()
        self.get_logger().info('inactive: the trial stopped, disarmed (silent)')
        self.diagnostics.publish_now()
        return super().on_deactivate(state)

    def on_cleanup(self, state: State) -> TransitionCallbackReturn:
        self._release()
        self.get_logger().info('unconfigured: ports closed')
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state: State) -> TransitionCallbackReturn:
        self._halt()
        self._release()
        return TransitionCallbackReturn.SUCCESS

    def on_error(self, state: State) -> TransitionCallbackReturn:
        self._halt()
        self._release()
        self.get_logger().error('a transition failed unexpectedly: ports closed, unconfigured')
        return TransitionCallbackReturn.SUCCESS

    def _halt(self) -> None:
        """Stop the trial in progress and disarm (nothing is transmitted after it)."""
        if self.station is not None:
            if self.station.armed:  # whether or not a trial runs: the robot stops
                self.station.stop_trial()
            self.station.arm(False)

    def _release(self) -> None:
        if self.station is not None:
            self.station.stop()
            self.station = None
        if self.diagnostics is not None:
            self.diagnostics.publish_now()
