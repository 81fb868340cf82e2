#!/usr/bin/env python3
# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
`make demo`: Intelligent Trial & Error end to end on the simulated hexapod, in about a minute.

1. The robot model and the shipped default behaviour-performance map
   (hexapod_adapt/maps/default_map.npz, written by generate_map; see docs/adaptation.md).
2. The damage: legs 1 and 4 fail (held in the failure pose of table 5.1). The control tripod
   gait, the robot's original gait, no longer walks forwards.
3. Adaptation through the ROS graph: gait_node + state_publisher + sim_node (the map's engine,
   legs failed, as fast as possible) + adapt_node as separate processes, and adapt_client calling
   the `adapt` action the way an operator would from the base station. Each 5 s trial is printed
   as it completes.
4. The run's MCAP recording (with the URDF and frames for a 3D replay), read back.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path
import signal
import subprocess
import sys
import time

T0 = time.perf_counter()
WS = Path(__file__).resolve().parent.parent
FAILED_LEGS = [1, 4]  # scenario S2: two opposite legs, where the tripod gait stops walking


def section(title: str) -> None:
    print(f'\n== {title} ==', flush=True)


def exe(pkg: str, name: str) -> str:
    return str(WS / 'install' / pkg / 'lib' / pkg / name)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description='The main job, end to end, in a few seconds.')
    parser.add_argument(
        '--out',
        type=Path,
        default=WS / 'out' / 'demo',
        help='where node logs and the recording go',
    )
    out = parser.parse_args(argv).out
    from hexapod_adapt.mapping.archive import load_archive
    from hexapod_adapt.mapping.maps import shipped_map
    from hexapod_adapt.mapping.simulation import engine_of_map, map_physics, map_substeps
    from hexapod_description import load_model, summary
    from hexapod_gait import preset
    from hexapod_sim import create_simulator, evaluate_gait
    from hexapod_util.processes import die_with_parent
    from hexapod_util.recording import read_messages
    from hexapod_util.ros_glue import ros_args

    out.mkdir(parents=True, exist_ok=True)
    section('robot model (hexapod_description)')
    print(summary(load_model()))

    section('behaviour-performance map (hexapod_adapt)')
    path = shipped_map()  # what adapt_node loads by default
    archive = load_archive(path)
    engine = engine_of_map(archive)
    substeps = map_substeps(archive, engine)  # the physics steps per row the map was made at
    s = archive.stats()
    speeds = archive.speeds()[archive.filled]
    print(
        f'{path.relative_to(WS) if path.is_relative_to(WS) else path}: {s.filled} gaits in'
        f' {archive.n_niches} niches after {archive.metadata["evaluations"]} {engine} evaluations'
        ' (seed'
        f' {archive.metadata["seed"]}); speeds {speeds.min():.3f} .. {speeds.max():.3f} m/s,'
        f' median {float(sorted(speeds)[len(speeds) // 2]):.3f}'
    )

    legs = ' and '.join(map(str, FAILED_LEGS))
    section(f'damage: legs {legs} fail')
    with create_simulator(map_physics(archive, engine)) as sim:
        intact = evaluate_gait(preset('control'), sim, collisions_fatal=False).speed
        damaged = evaluate_gait(
            preset('control'), sim, collisions_fatal=False, failed_legs=FAILED_LEGS
        ).speed
    print(
        f"control tripod gait (the robot's original gait) on {engine}: {intact:.3f} m/s intact, "
        f'{damaged:.3f} m/s with legs {legs} failed'
    )

    section('adaptation through the ROS graph: gait_node + sim_node + adapt_node, adapt_client')
    env = dict(
        os.environ,
        ROS_DOMAIN_ID=str(60 + os.getpid() % 30),
        ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST',
        PYTHONUNBUFFERED='1',
    )
    logs: list = []

    def start(pkg: str, name: str, **params) -> subprocess.Popen:
        """Start ``name`` with ``params`` (ROS parameter values), logging to out/<name>.log."""
        logs.append(open(out / f'{name}.log', 'w'))
        return subprocess.Popen(
            [exe(pkg, name), *ros_args(params)],
            env=env,
            stdout=logs[-1],
            stderr=subprocess.STDOUT,
            preexec_fn=die_with_parent,
        )

    # one time base: every node but sim_node runs on sim_node's /clock
    nodes = [
        start('hexapod_gait', 'gait_node', initial_preset='', use_sim_time=True),
        # the URDF and the leg frames, so the recording replays in Foxglove's 3D panel
        start('hexapod_gait', 'state_publisher', use_sim_time=True),
        start(
            'hexapod_sim',
            'sim_node',
            real_time_factor=0.0,
            failed_legs=FAILED_LEGS,
            engine=engine,  # trials on the engine that made the map, at its steps per row
            substeps=substeps,
        ),
        # no archive parameter: the default map
        start('hexapod_adapt', 'adapt_node', record_dir=str(out / 'runs'), use_sim_time=True),
    ]
    mcap = None
    try:
        t0 = time.perf_counter()
        client = subprocess.run(
            [exe('hexapod_adapt', 'adapt_client'), '--max-trials', '20'],
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            timeout=600,
        )
        print(client.stdout, end='')
        print(f'({time.perf_counter() - t0:.1f} s of wall time; 5 s of simulated time per trial)')
        for line in client.stdout.splitlines():
            if line.startswith('recording: '):
                mcap = line.split(': ', 1)[1]
        if client.returncode not in (0, 3):
            print(f'adapt_client failed (exit {client.returncode}); node logs in {out}/')
            return 1
    finally:
        for p in nodes:
            p.send_signal(signal.SIGINT)
        for p in nodes:
            try:
                p.wait(10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        for f in logs:
            f.close()

    if mcap:
        section("the run's MCAP recording, read back")
        counts: dict[str, int] = {}
        best = None
        for topic, msg, _ in read_messages(mcap):
            counts[topic] = counts.get(topic, 0) + 1
            if topic == '/adapt/trials':
                best = msg
        print(
            f'{Path(mcap).relative_to(WS) if Path(mcap).is_relative_to(WS) else mcap}: '
            + ', '.join(f'{n} x {t}' for t, n in sorted(counts.items()))
        )
        if best is not None:
            print(
                f'adapted gait {best.best_archive_index}: {best.best_speed:.3f} m/s with legs'
                f' {legs} failed, vs {damaged:.3f} m/s for the control tripod gait'
            )
    print(
        f'\ndemo finished in {time.perf_counter() - T0:.0f} s. Next: docs/adaptation.md '
        '(generate your own map, adapt on the real robot).'
    )
    return 0


if __name__ == '__main__':
    sys.exit(main())
