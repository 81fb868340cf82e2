# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
MCAP recording: real rclpy CDR and ros2msg schemas, read back by mcap_ros2 too.

The file stays readable after the writing process is killed.
"""

import signal
import subprocess
import sys
import textwrap

from hexapod_msgs.msg import AdaptationTrial
from hexapod_util.recording import McapRecorder, read_messages, RecordingClosed, schema_text
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from nav_msgs.msg import Odometry
import pytest


def test_schema_carries_every_nested_definition():
    text = schema_text('hexapod_msgs/msg/AdaptationTrial')
    for nested in (
        'MSG: std_msgs/Header',
        'MSG: builtin_interfaces/Time',
        'MSG: hexapod_msgs/GaitParameters',
    ):
        assert nested in text
    assert text.count('MSG: std_msgs/Header') == 1


def test_round_trip_through_our_reader_and_mcap_ros2(tmp_path):
    path = tmp_path / 'run.mcap'
    with McapRecorder(path) as rec:
        for i in range(3):
            m = AdaptationTrial(trial=i + 1, archive_index=10 * i, measured_speed=0.1 * i)
            m.descriptor = [0.5] * 6
            rec.record('adapt/trials', m)
        o = Odometry()
        o.pose.pose.position.x = 1.25
        rec.record('odom', o)
    ours = list(read_messages(path))
    assert [t for t, _, _ in ours] == ['adapt/trials'] * 3 + ['odom']
    assert [m.archive_index for t, m, _ in ours[:3]] == [0, 10, 20]
    with open(path, 'rb') as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        assert reader.get_summary() is not None  # finished: indexed
        decoded = [(c.topic, d) for _, c, _, d in reader.iter_decoded_messages()]
    assert decoded[1][1].trial == 2 and decoded[3][1].pose.pose.position.x == 1.25
    with pytest.raises(RecordingClosed):
        rec.record('odom', o)


def _killed_recording(path, trials: int, extra: int) -> None:
    """
    Run a writer that is killed with SIGKILL part-way through a trial.

    It records ``trials`` checkpointed trials (as adapt_node does), then ``extra`` messages of
    a trial in progress.
    """
    script = textwrap.dedent(f"""
        import time
        from hexapod_msgs.msg import AdaptationTrial
        from nav_msgs.msg import Odometry
        from hexapod_util.recording import McapRecorder
        rec = McapRecorder({str(path)!r})
        for i in range({trials}):
            for k in range(30):
                rec.record("odom", Odometry())
            rec.record("adapt/trials", AdaptationTrial(trial=i + 1))
            rec.checkpoint()
        for k in range({extra}):
            rec.record("odom", Odometry())
        print("written", flush=True)
        time.sleep(60)
    """)
    proc = subprocess.Popen([sys.executable, '-c', script], stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == 'written'
    proc.send_signal(signal.SIGKILL)
    proc.wait()


@pytest.mark.slow
def test_a_hard_killed_writer_keeps_every_completed_trial_and_recover_makes_it_indexed(tmp_path):
    from hexapod_util.recording import recover

    path = tmp_path / 'killed.mcap'
    _killed_recording(path, trials=5, extra=7)
    assert [m.trial for t, m, _ in read_messages(path) if t == 'adapt/trials'] == [1, 2, 3, 4, 5]
    with open(path, 'rb') as f:  # no summary: an indexed reader cannot use it
        with pytest.raises(Exception):
            list(make_reader(f).iter_messages())
    out = tmp_path / 'recovered.mcap'
    result = subprocess.run(
        [
            sys.executable,
            '-m',
            'hexapod_adapt.ros.recover_recording_cli',
            str(path),
            '--out',
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 0, result.stderr
    assert 'wrote' in result.stdout
    with open(out, 'rb') as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        summary = reader.get_summary()
        assert (
            summary is not None
            and summary.chunk_indexes
            and summary.statistics.message_count >= 155
        )
        trials = [
            d.trial for _, c, _, d in reader.iter_decoded_messages() if c.topic == 'adapt/trials'
        ]
    assert trials == [1, 2, 3, 4, 5]
    again = recover(out, tmp_path / 'twice.mcap')  # recovering a good file changes nothing
    assert again.messages == summary.statistics.message_count


def test_a_cleanly_closed_recording_is_chunked_indexed_and_summarised(tmp_path):
    with McapRecorder(tmp_path / 'clean.mcap') as rec:
        for i in range(4):
            rec.record('odom', Odometry())
            rec.record('adapt/trials', AdaptationTrial(trial=i + 1))
            rec.checkpoint()
    with open(tmp_path / 'clean.mcap', 'rb') as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        assert len(summary.chunk_indexes) >= 4 and summary.statistics.message_count == 8
        assert all(ci.message_index_offsets for ci in summary.chunk_indexes)
        assert len(list(reader.iter_messages(topics=['adapt/trials']))) == 4


def test_recordings_are_never_overwritten(tmp_path):
    from hexapod_util.recording import create_recording

    recorders = [create_recording(tmp_path) for _ in range(3)]  # three runs in the same second
    for i, rec in enumerate(recorders):
        rec.record('adapt/trials', AdaptationTrial(trial=i + 1))
        rec.close()
    assert len({r.path for r in recorders}) == 3
    assert sorted(m.trial for r in recorders for _, m, _ in read_messages(r.path)) == [1, 2, 3]
    with pytest.raises(FileExistsError):
        McapRecorder(recorders[0].path)


# -- recover_recording guards its input and its outputs (issue 32) ------------------------------
def _recover(*args, **kw) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, '-m', 'hexapod_adapt.ros.recover_recording_cli', *map(str, args)],
        capture_output=True,
        text=True,
        timeout=60,
        **kw,
    )


def _one_line(proc: subprocess.CompletedProcess) -> str:
    lines = [line for line in proc.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and 'Traceback' not in proc.stderr, proc.stderr
    return lines[0]


@pytest.mark.slow
def test_a_file_that_is_not_a_recording_is_refused_and_left_as_it_is(tmp_path):
    notes = tmp_path / 'notes.mcap'
    notes.write_text('my field notes: leg 3 sounded odd\n')
    before = notes.read_bytes()
    proc = _recover(notes)
    assert proc.returncode != 0
    assert 'is not an MCAP file' in _one_line(proc)
    assert notes.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ['notes.mcap']  # nothing written
    proc = _recover(notes, '--in-place')
    assert proc.returncode != 0 and notes.read_bytes() == before


@pytest.mark.slow
def test_by_default_a_copy_is_written_beside_the_input_which_is_untouched(tmp_path):
    path = tmp_path / 'killed.mcap'
    _killed_recording(path, trials=3, extra=5)
    before = path.read_bytes()
    proc = _recover(path)
    assert proc.returncode == 0, proc.stderr
    copy = tmp_path / 'killed.recovered.mcap'
    assert f'wrote {copy}' in proc.stdout and path.read_bytes() == before
    with open(copy, 'rb') as f:
        # every checkpointed trial; the messages after the last checkpoint died with the writer
        assert make_reader(f).get_summary().statistics.message_count == 3 * 31
    # the copy exists now: asked again, the command refuses to replace it ...
    copied = copy.read_bytes()
    proc = _recover(path)
    assert proc.returncode != 0 and 'already exists: --force' in _one_line(proc)
    assert copy.read_bytes() == copied
    # ... unless --force, which keeps the old one as NAME.bak
    assert _recover(path, '--force').returncode == 0
    assert (tmp_path / 'killed.recovered.mcap.bak').read_bytes() == copied


@pytest.mark.slow
def test_in_place_keeps_the_original_and_replaces_only_when_nothing_is_lost(tmp_path):
    path = tmp_path / 'killed.mcap'
    _killed_recording(path, trials=2, extra=4)
    before = path.read_bytes()
    proc = _recover(path, '--in-place')
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / 'killed.mcap.orig').read_bytes() == before
    with open(path, 'rb') as f:
        assert make_reader(f).get_summary().statistics.message_count == 2 * 31
    # a second --in-place would replace the kept original: refused
    proc = _recover(path, '--in-place')
    assert proc.returncode != 0 and 'killed.mcap.orig already exists' in _one_line(proc)


def test_in_place_refuses_when_the_copy_would_hold_fewer_messages(tmp_path):
    # a finished recording whose index counts more messages than its records still give (a
    # corrupted chunk): the copy would lose some, so the original stays
    path = tmp_path / 'damaged.mcap'
    with McapRecorder(path) as rec:
        for i in range(400):
            rec.record('odom', Odometry())
            if i % 100 == 99:
                rec.checkpoint()  # ends a chunk
    with open(path, 'rb') as f:
        second = make_reader(f).get_summary().chunk_indexes[1]
    data = bytearray(path.read_bytes())
    middle = second.chunk_start_offset + second.chunk_length // 2
    end = middle + 32
    data[middle:end] = b'\xff' * 32  # the second chunk's compressed data
    path.write_bytes(bytes(data))
    before = path.read_bytes()
    from hexapod_util.recording import readable_messages

    assert readable_messages(path) == 400
    proc = _recover(path, '--in-place')
    assert proc.returncode != 0, proc.stdout
    line = _one_line(proc)
    assert 'recovered 100 of the 400 messages' in line and 'left as it is' in line
    assert path.read_bytes() == before and not (tmp_path / 'damaged.mcap.orig').exists()


@pytest.mark.slow
def test_a_recording_still_being_written_is_refused(tmp_path):
    path = tmp_path / 'live.mcap'
    script = textwrap.dedent(f"""
        import time
        from nav_msgs.msg import Odometry
        from hexapod_util.recording import McapRecorder
        rec = McapRecorder({str(path)!r})
        rec.record("odom", Odometry())
        rec.checkpoint()
        print("recording", flush=True)
        time.sleep(60)
    """)
    proc = subprocess.Popen([sys.executable, '-c', script], stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == 'recording'
        before = path.read_bytes()
        refused = _recover(path, '--in-place')
        assert refused.returncode != 0
        assert f'still open for writing by process {proc.pid}' in _one_line(refused)
        assert path.read_bytes() == before
    finally:
        proc.kill()
        proc.wait()


def test_offered_qos_profiles_say_how_each_topic_is_offered():
    from hexapod_util.recording import offered_qos_yaml
    from hexapod_util.ros_glue import LATCHED, SENSOR
    import yaml

    latched = yaml.safe_load(offered_qos_yaml(LATCHED))[0]
    assert (latched['durability'], latched['reliability'], latched['depth']) == (1, 1, 1)
    assert latched['history'] == 1 and latched['deadline'] == {
        'sec': 9223372036,
        'nsec': 854775807,
    }
    sensor = yaml.safe_load(offered_qos_yaml(SENSOR))[0]
    assert (sensor['durability'], sensor['reliability']) == (2, 2)  # volatile, best effort
