"""MCAP recording: real rclpy CDR + ros2msg schemas, read back by mcap_ros2 too, and readable
after the writing process is killed."""
import signal
import subprocess
import sys
import textwrap

import pytest
from hexapod_msgs.msg import AdaptationTrial
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from nav_msgs.msg import Odometry

from hexapod_adapt.recording import McapRecorder, read_messages, schema_text


def test_schema_carries_every_nested_definition():
    text = schema_text("hexapod_msgs/msg/AdaptationTrial")
    for nested in ("MSG: std_msgs/Header", "MSG: builtin_interfaces/Time", "MSG: hexapod_msgs/GaitParameters"):
        assert nested in text
    assert text.count("MSG: std_msgs/Header") == 1


def test_round_trip_through_our_reader_and_mcap_ros2(tmp_path):
    path = tmp_path / "run.mcap"
    with McapRecorder(path) as rec:
        for i in range(3):
            m = AdaptationTrial(trial=i + 1, archive_index=10 * i, measured_speed=0.1 * i)
            m.descriptor = [0.5] * 6
            rec.record("adapt/trials", m)
        o = Odometry()
        o.pose.pose.position.x = 1.25
        rec.record("odom", o)
    ours = list(read_messages(path))
    assert [t for t, _, _ in ours] == ["adapt/trials"] * 3 + ["odom"]
    assert [m.archive_index for t, m, _ in ours[:3]] == [0, 10, 20]
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        assert reader.get_summary() is not None                       # finished: indexed
        decoded = [(c.topic, d) for _, c, _, d in reader.iter_decoded_messages()]
    assert decoded[1][1].trial == 2 and decoded[3][1].pose.pose.position.x == 1.25
    with pytest.raises(RuntimeError, match="closed"):
        rec.record("odom", o)


def test_a_hard_killed_writer_leaves_every_complete_message(tmp_path):
    path = tmp_path / "killed.mcap"
    script = textwrap.dedent(f"""
        import sys, time
        from hexapod_msgs.msg import AdaptationTrial
        from hexapod_adapt.recording import McapRecorder
        rec = McapRecorder({str(path)!r})
        for i in range(5):
            rec.record("adapt/trials", AdaptationTrial(trial=i + 1))
        print("written", flush=True)
        time.sleep(60)
    """)
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "written"
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert [m.trial for _, m, _ in read_messages(path)] == [1, 2, 3, 4, 5]
