# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""bridge_node's lifecycle against robot_emulator over pseudo-terminals."""

from __future__ import annotations

import json
import os
import time

from conftest import wait_for
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from hexapod_gait import preset
from hexapod_gait.ros_conversions import gait_to_msg
from hexapod_msgs.msg import GaitParameters as GaitParametersMsg
from hexapod_util.ros_glue import LATCHED
from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState, GetState
import pytest
from std_srvs.srv import Trigger

pytestmark = pytest.mark.ros


def _link(diagnostics: list) -> list:
    """The radio link's statuses on /diagnostics, oldest first."""
    return [s for a in diagnostics for s in a.status if s.name == 'bridge_node: radio link']


def test_every_lifecycle_transition_and_a_missing_or_vanishing_port(ros, launch, tmp_path):
    radio, imu = str(tmp_path / 'radio'), str(tmp_path / 'imu')
    node = launch('hexapod_bridge', 'bridge_node', params={'port': radio, 'autostart': False})
    diagnostics = ros.collect(DiagnosticArray, '/diagnostics', 50)

    def state() -> str:
        return ros.call(GetState, 'bridge_node/get_state', GetState.Request()).current_state.label

    def change(transition: int) -> bool:
        request = ChangeState.Request(transition=Transition(id=transition))
        return ros.call(ChangeState, 'bridge_node/change_state', request, timeout=30).success

    def trigger(name: str):
        return ros.call(Trigger, f'bridge_node/{name}', Trigger.Request(), timeout=30)

    assert state() == 'unconfigured'
    refused = trigger('start_trial')
    assert not refused.success and 'unconfigured' in refused.message
    # a port that does not exist: configure fails with the reason, the node stays unconfigured
    assert not change(Transition.TRANSITION_CONFIGURE)
    assert state() == 'unconfigured' and node.alive()
    wait_for(lambda: 'configure failed: the radio port' in node.log(), 10, 'the reason logged')
    wait_for(
        lambda: any('No such file' in s.message for s in _link(diagnostics)), 10, 'diagnostics'
    )
    # the port comes: configure again; inactive is silent
    emu = launch(
        'hexapod_bridge',
        'robot_emulator',
        args=['--radio-link', radio, '--imu-link', imu, '--sim'],
    )
    wait_for(lambda: os.path.exists(radio), 60, "the emulator's port")
    assert change(Transition.TRANSITION_CONFIGURE) and state() == 'inactive'
    refused = trigger('start_trial')
    assert not refused.success and 'not armed' in refused.message
    # active: armed, a gait uploaded and a trial walking
    assert change(Transition.TRANSITION_ACTIVATE) and state() == 'active'
    pub = ros.node.create_publisher(GaitParametersMsg, 'gait/parameters', LATCHED)
    pub.publish(gait_to_msg(preset('tripod').replace(archive_index=3)))
    wait_for(lambda: 'gait uploaded' in node.log(), 30, 'the upload')
    started = trigger('start_trial')
    assert started.success, started.message
    time.sleep(1.5)
    # deactivate: the robot stops (its walk ends before its 5 s), the bridge disarms
    assert change(Transition.TRANSITION_DEACTIVATE) and state() == 'inactive'
    wait_for(lambda: 'TRIAL ' in emu.log(), 20, "the emulator's report of the walk")
    walk = json.loads(emu.log().split('TRIAL ', 1)[1].splitlines()[0])
    assert walk['state'] == 'stopped', walk  # not 'done': it did not walk its 5 s
    assert 'inactive: the trial stopped, disarmed' in node.log()
    # cleanup closes the ports; configure and activate work again
    assert change(Transition.TRANSITION_CLEANUP) and state() == 'unconfigured'
    wait_for(lambda: _link(diagnostics)[-1].message.startswith('no link'), 10, 'no link')
    assert change(Transition.TRANSITION_CONFIGURE) and change(Transition.TRANSITION_ACTIVATE)
    assert state() == 'active'
    # the port vanishes while active: the node stays active and says so; it is not a transition
    emu.stop()
    wait_for(lambda: _link(diagnostics)[-1].level == DiagnosticStatus.ERROR, 10, 'the link down')
    assert state() == 'active' and node.alive()
    # shutdown from active: finalized, the node process still answers
    assert change(Transition.TRANSITION_ACTIVE_SHUTDOWN) and state() == 'finalized'
    assert node.alive()
