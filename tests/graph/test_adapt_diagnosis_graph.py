# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A blind run through the graph names a damage nobody told adapt_node, says so, and stops itself.

sim_node holds the damage (set at start-up, as ``SetLegFailure`` sets it); the goal is blind, so
adapt_node does not ask the simulator. The diagnosis after each trial is on the goal's feedback,
on ``adapt/diagnosis`` and in the run's recording.
"""

from __future__ import annotations

from hexapod_msgs.action import Adapt
from hexapod_msgs.msg import DamageDiagnosis
from hexapod_sim.damage import Damage
from hexapod_util.recording import read_messages
from hexapod_util.ros_glue import EVENTS
import pytest

from conftest import fast_sim_graph, wait_for

pytestmark = [pytest.mark.ros, pytest.mark.slow]


def test_a_blind_run_names_the_hidden_damage_says_so_and_stops_by_itself(ros, launch, tmp_path):
    hidden = Damage.lifted([1, 4])
    fast_sim_graph(launch, [1, 4], record_dir=str(tmp_path / 'runs'))  # the default map
    published = ros.collect(DamageDiagnosis, 'adapt/diagnosis', EVENTS)
    run = ros.send_adapt(Adapt.Goal(blind=True), timeout=60)
    wait_for(run.done, 900, 'the blind run to end')
    result = run.result()
    assert result.success, result.message
    assert 'the damage is named from the trials among 21 hypotheses' in result.prior
    assert 1 <= result.trials < 24, result.message  # it stopped by itself, not on the budget
    said = [f.diagnosis for f in run.trials]
    assert len(said) == result.trials and all(d.hypotheses for d in said)
    assert said[-1].named == hidden.label, said[-1]
    assert said[-1].hypotheses[0] == hidden.label and said[-1].probabilities[0] >= 0.9
    wait_for(lambda: len(published) == result.trials, 10, 'a diagnosis on adapt/diagnosis a trial')
    assert [d.named for d in published] == [d.named for d in said]
    recorded = [
        m for topic, m, _ in read_messages(result.mcap_path) if topic == '/adapt/diagnosis'
    ]
    assert [d.named for d in recorded] == [d.named for d in said]
