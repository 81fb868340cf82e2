# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Differential tests of the C++ firmware module (firmware/) against the Python model.

A :class:`Script` of timed events (radio bytes arrive, the main loop polls, print the table) runs
through both: the model in-process (:func:`run_model`), the module through its sanitizer-built
``fw_replay`` tool (:func:`run_native`). Both print the same lines: the bytes sent and the state
after every event, the gait when it changes, the 120 Hz table and the servo targets (with the fold
of a leg with a dead servo) on request. :func:`compare` finds the first divergence; gait tables
and targets agree within the module's fixed-point units (TABLE_TOLERANCE).
:func:`fuzz_script` makes a seeded script of random frames: uploads of random gaits, every
command, legacy frames, duplicates, garbage, truncated and corrupted frames, gaps that trip the
failsafe. ``firmware_fuzz`` (CLI) runs one.
"""

from __future__ import annotations

from dataclasses import dataclass
import os
import subprocess
import time

from hexapod_bridge.emulator.firmware import RobotFirmware
from hexapod_bridge.emulator.scripts import fuzz_script, gait_values, Script
from hexapod_bridge.protocol import extension as ext
from hexapod_bridge.protocol.stream import HostParser
import numpy as np

#: Largest difference between the two gait tables: half the module's fixed-point unit (positions
#: 2e-4 rad, rates 1e-3 rad/s) plus float32 rounding.
TABLE_TOLERANCE = {'position': 1.0e-4 + 1e-6, 'velocity': 5.0e-4 + 1e-5}
#: The module stores joint rates in int16 units of 1e-3 rad/s: larger ones are clipped.
VELOCITY_LIMIT = 32.767


class FirmwareBuildMissing(FileNotFoundError):
    """The C++ module's host build (package hexapod_firmware) is not installed; says what to do."""


def firmware_prefix() -> str:
    """Return the install prefix of the hexapod_firmware package (the C++ module's host build)."""
    from ament_index_python.packages import get_package_prefix, PackageNotFoundError

    try:
        return get_package_prefix('hexapod_firmware')
    except PackageNotFoundError:
        raise FirmwareBuildMissing(
            'package hexapod_firmware is not built: run scripts/bootstrap.sh (colcon build)'
        ) from None


def replay_tool() -> str:
    """Return the path of the sanitizer-built fw_replay tool."""
    path = os.path.join(firmware_prefix(), 'lib', 'hexapod_firmware', 'fw_replay')
    if not os.access(path, os.X_OK):
        raise FirmwareBuildMissing(f'{path} is missing: rebuild package hexapod_firmware')
    return path


def run_model(script: Script) -> list[str]:
    """Run a script through the Python model; return its output lines (fw_replay's format)."""
    t = script.timing
    fw = RobotFirmware(
        walk_duration=t.walk_duration,
        failsafe_windows=t.failsafe_windows,
        telemetry_ticks=t.telemetry_ticks,
        ping_check_ticks=t.ping_check_ticks,
        now=script.start_ms / 1000.0,
        servo_ping=lambda servo: servo not in script.dead_servos,
        leg_map=script.leg_map,
    )
    lines: list[str] = []
    last = gait_values(fw.gait)
    for event in script.events:
        if event[0] == 'S':
            targets = fw.servo_targets
            lines.append(
                f'S {targets.writes} ' + ' '.join(repr(float(v)) for v in targets.position)
            )
            continue
        if event[0] == 'T':
            table = fw.robot_table
            lines.append(f'T {len(table)}')
            lines.extend(
                ' '.join(repr(float(v)) for v in np.concatenate([p, v]))
                for p, v in zip(table.positions, table.velocities)
            )
            continue
        if event[0] == 'B':
            fw.receive(event[2], event[1] / 1000.0)
            radio = bytes(fw.out_radio)
            fw.out_radio.clear()
        else:
            radio, _ = fw.advance(event[1] / 1000.0)
        staged = sum(v is not None for v in fw.staged)
        lines.append(
            f'E {radio.hex() or "-"} {int(fw.walking)} {int(fw.estopped)} {int(fw.motors_on)}'
            f' {fw.gait_id} {staged} {fw._tick_count} {int(fw.trial_state)} {len(fw.robot_table)}'
        )
        values = gait_values(fw.gait)
        if values != last:
            lines.append('G ' + ' '.join(repr(v) for v in values))
            last = values
    return lines


