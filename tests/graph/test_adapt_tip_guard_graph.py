# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The tip guard of adaptation, through the graph: adapt_node + gait_node + sim_node (fast mode).

A map whose best gait tips the robot over with leg 1 lifted: its trial is stopped when the body
tilts past adapt_node's tip_guard, counts as 0 m/s, is never tried again, and says so on
adapt/trials and in the run's MCAP recording.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.simulation import simulation_fingerprint
from hexapod_adapt.online.adaptation import DEFAULT_TIP_GUARD
from hexapod_gait import preset, to_genotype
from hexapod_msgs.action import Adapt
from hexapod_msgs.msg import AdaptationTrial
from hexapod_sim import create_simulator, evaluate_gait
from hexapod_util.recording import read_messages
import numpy as np
import pytest

from conftest import fast_sim_graph, set_adapt_parameter, wait_for

pytestmark = pytest.mark.ros
FAILED = [1]
#: A gait that ends on its back on PyBullet, intact and with leg 1 lifted (frozen: see the file).
FALLING = Path(__file__).resolve().parents[2] / 'hexapod_adapt/test/data/falling_gaits.json'
TIPPER = json.loads(FALLING.read_text())['tips_intact_and_leg_1_lifted']['genotype']


def _tipper_first(genes, failed_legs, guard, path, margin=0.0):
    """
    An archive of ``genes`` whose first (the tipper) the map ranks fastest.

    Checked on PyBullet with ``failed_legs``: the first tilts past ``guard`` [rad] by more than
    ``margin``, the others stay under it by more than ``margin``.
    """
    with create_simulator() as sim:
        walks = [
            evaluate_gait(
                g, sim, collisions_fatal=False, failed_legs=failed_legs, record_tilt=True
            )
            for g in genes
        ]
    assert walks[0].peak_tilt > guard + margin, 'the tipper no longer tips: pick another'
    assert all(w.peak_tilt < guard - margin for w in walks[1:]), [w.peak_tilt for w in walks]
    desc = np.eye(3, 6) * 0.5 + 0.25  # three distinct niches
    archive = Archive(
        desc,
        np.array([3.0, 1.0, 0.5]),  # the map believes the tipper is the fastest
        desc,
        np.array(genes),
        {'seed': 5, 'evaluations': 3, **simulation_fingerprint('pybullet')},
    )
    return archive.save(path)


@pytest.fixture(scope='module')
def tipping_archive(tmp_path_factory):
    """Three gaits: the tipper, with the highest map speed, then the control and wave gaits."""
    genes = [
        np.array(TIPPER),
        to_genotype(preset('control')),
        to_genotype(preset('wave')),
    ]
    path = tmp_path_factory.mktemp('archive') / 'tipping.npz'
    return _tipper_first(genes, FAILED, DEFAULT_TIP_GUARD, path)


@pytest.mark.slow
def test_a_trial_that_tips_is_stopped_counted_as_failed_and_never_tried_again(
    ros, launch, tmp_path, tipping_archive
):
    sim = launch(
        'hexapod_sim',
        'sim_node',
        params={'real_time_factor': 0.0, 'publish_period_steps': 12, 'failed_legs': FAILED},
    )
    gait = launch('hexapod_gait', 'gait_node', params={'initial_preset': ''})
    node = launch(
        'hexapod_adapt',
        'adapt_node',
        # no diagnosis: its safety model would skip the tipper before a trial could tip
        params={
            'archive': str(tipping_archive),
            'record_dir': str(tmp_path / 'runs'),
            'diagnose': False,
        },
    )
    trials = ros.collect(AdaptationTrial, 'adapt/trials', 10)
    response = ros.adapt(Adapt.Goal(max_trials=3, alpha=1.0, blind=True), timeout=300)
    assert response.trials >= 2, response.message
    wait_for(lambda: len(trials) == response.trials, 10, 'one AdaptationTrial per trial')
    first = trials[0]
    assert first.archive_index == 0 and first.tipped and first.measured_speed == 0.0
    assert [t.archive_index for t in trials].count(0) == 1  # never tried again
    assert not any(t.tipped for t in trials[1:])
    assert response.best_archive_index != 0 and response.best_speed > 0.0
    recorded = [m for topic, m, _ in read_messages(response.mcap_path) if topic == '/adapt/trials']
    assert [m.tipped for m in recorded] == [t.tipped for t in trials]
    # each channel says how it was offered (the ros2 MCAP profile): latched ones replay latched
    from mcap.reader import make_reader
    import yaml

    with open(response.mcap_path, 'rb') as f:
        channels = make_reader(f).get_summary().channels.values()
    offered = {c.topic: yaml.safe_load(c.metadata['offered_qos_profiles'])[0] for c in channels}
    assert {'/adapt/trials', '/odom', '/gait/parameters'} <= set(offered), sorted(offered)
    assert offered['/gait/parameters']['durability'] == 1  # transient local
    assert offered['/odom']['durability'] == 2 and offered['/odom']['depth'] == 5000
    assert offered['/adapt/trials']['reliability'] == 1
    assert node.alive() and sim.alive() and gait.alive()


