#!/usr/bin/env python3
# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
r"""
Start a node graph from the install space.

The equivalent of the launch files for this environment, which has no `ros2 launch`. Each node's
output is prefixed with its name; Ctrl-C stops them all. A node that exits on its own is named,
with its exit status and its last lines; the others keep running (``--stop-on-exit``: all stop).

    python scripts/launch.py sim [--rtf 0] [--failed-legs 1 4] [--preset wave]
    python scripts/launch.py adapt-sim [--archive MAP] [--failed-legs 1]  # + adapt_node, fast
    python scripts/launch.py navigate-sim [--failed-legs 1 2]  # + navigate_node (MuJoCo)
    python scripts/launch.py sim --engine mujoco                          # the other engine
    # robot_emulator (PyBullet) + bridge_node (+ state_publisher, as on the robot):
    python scripts/launch.py emulated-robot [--archive [MAP]]
    python scripts/launch.py robot --port /dev/ttyUSB0 [--imu-port /dev/ttyUSB1] \\
        [--archive [MAP] [--manual]]
With --archive the robot profiles also start adapt_node (mode robot, or manual with --manual).
Without a MAP adapt_node loads the shipped default map. With --navigate they also start
navigate_node (mode robot): the navigate action on the real radio and IMU odometry.
"""

from __future__ import annotations

import argparse
from collections import deque
import os
from pathlib import Path
import signal
import subprocess
import sys
import threading
import time

WS = Path(__file__).resolve().parent.parent


def exe(pkg: str, name: str) -> str:
    path = WS / 'install' / pkg / 'lib' / pkg / name
    if not path.exists():
        sys.exit(f'launch: {path} not found; run `make build` first')
    return str(path)


#: Lines of each process's output kept to show when it exits on its own.
LAST_LINES = 12


def pump(name: str, stream, last: deque) -> None:
    for line in iter(stream.readline, ''):
        last.append(line)
        sys.stdout.write(f'[{name}] {line}')
        sys.stdout.flush()


def exit_status(code: int) -> str:
    """Say how a process ended from its return code (negative: the signal that killed it)."""
    if code < 0:
        return f'killed by {signal.Signals(-code).name} (status {128 - code})'
    if code > 128 and code - 128 in {int(s) for s in signal.Signals}:
        return f'exit status {code} ({signal.Signals(code - 128).name})'
    return f'exit status {code}'


def map_physics(archive: str | None, engine: str | None) -> tuple[str | None, int]:
    """
    Return sim_node's engine and physics steps per row for ``archive`` (None/'' = the default map).

    The engine: ``engine`` if given, else the map's. The steps: those the library walks the map's
    gaits at on that engine (``trial_substeps``: the map's own on its engine, the converged step
    on another); 0, the engine's default, if the map is unreadable (adapt_node refuses it with
    the reason, and sim_node keeps its defaults).
    """
    from hexapod_adapt.mapping.archive import ArchiveError, load_archive
    from hexapod_adapt.mapping.maps import shipped_map
    from hexapod_adapt.mapping.simulation import engine_of_map, trial_substeps

    try:
        loaded = load_archive(archive or shipped_map())
    except ArchiveError:
        return engine, 0
    engine = engine or engine_of_map(loaded)
    return engine, trial_substeps(loaded, engine)


def simulated_profile(profile: str) -> bool:
    """Whether a profile runs sim_node (and its /clock) in place of the robot."""
    return profile in ('sim', 'adapt-sim', 'navigate-sim')


