# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_bridge robot_emulator``.

The robot's side of the radio link (and an emulated Xsens MTi) on pseudo-terminals, for running
bridge_node without hardware.

    robot_emulator --radio-link /tmp/hexapod_radio --imu-link /tmp/hexapod_imu --sim
    robot_emulator ... --sim --firmware native --dead-servo 5 --dead-servo 14

``--firmware native`` runs the C++ firmware module (firmware/, package hexapod_firmware) in place
of the Python model. ``--dead-servo ID`` makes a servo not answer pings (the firmware reports it
as FF FD 0B <id>) and, with --sim, its joint unpowered, the live joints of its leg folding it
(the fold policy of hexapod_sim.damage). ``--leg-map`` numbers the emulated robot's legs as
bridge_node's ``leg_map`` does (the robot's leg number of each URDF leg; identity by default):
per-leg parameters and servos are in the robot's numbering, the geometry and the simulator the
URDF's; give both the same map.

Prints ``RADIO <path>`` and ``IMU <path>`` once the ports exist, ``WALK <gait id> at <seconds on
CLOCK_MONOTONIC>`` when a walk starts, and ``TRIAL {json}`` with the simulator's own measurement
when a walk ends. SIGUSR1 makes the radio port vanish (the pty is
closed and its link removed; it prints ``RADIO gone at <seconds on CLOCK_MONOTONIC>``), SIGUSR2
brings a new one back at the same link path - the fault-injection handles the reliability tests
use. SIGHUP restarts the robot's microcontroller: the firmware starts afresh (no gait uploaded,
not walking, its IMU counter from zero) while the ports stay open, and it prints ``REBOOTED at
<seconds on CLOCK_MONOTONIC>``. SIGINT/SIGTERM end it.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import select
import signal
import sys
import time
import tty

from hexapod_bridge.emulator.firmware import FirmwareTiming, ImuNoise, RobotFirmware
from hexapod_bridge.emulator.native import NativeRobotFirmware
from hexapod_bridge.protocol import extension as ext
from hexapod_bridge.reports import servo_report
from hexapod_bridge.servos import SERVO_IDS, servo_place
from hexapod_sim import create_simulator, ENGINES, SimConfig
from hexapod_sim.damage import Damage
from hexapod_sim.simulator import peak_tilt
from hexapod_util.cli import number, run_command

# The line the emulator prints when its radio port vanishes, followed by the time on
# CLOCK_MONOTONIC (comparable with time.monotonic() in any process on the machine).
RADIO_GONE = 'RADIO gone at '
#: A body tilted past this [rad] for --right-after s has fallen: the emulated operator rights it.
FALLEN_TILT = math.radians(30.0)
RIGHTED = 'RIGHTED at '
REBOOTED = 'REBOOTED at '
WALK = 'WALK '
#: The most time the emulated robot's clock moves in one turn of its loop [s].
CATCH_UP_S = 0.25


def radio_gone_times(output: str) -> list[float]:
    """When the radio port vanished, on CLOCK_MONOTONIC, read from the emulator's output."""
    return [
        float(line.removeprefix(RADIO_GONE))
        for line in output.splitlines()
        if line.startswith(RADIO_GONE)
    ]


def _pty_link(path: str) -> bool:
    """Whether ``path`` is a symlink to a pseudo-terminal (an emulator's port, maybe stale)."""
    return os.path.islink(path) and os.readlink(path).startswith('/dev/pts/')


