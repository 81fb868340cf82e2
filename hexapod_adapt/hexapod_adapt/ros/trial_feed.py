# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
What adapt_node says of each trial: ``adapt/trials``, ``adapt/diagnosis``, the goal's feedback.

Each trial is published on ``adapt/trials`` and, in a run that names its damage from the trials,
the diagnosis after it on ``adapt/diagnosis``; both go into the goal's feedback and the run's
recording, and the trial into the log.
"""

from __future__ import annotations

from typing import Callable

from hexapod_adapt.online import run_messages as say
from hexapod_adapt.online.session import AdaptationSession
from hexapod_adapt.online.trials import GaitOf
from hexapod_adapt.ros.graph_port import trial_msg
from hexapod_adapt.ros.run_recording import RunRecording
from hexapod_gait.ros_conversions import gait_to_msg
from hexapod_msgs.action import Adapt
from hexapod_msgs.msg import AdaptationTrial, DamageDiagnosis
from hexapod_util.ros_glue import EVENTS, TRIALS, unless_closing

#: The hypotheses a diagnosis message names, the most probable first.
TOP_HYPOTHESES = 5


def diagnosis_msg(session: AdaptationSession, trial: int) -> DamageDiagnosis | None:
    """Return the session's diagnosis after ``trial`` (None: the run makes none)."""
    post = session.posterior
    if post is None:
        return None
    top = post.top(TOP_HYPOTHESES)
    named = session.result().named
    return DamageDiagnosis(
        trial=trial,
        hypotheses=[label for label, _ in top],
        probabilities=[p for _, p in top],
        named=named[-1] if named else '',
        rescoring=session.rescoring is not None,
    )


class TrialFeed:
    """Publish, feed back, record and log each trial of a run (``node``'s publishers)."""

    def __init__(self, node, recording: RunRecording, say_vetoes: Callable) -> None:
        self.node, self.recording, self.say_vetoes = node, recording, say_vetoes
        self.trial_pub = node.create_publisher(AdaptationTrial, 'adapt/trials', TRIALS)
        self.diagnosis_pub = node.create_publisher(DamageDiagnosis, 'adapt/diagnosis', EVENTS)

    def __call__(self, handle, session: AdaptationSession, gaits: GaitOf, trial, niche) -> None:
        """Say one trial (and the diagnosis after it) everywhere it goes."""
        node = self.node
        self.say_vetoes(session)
        best_niche, best_speed = session.best() or (-1, 0.0)  # none while every trial tipped
        msg = trial_msg(trial, niche, best_niche, best_speed, session.archive)
        msg.header.stamp = node.get_clock().now().to_msg()
        msg.gait = gait_to_msg(gaits(niche))
        msg.recording = self.recording.problem
        # a node shutting down publishes nothing more: the recording still takes the trial
        unless_closing(node, self.trial_pub.publish, msg)
        feedback = Adapt.Feedback(
            trial=msg, trials_left=max(0, session.rules.max_trials - trial.number)
        )
        diagnosis = diagnosis_msg(session, trial.number)
        if diagnosis is not None:
            diagnosis.header.stamp = msg.header.stamp
            feedback.diagnosis = diagnosis
            if session.rescoring is not None:  # the pause before the next trial, said first
                feedback.note = say.rescore_note(session.rescoring)
            unless_closing(node, self.diagnosis_pub.publish, diagnosis)
            self.recording.record('adapt/diagnosis', diagnosis)
        unless_closing(node, handle.publish_feedback, feedback)
        self.recording.record('adapt/trials', msg)
        self.recording.checkpoint()  # a completed trial survives a kill or power loss
        if trial.tipped:  # rclpy fixes a call site's severity: one call per severity
            node.get_logger().warning(say.trial_message(trial, niche))
        else:
            node.get_logger().info(say.trial_message(trial, niche))
        if diagnosis is not None:
            node.get_logger().info(
                say.diagnosis_message(
                    trial.number,
                    diagnosis.named,
                    session.posterior,
                    session.unfit,
                    session.widened,
                    session.rescoring is not None,
                )
            )