def main(argv: list[str] | None = None) -> int:
    from hexapod_sim.simulator import ENGINES
    from hexapod_util.processes import die_with_parent
    from hexapod_util.ros_glue import ros_args

    parser = argparse.ArgumentParser(
        description='Start the hexapod node graph (no `ros2 launch` needed).'
    )
    parser.add_argument(
        'profile', choices=['sim', 'adapt-sim', 'navigate-sim', 'emulated-robot', 'robot']
    )
    parser.add_argument(
        '--navigate',
        action='store_true',
        help='robot profiles: also start navigate_node (mode robot) for the navigate action',
    )
    parser.add_argument(
        '--archive',
        nargs='?',
        const='',
        default=None,
        help='start adapt_node with this map (adapt-sim always does); no MAP = the default map',
    )
    parser.add_argument(
        '--manual', action='store_true', help='adapt_node takes tape-measured distances'
    )
    parser.add_argument(
        '--rtf',
        type=float,
        default=None,
        help="sim real_time_factor (0 = as fast as possible; default: sim_node's, 1)",
    )
    parser.add_argument(
        '--engine',
        choices=ENGINES,
        help="sim_node's physics engine (default: pybullet; adapt-sim: the map's)",
    )
    parser.add_argument(
        '--preset', default=None, help="gait_node initial preset (default: gait_node's, tripod)"
    )
    parser.add_argument(
        '--params-file',
        default=None,
        metavar='YAML',
        help='a ros__parameters file for every node it names (config/*.yaml of the packages);'
        ' the options above, when given, take precedence',
    )
    parser.add_argument(
        '--failed-legs', type=int, nargs='*', default=[], help='sim profiles: legs lifted'
    )
    parser.add_argument(
        '--dead-servo',
        type=int,
        action='append',
        default=[],
        metavar='ID',
        help='emulated-robot: a servo (2..19) that does not answer; its joint is unpowered and the'
        ' firmware folds the leg (repeatable, at most two legs)',
    )
    parser.add_argument(
        '--firmware',
        choices=['python', 'native'],
        default='python',
        help="emulated-robot: the robot's firmware, the Python model or the C++ module",
    )
    parser.add_argument(
        '--leg-map',
        type=int,
        nargs=6,
        default=None,
        metavar='N',
        help="robot profiles: the robot's leg number of URDF legs 1..6 (bridge_node's leg_map;"
        ' emulated-robot: the emulated robot is numbered so too); default identity',
    )
    parser.add_argument(
        '--port',
        default=None,
        help="robot: the radio's port (default: the --params-file's, else /tmp/hexapod_radio)",
    )
    parser.add_argument(
        '--imu-port',
        default=None,
        help="robot: the Xsens IMU's port (default: the file's, else '')",
    )
    parser.add_argument(
        '--stop-on-exit',
        action='store_true',
        help='stop every node when one exits on its own (default: it is named, the rest run on)',
    )
    args = parser.parse_args(argv)
    if args.profile == 'emulated-robot' and args.failed_legs:
        parser.error(
            'emulated-robot: damage the robot with --dead-servo ID (a servo that does not answer);'
            ' --failed-legs is for the sim profiles'
        )
    if args.profile != 'emulated-robot' and (args.dead_servo or args.firmware != 'python'):
        parser.error('--dead-servo and --firmware are for the emulated-robot profile')
    if simulated_profile(args.profile) and args.leg_map is not None:
        parser.error('--leg-map is for the robot profiles (emulated-robot, robot)')
    leg_map = {'leg_map': args.leg_map} if args.leg_map is not None else {}

    commands: list[tuple[str, list[str]]] = []
    substeps = 0  # sim_node's physics steps per row (0: the engine's default)
    if args.profile == 'adapt-sim':
        args.rtf, args.preset = 0.0, ''
        # trials on the map's engine, at the physics steps per row it was made at
        args.engine, substeps = map_physics(args.archive, args.engine)
    if args.profile == 'navigate-sim':
        # the repertoire's engine; real time by default (--rtf): steps follow each other unplanned
        # walking between them grows with the speed-up
        args.preset, args.engine = '', args.engine or 'mujoco'
    simulated = simulated_profile(args.profile)  # sim_node's /clock
    # navigation on the robot: one bridge trial is one repertoire step
    bridge_trial = {}
    if args.navigate:
        from hexapod_adapt.mapping.steps import STEP_DURATION

        bridge_trial = {'trial_duration': STEP_DURATION}
    if simulated:
        sim_params = {} if args.rtf is None else {'real_time_factor': args.rtf}
        if args.engine:
            sim_params['engine'] = args.engine
        if substeps:
            sim_params['substeps'] = substeps
        if args.failed_legs:
            sim_params['failed_legs'] = args.failed_legs
        # one time base: every node but the clock source (sim_node) runs on sim time
        commands = [
            (
                'gait_node',
                [exe('hexapod_gait', 'gait_node')]
                + ros_args(
                    ({} if args.preset is None else {'initial_preset': args.preset})
                    | {'use_sim_time': True}
                ),
            ),
            ('sim_node', [exe('hexapod_sim', 'sim_node')] + ros_args(sim_params)),
        ]
    elif args.profile == 'emulated-robot':
        commands = [
            (
                'robot_emulator',
                [
                    exe('hexapod_bridge', 'robot_emulator'),
                    '--sim',
                    '--imu-noise',
                    '--radio-link',
                    '/tmp/hexapod_radio',
                    '--imu-link',
                    '/tmp/hexapod_imu',
                    '--firmware',
                    args.firmware,
                ]
                + [f'--dead-servo={servo}' for servo in args.dead_servo]
                + (['--leg-map', *map(str, args.leg_map)] if args.leg_map else [])
                + (['--engine', args.engine] if args.engine else []),
            ),
            (
                'bridge_node',
                [exe('hexapod_bridge', 'bridge_node')]
                + ros_args(
                    {
                        'port': '/tmp/hexapod_radio',
                        'imu_port': '/tmp/hexapod_imu',
                        'arm_on_start': True,  # up to active: configured and armed
                        **bridge_trial,
                        **leg_map,
                    }
                ),
            ),
        ]
    else:
        # a lifecycle node brought up to active (armed) unless a file says otherwise
        defaults = (
            {}
            if args.params_file
            else {'port': '/tmp/hexapod_radio', 'imu_port': '', 'arm_on_start': True}
        )
        ports = {'port': args.port, 'imu_port': args.imu_port}
        ports = defaults | {name: value for name, value in ports.items() if value is not None}
        commands = [
            (
                'bridge_node',
                [exe('hexapod_bridge', 'bridge_node')]
                + ros_args({**ports, **bridge_trial, **leg_map}),
            )
        ]
    # robot_state_publisher's job: leg links on /tf, latched robot_description and /tf_static
    commands.append(
        (
            'state_publisher',
            [exe('hexapod_gait', 'state_publisher')] + ros_args({'use_sim_time': simulated}),
        )
    )
    if args.archive is not None or args.profile == 'adapt-sim':
        mode = 'sim' if simulated else ('manual' if args.manual else 'robot')
        commands.append(
            (
                'adapt_node',
                [exe('hexapod_adapt', 'adapt_node')]
                + ros_args(
                    {
                        'archive': str(Path(args.archive).resolve()) if args.archive else '',
                        'mode': mode,
                        'use_sim_time': mode == 'sim',
                    }
                ),
            )
        )

    if args.profile == 'navigate-sim' or args.navigate:
        mode = 'sim' if simulated else 'robot'
        commands.append(
            (
                'navigate_node',
                [exe('hexapod_navigation', 'navigate_node')]
                + ros_args(
                    {'mode': mode, 'use_sim_time': mode == 'sim'}
                    | ({} if simulated else {'trial_duration': bridge_trial['trial_duration']})
                ),
            )
        )

    if args.params_file:
        path = Path(args.params_file).expanduser().resolve()
        if not path.is_file():
            parser.error(f'--params-file {args.params_file}: no such file')
        # the file first: the options given (later on the command line) take precedence
        file = ['--ros-args', '--params-file', str(path)]
        commands = [  # the nodes (the emulator is a program of its own, not a node)
            (name, cmd if name == 'robot_emulator' else cmd[:1] + file + cmd[1:])
            for name, cmd in commands
        ]
    env = dict(os.environ, PYTHONUNBUFFERED='1')
    # Ctrl-C and SIGTERM stop the graph even when this process was started with SIGINT ignored
    # (a background job of a non-interactive shell inherits SIG_IGN, and Python keeps it).
    stop = threading.Event()
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda *_: stop.set())

    def default_signals() -> None:  # the nodes get Ctrl-C back whatever we inherited
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        die_with_parent()  # and stop if this launcher is killed outright

    procs, pumps, lasts = [], [], []
    for name, cmd in commands:
        proc = subprocess.Popen(
            cmd,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            env=env,
            preexec_fn=default_signals,
        )
        last: deque = deque(maxlen=LAST_LINES)
        pumps.append(threading.Thread(target=pump, args=(name, proc.stdout, last), daemon=True))
        pumps[-1].start()
        procs.append(proc)
        lasts.append(last)
        time.sleep(1.0 if name == 'robot_emulator' else 0.0)  # let the emulator create its ports
    told: set[int] = set()
    try:
        while not stop.is_set() and any(p.poll() is None for p in procs):
            for i, p in enumerate(procs):
                if p.poll() is not None and i not in told:
                    told.add(i)
                    pumps[i].join(1.0)  # its last words first
                    _tell_exit(commands[i][0], p.returncode, lasts[i], args.stop_on_exit)
            if told and args.stop_on_exit:
                break
            stop.wait(0.2)
    finally:
        # SIGINT (the nodes finish cleanly), then SIGTERM, then SIGKILL: never leave one running
        for signum, grace in ((signal.SIGINT, 10.0), (signal.SIGTERM, 5.0), (signal.SIGKILL, 5.0)):
            alive = [p for p in procs if p.poll() is None]
            if signum == signal.SIGTERM:
                _ask_for_stacks(alive, [commands[procs.index(p)][0] for p in alive])
            for p in alive:
                if signum != signal.SIGINT:
                    name = commands[procs.index(p)][0]
                    print(f'[launch] {name} still running: sending {signum.name}', flush=True)
                p.send_signal(signum)
            deadline = time.monotonic() + grace
            while alive and time.monotonic() < deadline:
                alive = [p for p in alive if p.poll() is None]
                time.sleep(0.05)
    # the first failure (a node killed by a signal counts, as 128 + its number), else 0; a command
    # that reports the Ctrl-C it was stopped with (128 + SIGINT) stopped cleanly
    codes = [
        p.returncode
        for p in procs
        if p.returncode and not (stop.is_set() and p.returncode == 128 + signal.SIGINT)
    ]
    return (codes[0] if codes[0] > 0 else 128 - codes[0]) if codes else 0


def _ask_for_stacks(procs: list, names: list[str]) -> None:
    """Have the nodes that outlived their Ctrl-C print where their threads are, into the log."""
    from hexapod_util.ros_glue import STACKS_SIGNAL

    nodes = [(p, n) for p, n in zip(procs, names) if n != 'robot_emulator']  # not a node
    for p, name in nodes:
        print(f'[launch] {name} did not stop at Ctrl-C: its stacks follow', flush=True)
        p.send_signal(STACKS_SIGNAL)
    if nodes:
        time.sleep(1.0)  # the dumps reach the log before anything else is said


def _tell_exit(name: str, code: int, last: deque, stopping: bool) -> None:
    """Say which node exited on its own, how, and its last lines."""
    after = 'stopping the others (--stop-on-exit)' if stopping else 'the others keep running'
    lines = ''.join(f'[launch]   | {line}' for line in last) or '[launch]   | (no output)\n'
    sys.stdout.write(
        f'[launch] {name} exited on its own, {exit_status(code)}; {after}. Its last lines:\n'
        + lines
    )
    sys.stdout.flush()


if __name__ == '__main__':
    sys.exit(main())