class PtyPort:
    """The robot end of a pseudo-terminal, published at a stable symlink path."""

    def __init__(self, link: str) -> None:
        self.link = link
        self.master: int | None = None
        self.slave: int | None = None
        self.path: str | None = None  # the pseudo-terminal the link points at, once open

    def open(self) -> str:  # noqa: A003 (the pty pair is opened, as a file is)
        """
        Create the pseudo-terminal and its symlink at ``link``.

        A link left by an earlier emulator (a symlink to a pseudo-terminal) is replaced; anything
        else at ``link`` is the user's, and is refused (ValueError) and left as it is.
        """
        if os.path.lexists(self.link) and not _pty_link(self.link):
            raise ValueError(
                f'{self.link} exists and is not a pseudo-terminal link: refusing to replace it'
                ' (give another --radio-link / --imu-link)'
            )
        self.master, self.slave = os.openpty()
        tty.setraw(self.master)
        tty.setraw(self.slave)
        os.set_blocking(self.master, False)
        path = os.ttyname(self.slave)
        tmp = f'{self.link}.tmp{os.getpid()}'
        if os.path.lexists(tmp):
            os.unlink(tmp)
        os.symlink(path, tmp)
        os.replace(tmp, self.link)
        self.path = path
        return path

    def close(self) -> None:
        """Close the pseudo-terminal and remove its symlink (only if it is still this one's)."""
        if os.path.islink(self.link) and os.readlink(self.link) == self.path:
            os.unlink(self.link)
        for fd in (self.master, self.slave):
            if fd is not None:
                try:
                    os.close(fd)
                except OSError:
                    pass
        self.master = self.slave = None

    def write(self, data: bytes) -> None:
        """Write bytes to the host side (dropped when no host has the port open)."""
        if self.master is None or not data:
            return
        try:
            os.write(self.master, data)
        except (BlockingIOError, OSError):
            pass  # nobody reading: bytes are lost, as on a radio with no receiver

    def read(self) -> bytes:
        """Bytes the host wrote since the last call (b'' if none)."""
        if self.master is None:
            return b''
        try:
            return os.read(self.master, 4096)
        except (BlockingIOError, OSError):
            return b''


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``robot_emulator``: serve the emulated robot until Ctrl-C."""
    parser = argparse.ArgumentParser(
        description="Emulate the hexapod's firmware on pseudo-terminals."
    )
    parser.add_argument(
        '--radio-link', default='/tmp/hexapod_radio', help='symlink path of the radio port'
    )
    parser.add_argument(
        '--imu-link', default='', help="symlink path of an emulated Xsens port ('' = none)"
    )
    parser.add_argument('--sim', action='store_true', help='drive a simulator (the robot walks)')
    parser.add_argument(
        '--engine',
        choices=ENGINES,
        default='pybullet',
        help='physics engine of the emulated robot with --sim',
    )
    parser.add_argument(
        '--imu-noise', action='store_true', help='add Xsens-like noise and bias to the IMU'
    )
    parser.add_argument(
        '--seed', type=number(int, 0, 2**32 - 1), default=0, help='seed of the IMU noise'
    )
    parser.add_argument(
        '--right-after',
        type=number(float, 0, 3600),
        default=0.0,
        help='with --sim, put the robot back on its feet when its body has lain tilted past'
        f' {math.degrees(FALLEN_TILT):.0f} deg this many seconds, as an operator would'
        ' (0 = never)',
    )
    parser.add_argument(
        '--walk-duration',
        type=number(float, 0, 600, low_open=True),
        default=5.0,
        help="seconds a walk lasts after the robot's reset (firmware: 5), (0, 600]",
    )
    parser.add_argument(
        '--failsafe-windows',
        type=number(int, 1, 1000),
        default=11,
        help='ping check windows without a ping before a walk stops (firmware: 11), 1..1000',
    )
    parser.add_argument(
        '--firmware',
        choices=FIRMWARES,
        default='python',
        help="the robot's firmware: the Python model or the C++ module (firmware/)",
    )
    parser.add_argument(
        '--dead-servo',
        type=number(int, SERVO_IDS[0], SERVO_IDS[-1]),
        action='append',
        default=[],
        metavar='ID',
        help=f'a servo that does not answer pings ({SERVO_IDS[0]}..{SERVO_IDS[-1]}; repeatable);'
        ' with --sim its joint is unpowered and the live joints fold the leg (at most two legs)',
    )
    parser.add_argument(
        '--leg-map',
        type=int,
        nargs=6,
        default=list(ext.IDENTITY_LEG_MAP),
        metavar='N',
        help="the emulated robot's leg number of URDF legs 1..6, a permutation of 1..6 (default"
        " identity); give bridge_node the same leg_map (the real robot's firmware numbers its"
        ' legs clockwise: 1 6 5 4 3 2, unverified)',
    )
    args = parser.parse_args(argv)
    try:
        args.leg_map = ext.validate_leg_map(args.leg_map)
    except ext.ExtensionError as exc:
        parser.error(f'--leg-map: {exc}')
    legs = sorted({servo_place(s).robot_leg for s in args.dead_servo})
    if len(legs) > 2:
        parser.error(f'--dead-servo names servos on {len(legs)} legs: at most 2 legs can fail')
    return run_command('robot_emulator', lambda: _serve(args))


def _serve(args: argparse.Namespace) -> int:

    dead = frozenset(args.dead_servo)
    sim = _damaged_sim(args, dead) if args.sim else None
    start = time.monotonic()

    def boot(now: float) -> RobotFirmware | NativeRobotFirmware:
        return make_firmware(
            args.firmware,
            sim=sim,
            timing=FirmwareTiming(args.walk_duration, args.failsafe_windows),
            imu_noise=ImuNoise() if args.imu_noise else None,
            seed=args.seed,
            servo_ping=lambda servo: servo not in dead,
            leg_map=args.leg_map,
            now=now,
        )

    firmware = boot(0.0)
    radio = PtyPort(args.radio_link)
    imu = PtyPort(args.imu_link) if args.imu_link else None
    print(f'RADIO {radio.open()}', flush=True)
    if imu is not None:
        try:
            print(f'IMU {imu.open()}', flush=True)
        except ValueError:
            radio.close()  # the radio's link goes with the refusal
            raise

    requests: list[str] = []
    signal.signal(signal.SIGUSR1, lambda *_: requests.append('vanish'))
    signal.signal(signal.SIGUSR2, lambda *_: requests.append('return'))
    signal.signal(signal.SIGHUP, lambda *_: requests.append('reboot'))
    stopped_by: list[int] = []
    for signum in (signal.SIGINT, signal.SIGTERM):  # a second Ctrl-C cannot cut the clean-up short
        signal.signal(signum, lambda number, _: stopped_by.append(number))
    reported = walks = 0
    lying_since: float | None = None  # when the body last tilted past FALLEN_TILT
    now = 0.0  # the robot's clock: the wall clock's, catching up at most CATCH_UP_S a turn
    try:
        while not stopped_by:
            while requests:
                what = requests.pop(0)
                if what == 'vanish' and radio.master is not None:
                    radio.close()
                    print(f'{RADIO_GONE}{time.monotonic():.6f}', flush=True)
                    print_stats(firmware)
                elif what == 'return' and radio.master is None:
                    print(f'RADIO {radio.open()}', flush=True)
                elif what == 'reboot':
                    print_stats(firmware)
                    firmware, reported, walks = boot(now), 0, 0
                    print(f'{REBOOTED}{time.monotonic():.6f}', flush=True)
            fds = [radio.master] if radio.master is not None else []
            ready = select.select(fds, [], [], 0.002)[0] if fds else (time.sleep(0.002) or [])
            # after a stall (a stopped process, a loaded machine) the robot catches up in pieces,
            # serving the radio between them, as a robot that never stopped would
            now = min(time.monotonic() - start, now + CATCH_UP_S)
            if ready:
                firmware.receive(radio.read(), now)
            if imu is not None:
                imu.read()  # commands to the IMU are accepted and ignored
            out_radio, out_imu = firmware.advance(now)
            if sim is not None and args.right_after > 0:
                lying_since = _right_if_fallen(sim, now, lying_since, args.right_after)
            radio.write(out_radio)
            if imu is not None:
                imu.write(out_imu)
            walks, reported = _print_trials(firmware, walks, reported)
    finally:
        radio.close()
        if imu is not None:
            imu.close()
        print_stats(firmware)
    name = signal.Signals(stopped_by[0]).name
    print(f'robot_emulator: stopped by {name}', file=sys.stderr, flush=True)
    return 128 + stopped_by[0]


def _damaged_sim(args: argparse.Namespace, dead: frozenset[int]):
    """Return the simulator of the robot with the ``dead`` servos' joints unpowered."""
    sim = create_simulator(SimConfig(engine=args.engine))
    # a dead servo's joint is free, its leg folded by the live ones (hexapod_sim.damage); the
    # simulator's legs are the URDF's: the robot's leg of a servo goes through leg_map
    joints: dict[int, set[str]] = {}
    for servo in dead:
        place = servo_report(servo, args.leg_map)
        joints.setdefault(place.leg, set()).add(place.joint)
    sim.set_damage(Damage.unpowered(joints))
    return sim


