# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The recording policy of a run.

Latched messages first, missing definitions refused by name, and no recording problem ever
reaching the run.
"""

from __future__ import annotations

import os

from hexapod_adapt.ros.run_recording import RunRecording
from hexapod_msgs.msg import AdaptationTrial
from hexapod_util.recording import read_messages, schema_text, SchemaUnavailable
from nav_msgs.msg import Odometry
import pytest
from std_msgs.msg import String

TYPES = {
    'robot_description': 'std_msgs/msg/String',
    'odom': 'nav_msgs/msg/Odometry',
    'adapt/trials': 'hexapod_msgs/msg/AdaptationTrial',
}


def _recording(errors: list[str]) -> RunRecording:
    clock = iter(range(1, 10**6))
    return RunRecording(lambda topic: '/' + topic.lstrip('/'), lambda: next(clock), errors.append)


def test_a_missing_definition_names_the_type_and_package():
    with pytest.raises(SchemaUnavailable) as info:
        schema_text('no_such_pkg/msg/Thing')
    assert info.value.type_name == 'no_such_pkg/msg/Thing'
    assert "package 'no_such_pkg' is not in the ament index" in str(info.value)


def test_a_run_starts_with_the_latched_messages_and_records_the_rest(tmp_path):
    errors: list[str] = []
    rec = _recording(errors)
    rec.on_latched('robot_description', String(data='<robot/>'))
    rec.record('odom', Odometry())  # no run: nothing recorded, nothing raised
    path = rec.start(tmp_path, TYPES)
    rec.record('odom', Odometry())
    rec.record('adapt/trials', AdaptationTrial(trial=1))
    rec.checkpoint()
    rec.stop()
    topics = [topic for topic, _, _ in read_messages(path)]
    assert topics == ['/robot_description', '/odom', '/adapt/trials']
    assert rec.problem == '' and errors == []


def test_a_type_without_a_definition_is_refused_at_the_start_and_the_rest_recorded(tmp_path):
    errors: list[str] = []
    rec = _recording(errors)
    path = rec.start(tmp_path, {**TYPES, 'odom': 'no_such_pkg/msg/Odometry'})
    assert path is not None
    assert rec.problem.startswith('not recording odom: no definition of no_such_pkg/msg/Odometry')
    assert errors and 'no_such_pkg' in errors[0]
    rec.record('odom', Odometry())  # refused topic: skipped, never raises
    rec.record('adapt/trials', AdaptationTrial(trial=1))
    rec.stop()
    assert [topic for topic, _, _ in read_messages(path)] == ['/adapt/trials']


def test_a_type_not_declared_is_refused_when_it_comes(tmp_path, monkeypatch):
    import hexapod_util.recording as recording

    errors: list[str] = []
    rec = _recording(errors)
    path = rec.start(tmp_path, {'adapt/trials': TYPES['adapt/trials']})
    real = recording.schema_text

    def missing_nav_msgs(name):
        if name.startswith('nav_msgs/'):
            raise SchemaUnavailable(name, "package 'nav_msgs' is not in the ament index")
        return real(name)

    monkeypatch.setattr(recording, 'schema_text', missing_nav_msgs)
    rec.record('odom', Odometry())  # the node's defect: this raised in the odometry callback
    rec.record('adapt/trials', AdaptationTrial(trial=2))
    rec.stop()
    assert 'not recording odom' in rec.problem and 'nav_msgs' in rec.problem
    assert [topic for topic, _, _ in read_messages(path)] == ['/adapt/trials']


def test_an_unwritable_directory_disables_recording_with_the_reason(tmp_path):
    errors: list[str] = []
    rec = _recording(errors)
    blocker = tmp_path / 'file'
    blocker.write_text('not a directory')
    assert rec.start(blocker / 'runs', TYPES) is None
    assert rec.problem.startswith(f'cannot record in {blocker / "runs"}')
    rec.record('odom', Odometry())  # nothing open: nothing happens
    rec.checkpoint()
    rec.stop()
    assert not rec.recording and len(errors) == 1


def test_a_write_failure_mid_run_ends_the_recording_not_the_run(tmp_path):
    errors: list[str] = []
    rec = _recording(errors)
    path = rec.start(tmp_path, TYPES)
    rec.record('adapt/trials', AdaptationTrial(trial=1))
    rec.checkpoint()
    os.close(rec._recorder._file.fileno())  # the disk goes away under the writer
    rec.checkpoint()
    assert not rec.recording and 'recording stopped' in rec.problem
    rec.record('adapt/trials', AdaptationTrial(trial=2))  # ignored, never raises
    rec.stop()
    assert [m.trial for _, m, _ in read_messages(path)] == [1]
    rec.start(tmp_path, TYPES)
    assert rec.problem == '' and rec.recording  # the next run records again
    rec.stop()