@pytest.fixture(scope='module')
def intact_tipping_archive(tmp_path_factory):
    """The tipper (fastest by the map), then the tripod and the wave, measured intact."""
    genes = [
        np.array(TIPPER),
        to_genotype(preset('tripod')),
        to_genotype(preset('wave')),
    ]
    path = tmp_path_factory.mktemp('archive') / 'intact_tipping.npz'
    # margin: the tipper ends on its back, the tripod and the wave stay under 1 deg (measured)
    return _tipper_first(genes, (), DEFAULT_TIP_GUARD, path, margin=0.1)


@pytest.mark.slow
def test_a_robot_trial_that_tips_is_stopped_through_the_bridge_by_the_imu(
    ros, launch, tmp_path, intact_tipping_archive
):
    from std_srvs.srv import SetBool
    from test_adapt_robot_graph import _emulated_robot

    # the tipper may leave the robot lying past the guard (or it settles back on its feet): the
    # next trial waits until it stands, and the emulated operator rights it after 2 s
    emu, radio, imu = _emulated_robot(
        launch, tmp_path, '--sim', '--seed', '5', '--right-after', '2'
    )
    bridge = launch('hexapod_bridge', 'bridge_node', params={'port': radio, 'imu_port': imu})
    node = launch(
        'hexapod_adapt',
        'adapt_node',
        params={
            'archive': str(intact_tipping_archive),
            'mode': 'robot',
            'record_dir': '',
            'tip_guard': DEFAULT_TIP_GUARD,
            'diagnose': False,  # as above: the trial's guard is what is tested
        },
    )
    trials = ros.collect(AdaptationTrial, 'adapt/trials', 10)
    assert ros.call(SetBool, 'bridge_node/arm', SetBool.Request(data=True)).success
    response = ros.adapt(Adapt.Goal(max_trials=2, alpha=1.0, blind=True), timeout=180)
    assert response.trials == 2, response.message
    wait_for(lambda: len(trials) == 2, 10, 'one AdaptationTrial per trial')
    assert trials[0].archive_index == 0 and trials[0].tipped and trials[0].measured_speed == 0.0
    assert trials[1].archive_index != 0 and not trials[1].tipped
    assert 'tip guard' in node.log()
    assert node.alive() and bridge.alive() and emu.alive()


@pytest.fixture(scope='module')
def rocking_archive(tmp_path_factory):
    """The quadruped, the wave and the tripod: with leg 1 lifted, the wave rocks the least."""
    genes = [to_genotype(preset(name)) for name in ('quadruped', 'wave', 'tripod')]
    desc = np.eye(3, 6) * 0.5 + 0.25
    archive = Archive(
        desc,
        np.array([1.0, 0.9, 0.8]),
        desc,
        np.array(genes),
        {'seed': 5, 'evaluations': 3, **simulation_fingerprint('pybullet')},
    )
    return archive.save(tmp_path_factory.mktemp('archive') / 'rocking.npz'), genes


@pytest.mark.slow
def test_a_gait_that_tips_in_the_prior_simulation_is_never_tried(
    ros, launch, tmp_path, rocking_archive
):
    """
    With the damage known, the gait the prior ranks first tilts past the guard there: skipped.

    The guard is set between the wave's rocking and the quadruped's (measured on PyBullet with
    leg 1 lifted), and the quadruped walks faster: the prior's first, and vetoed.
    """
    path, genes = rocking_archive
    with create_simulator() as sim:
        walks = [
            evaluate_gait(g, sim, collisions_fatal=False, failed_legs=FAILED, record_tilt=True)
            for g in genes
        ]
    guard = 0.5 * (walks[0].peak_tilt + walks[1].peak_tilt)
    assert walks[1].peak_tilt < guard < walks[0].peak_tilt, [w.peak_tilt for w in walks]
    assert walks[0].speed > walks[1].speed and walks[0].speed > walks[2].speed
    sim, gait, node = fast_sim_graph(
        launch,
        FAILED,
        archive=str(path),
        record_dir='',
        prior_cache_dir=str(tmp_path),
        tip_guard=guard,
    )
    trials = ros.collect(AdaptationTrial, 'adapt/trials', 10)
    response = ros.adapt(Adapt.Goal(max_trials=1), timeout=300)
    assert response.trials == 1, response.message
    assert 'one that tilts past the' in response.prior
    wait_for(lambda: len(trials) == 1, 10, 'the trial')
    assert trials[0].archive_index == 1 and not trials[0].tipped  # the wave, not the quadruped
    assert 'never tried, predicted to tip past the tip guard: gait(s) 0' in response.message
    wait_for(lambda: 'gait 0 skipped' in node.log(), 10, 'the log line of the veto')
    # the guard off (pi): no screen, and the prior's first, the quadruped, is tried
    from rcl_interfaces.msg import ParameterType, ParameterValue

    off = ParameterValue(type=ParameterType.PARAMETER_DOUBLE, double_value=math.pi)
    assert set_adapt_parameter(ros, 'tip_guard', off).successful
    unguarded = ros.adapt(Adapt.Goal(max_trials=1), timeout=300)
    assert unguarded.trials == 1 and 'never tried' not in unguarded.message
    assert 'tilts past the' not in unguarded.prior, unguarded.prior
    wait_for(lambda: len(trials) == 2, 10, 'the unguarded trial')
    assert trials[1].archive_index == 0 and not trials[1].tipped
    assert node.alive() and sim.alive() and gait.alive()