def _print_trials(firmware, walks: int, reported: int) -> tuple[int, int]:
    """Print the walks begun and the trials ended since; return the new counts of each."""
    trials = firmware.trials
    while walks < len(trials):
        print(f'{WALK}{trials[walks].gait_id} at {time.monotonic():.6f}', flush=True)
        walks += 1
    while reported < len(trials) and trials[reported].end_position is not None:
        print('TRIAL ' + json.dumps(trials[reported].summary()), flush=True)
        reported += 1
    return walks, reported


def _right_if_fallen(sim, now: float, lying_since: float | None, after: float) -> float | None:
    """Put a body that has lain past FALLEN_TILT ``after`` s back on its feet; its new since."""
    if peak_tilt(sim.base_pose()[1]) <= FALLEN_TILT:
        return None
    if lying_since is None:
        return now
    if now - lying_since < after:
        return lying_since
    sim.reset(sim.joint_states()[0])  # on its feet at the origin, the joints as they are
    print(f'{RIGHTED}{now:.3f}', flush=True)
    return None


FIRMWARES = ('python', 'native')


def make_firmware(
    kind: str,
    sim,
    timing: FirmwareTiming,
    imu_noise: ImuNoise | None,
    seed: int,
    servo_ping,
    leg_map: tuple[int, ...] = ext.IDENTITY_LEG_MAP,
    now: float = 0.0,
) -> RobotFirmware | NativeRobotFirmware:
    """Return the emulated robot's firmware booted at ``now``: the Python model or the C++ one."""
    if kind == 'native':
        return NativeRobotFirmware(
            sim,
            timing,
            imu_noise=imu_noise,
            seed=seed,
            now=now,
            servo_ping=servo_ping,
            leg_map=leg_map,
        )
    return RobotFirmware(
        sim=sim,
        walk_duration=timing.walk_duration,
        failsafe_windows=timing.failsafe_windows,
        telemetry_ticks=timing.telemetry_ticks,
        ping_check_ticks=timing.ping_check_ticks,
        imu_noise=imu_noise,
        seed=seed,
        now=now,
        servo_ping=servo_ping,
        leg_map=leg_map,
    )


def print_stats(firmware: RobotFirmware | NativeRobotFirmware) -> None:
    """Print the firmware's frame and link counters."""
    stats = firmware.stats
    print(
        f'STATS pings={stats.pings} failsafe_trips={stats.failsafe_trips}'
        f' missed_windows={stats.missed_windows} frames={stats.frames}'
        f' duplicates={stats.duplicates} resyncs={firmware.resyncs}',
        flush=True,
    )


if __name__ == '__main__':
    sys.exit(main())