def run_native(script: Script, tool: str | None = None, timeout: float = 600.0) -> list[str]:
    """Run a script through the C++ module's fw_replay; return its output lines."""
    result = subprocess.run(
        [tool or replay_tool()],
        input=script.encode(),
        capture_output=True,
        timeout=timeout,
        check=False,
    )
    if result.returncode != 0:
        raise RuntimeError(
            f'fw_replay failed with exit status {result.returncode}:'
            f' {result.stderr.decode(errors="replace")[-4000:]}'
        )
    return result.stdout.decode().splitlines()


@dataclass(frozen=True)
class Divergence:
    """Where the module and the model first disagree (output line and event numbers)."""

    line: int
    event: int
    model: str
    native: str


@dataclass(frozen=True)
class Comparison:
    """The result of :func:`compare`: counts, and the first divergence if any."""

    events: int
    tables: int
    max_position_error: float
    max_velocity_error: float
    divergence: Divergence | None


def compare(model: list[str], native: list[str]) -> Comparison:
    """Compare two outputs line by line: exact; gaits by value, tables within tolerance."""
    events = tables = 0
    max_p = max_v = 0.0
    i = 0
    rows_left = 0

    def diverged(k: int) -> Comparison:
        a = model[k] if k < len(model) else '<end>'
        b = native[k] if k < len(native) else '<end>'
        return Comparison(events, tables, max_p, max_v, Divergence(k, events, a, b))

    while i < max(len(model), len(native)):
        if i >= len(model) or i >= len(native):
            return diverged(i)
        a, b = model[i], native[i]
        if rows_left:
            x = np.array(a.split(), dtype=float)
            y = np.array(b.split(), dtype=float)
            if x.shape != (36,) or y.shape != (36,):
                return diverged(i)
            dp = float(np.max(np.abs(x[:18] - y[:18])))
            dv = float(np.max(np.abs(np.clip(x[18:], -VELOCITY_LIMIT, VELOCITY_LIMIT) - y[18:])))
            max_p, max_v = max(max_p, dp), max(max_v, dv)
            if dp > TABLE_TOLERANCE['position'] or dv > TABLE_TOLERANCE['velocity']:
                return diverged(i)
            rows_left -= 1
        elif a.startswith('G ') and b.startswith('G '):
            if [float(v) for v in a.split()[1:]] != [float(v) for v in b.split()[1:]]:
                return diverged(i)
        elif a.startswith('S ') and b.startswith('S '):
            x, y = a.split()[1:], b.split()[1:]  # the writes, then 18 targets
            if len(x) != 19 or len(y) != 19 or x[0] != y[0]:
                return diverged(i)
            dp = float(np.max(np.abs(np.array(x[1:], float) - np.array(y[1:], float))))
            max_p = max(max_p, dp)
            if dp > TABLE_TOLERANCE['position']:
                return diverged(i)
        elif a.startswith('T ') and a == b:
            rows_left = int(a.split()[1])
            tables += 1
        elif a != b:
            return diverged(i)
        elif a.startswith('E '):
            events += 1
        i += 1
    return Comparison(events, tables, max_p, max_v, None)


@dataclass(frozen=True)
class FuzzResult:
    """One differential fuzz run: what it sent and whether the two firmwares agreed."""

    frames: int
    events: int
    tables: int
    commits_ok: int
    trials: int
    seconds: float
    max_position_error: float
    max_velocity_error: float
    divergence: Divergence | None


def _count_reports(lines: list[str]) -> tuple[int, int]:
    """Return (accepted COMMITs, started walks) in a model output."""
    parser, commits, walks = HostParser(), 0, 0
    for line in lines:
        if not line.startswith('E ') or line.split()[1] == '-':
            continue
        for frame in parser.feed(bytes.fromhex(line.split()[1])):
            if not isinstance(frame, ext.ReportFrame):
                continue
            if frame.type == ext.Report.ACK and frame.payload[:2] == bytes([ext.Cmd.COMMIT, 0]):
                commits += 1
            if frame.type == ext.Report.TRIAL and frame.payload[0] == ext.TrialState.WALKING:
                walks += 1
    return commits, walks


def fuzz(seed: int, frames: int, dead_servos: frozenset[int] = frozenset()) -> FuzzResult:
    """Run one seeded fuzz script through the model and the module and compare them."""
    t0 = time.monotonic()
    script = fuzz_script(seed, frames, dead_servos)
    model = run_model(script)
    native = run_native(script)
    result = compare(model, native)
    commits, walks = _count_reports(model)
    return FuzzResult(
        frames,
        result.events,
        result.tables,
        commits,
        walks,
        time.monotonic() - t0,
        result.max_position_error,
        result.max_velocity_error,
        result.divergence,
    )
