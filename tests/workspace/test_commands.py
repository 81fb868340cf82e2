# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Every console command on bad input and on the normal signals.

Each ends with one line naming the problem, a non-zero status, no traceback, and loses nothing.
Table-driven: the numeric options at their bounds and just outside (in-process, through each
command's own ``main``), bad paths (through the installed executables), and SIGINT / SIGTERM
while each long-running command runs (real processes; the signal is sent once the command has
installed its handler, read from /proc, so no case depends on timing).
"""

from __future__ import annotations

from dataclasses import dataclass
import os
from pathlib import Path
import signal
import subprocess
import time
from typing import Callable

from hexapod_util.processes import child_pids, is_running
import pytest

from conftest import executable, wait_for

PACKAGE = {
    'generate_map': 'hexapod_adapt',
    'adapt_client': 'hexapod_adapt',
    'run_experiment': 'hexapod_adapt',
    'run_navigation': 'hexapod_navigation',
    'navigate_client': 'hexapod_navigation',
    'plot_map': 'hexapod_adapt',
    'recover_recording': 'hexapod_adapt',
    'report_distance': 'hexapod_adapt',
    'adapt_service': 'hexapod_adapt',
    'robot_emulator': 'hexapod_bridge',
    'firmware_fuzz': 'hexapod_bridge',
    'leg_check': 'hexapod_bridge',
    'render_walk': 'hexapod_sim',
    'fidelity_table': 'hexapod_sim',
    'footfall': 'hexapod_gait',
    'describe': 'hexapod_description',
}
DEMO_MAP = str(Path(__file__).resolve().parents[2] / 'hexapod_adapt' / 'maps' / 'demo_map.npz')


def _main(command: str) -> Callable[[list[str]], int]:
    """The function a command's executable runs (adapt_client: its parser only, no ROS)."""
    if command == 'generate_map':
        from hexapod_adapt.mapping.generate_map_cli import main
    elif command == 'adapt_client':
        from hexapod_adapt.ros.adapt_client_cli import build_parser

        return lambda argv: build_parser().parse_args(argv)
    elif command == 'report_distance':
        from hexapod_adapt.ros.report_distance_cli import build_parser

        return lambda argv: build_parser().parse_args(['0.5', *argv])
    elif command == 'adapt_service':
        from hexapod_adapt.ros.adapt_service_cli import build_parser

        return lambda argv: build_parser().parse_args(['forget', *argv])
    elif command == 'run_experiment':
        from hexapod_adapt.online.run_experiment_cli import main
    elif command == 'run_navigation':
        from hexapod_navigation.offline.run_navigation_cli import main
    elif command == 'navigate_client':
        from hexapod_navigation.ros.navigate_client_cli import build_parser

        return lambda argv: build_parser().parse_args(argv)
    elif command == 'robot_emulator':
        from hexapod_bridge.emulator.robot_emulator_cli import main
    elif command == 'firmware_fuzz':
        from hexapod_bridge.emulator.firmware_fuzz_cli import main
    elif command == 'leg_check':
        from hexapod_bridge.leg_check_cli import build_parser

        return lambda argv: build_parser().parse_args(['2', *argv])
    elif command == 'render_walk':
        from hexapod_sim.render_walk_cli import main
    elif command == 'footfall':
        from hexapod_gait.footfall_cli import main
    else:
        raise KeyError(command)
    return main


@dataclass(frozen=True)
class Bound:
    """A numeric option's range as its command states it."""

    command: str
    option: str
    low: float | None
    high: float | None
    integer: bool = True
    low_open: bool = False
    zero_means_default: bool = False


BOUNDS = [
    Bound('generate_map', '--niches', 2, 10_000_000),
    Bound('generate_map', '--evaluations', 1, 10**12),
    Bound('generate_map', '--seed', 0, 2**32 - 1),
    Bound('generate_map', '--workers', 0, 4096),
    Bound('generate_map', '--lag', 0, 1_000_000),
    Bound('generate_map', '--chunk', 0, 100_000),
    Bound('generate_map', '--random-init', 0.0, 1.0, integer=False),
    Bound('generate_map', '--cvt-samples', 1, 10**9),
    Bound('generate_map', '--checkpoint-every', 0.0, None, integer=False, low_open=True),
    Bound('generate_map', '--log-every', 0.0, None, integer=False, low_open=True),
    Bound('generate_map', '--emitter-count', 1, 64),
    Bound('generate_map', '--emitter-batch', 1, 10_000),
    Bound('generate_map', '--sigma0', 1e-4, 1.0, integer=False),
    Bound('generate_map', '--lanes', 1, 64),
    Bound('report_distance', '--timeout', 0.0, 3600.0, False, low_open=True),
    Bound('adapt_service', '--timeout', 0.0, 3600.0, False, low_open=True),
    Bound('adapt_client', '--max-trials', 1, 1000, zero_means_default=True),
    Bound('adapt_client', '--trial-duration', 1.0, 120.0, False, zero_means_default=True),
    Bound('adapt_client', '--alpha', 0.05, 1.0, False, zero_means_default=True),
    Bound('adapt_client', '--kappa', 0.0, 100.0, False),
    Bound('adapt_client', '--length-scale', 1e-3, 10.0, False, zero_means_default=True),
    Bound('adapt_client', '--noise', 1e-9, 1.0, False, zero_means_default=True),
    Bound('adapt_client', '--stop-gain', 1e-6, 1.0, False, zero_means_default=True),
    Bound('adapt_client', '--timeout', 0.0, 1e6, False, low_open=True),
    Bound('run_experiment', '--max-trials', 1, 1000),
    Bound('run_experiment', '--alpha', 0.05, 1.0, False),
    Bound('run_experiment', '--kappa', 0.0, 100.0, False),
    Bound('run_experiment', '--length-scale', 1e-3, 10.0, False),
    Bound('run_experiment', '--noise', 1e-9, 1.0, False),
    Bound('run_experiment', '--stop-gain', 1e-6, 1.0, False),
    Bound('run_navigation', '--goals', 1, 1000),
    Bound('run_navigation', '--goal-seed', 0, 2**32 - 1),
    Bound('run_navigation', '--workers', 1, 256),
    Bound('run_navigation', '--tolerance', 0.0, 10.0, False, low_open=True),
    Bound('run_navigation', '--time-limit', 0.0, 3600.0, False, low_open=True),
    Bound('run_navigation', '--length-scale', 0.0, 10.0, False, low_open=True),
    Bound('navigate_client', '--tolerance', 0.0, 10.0, False),
    Bound('navigate_client', '--time-limit', 0.0, 3600.0, False),
    Bound('navigate_client', '--timeout', 0.0, 1e6, False, low_open=True),
    Bound('leg_check', '--timeout', 0.0, 600.0, False, low_open=True),
    Bound('robot_emulator', '--seed', 0, 2**32 - 1),
    Bound('robot_emulator', '--walk-duration', 0.0, 600.0, False, low_open=True),
    Bound('robot_emulator', '--failsafe-windows', 1, 1000),
    Bound('robot_emulator', '--dead-servo', 2, 19),
    Bound('firmware_fuzz', '--frames', 1, 10**8),
    Bound('firmware_fuzz', '--seed', 0, 2**31),
    Bound('firmware_fuzz', '--chunk', 1000, 10**7),
    Bound('firmware_fuzz', '--dead-servo', 2, 19),
    Bound('render_walk', '--seconds', 0.0, 60.0, False, low_open=True),
    Bound('render_walk', '--fps', 1, 60),
    Bound('render_walk', '--failed-legs', 1, 6),
    Bound('footfall', '--cycles', 0.0, 100.0, False, low_open=True),
]
REQUIRED = {'generate_map': ['--out', '{tmp}/map.npz'], 'navigate_client': ['1.0', '0.5']}


def _cases():
    for b in BOUNDS:
        for end, value in (('low', b.low), ('high', b.high)):
            if value is None:
                continue
            step = 1 if b.integer else (abs(value) * 1e-3 or 1e-6)
            if end == 'low':
                inside = value + step if b.low_open else value
                outside = value if b.low_open else value - step
            else:
                inside, outside = value, value + step
            yield b, inside, True
            yield b, outside, outside == 0 and b.zero_means_default


def _text(value: float, integer: bool) -> str:
    return str(int(value)) if integer else repr(float(value))


@pytest.mark.parametrize(
    'bound, value, accepted',
    list(_cases()),
    ids=[f'{b.command}{b.option}={v:g}' for b, v, _ in _cases()],
)
def test_numeric_options_at_their_bounds_and_just_outside(
    bound, value, accepted, tmp_path, capsys
):
    required = [a.format(tmp=tmp_path) for a in REQUIRED.get(bound.command, [])]
    # an unknown option after the one under test: argparse converts (and checks) every value in
    # order, then refuses the unknown one, so nothing runs either way
    argv = [*required, f'{bound.option}={_text(value, bound.integer)}', '--zzz-not-an-option']
    with pytest.raises(SystemExit) as info:
        _main(bound.command)(argv)
    error = capsys.readouterr().err.strip().splitlines()[-1]
    assert info.value.code == 2
    if accepted:
        assert 'unrecognized arguments: --zzz-not-an-option' in error, error
    else:
        assert f'argument {bound.option}:' in error and 'must be' in error, error


# -- paths, through the installed executables -------------------------------------------------
def _run(command: str, *args: str, timeout: float = 120) -> subprocess.CompletedProcess:
    return subprocess.run(
        [str(executable(PACKAGE[command], command)), *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        env=dict(os.environ, PYTHONUNBUFFERED='1'),
        stdin=subprocess.DEVNULL,
    )


def _last_line(proc) -> str:
    lines = [line for line in proc.stderr.splitlines() if line.strip()]
    return lines[-1] if lines else ''


PATHS = [
    ('generate_map', ['--out', '{dir}'], 'is a directory, not a file'),
    ('generate_map', ['--out', '{file}/map.npz'], 'is not a directory'),
    ('generate_map', ['--out', '/proc/hexapod/map.npz'], 'cannot create directory /proc/hexapod'),
    ('generate_map', ['--out', '/proc/map.npz'], 'cannot write in /proc'),
    ('generate_map', ['--out', '{dir}/m.npz', '--cvt-dir', '{file}'], 'is not a directory'),
    ('generate_map', ['--out', '{dir}/m.npz', '--log', '{dir}'], 'is a directory, not a file'),
    ('run_experiment', ['--archive', '{missing}'], 'no such file'),
    ('run_experiment', ['--archive', '{dir}'], 'is a directory, not a file'),
    ('run_experiment', ['--archive', '{garbage}'], 'garbage'),
    ('run_experiment', ['--out-dir', '{file}'], 'is not a directory'),
    ('run_experiment', ['--out', '{dir}'], 'is a directory, not a file'),
    ('run_navigation', ['--repertoire', '{missing}'], 'no such file'),
    ('run_navigation', ['--repertoire', '{dir}'], 'is a directory, not a file'),
    ('run_navigation', ['--repertoire', '{garbage}'], 'garbage'),
    ('run_navigation', ['--repertoire', DEMO_MAP], 'not a navigation repertoire'),
    ('run_navigation', ['--out-dir', '{file}'], 'is not a directory'),
    ('plot_map', ['--archive', '{missing}'], 'no such file'),
    ('plot_map', ['--archive', '{garbage}'], 'garbage'),
    ('plot_map', ['--archive', DEMO_MAP, '--out-dir', '{file}'], 'is not a directory'),
    ('plot_map', ['--archive', DEMO_MAP, '--log', '{dir}'], 'is a directory, not a file'),
    ('recover_recording', ['{missing}'], 'no such file'),
    ('recover_recording', ['{dir}'], 'is a directory, not a file'),
    ('recover_recording', ['{garbage}', '--out', '{dir}'], 'is a directory, not a file'),
    ('recover_recording', ['{garbage}', '--out', '/proc/x.mcap'], 'cannot write in /proc'),
    ('robot_emulator', ['--radio-link', '{file}/radio'], 'Not a directory'),
    ('robot_emulator', ['--radio-link', '/proc/hexapod_radio'], 'hexapod_radio'),
    ('render_walk', ['--out', '{dir}'], 'is a directory, not a file'),
    ('render_walk', ['--out', '{file}/walk.gif'], 'is not a directory'),
    ('fidelity_table', ['--agreement-map', '{missing}'], 'no such file'),
    ('fidelity_table', ['--agreement-map', '{dir}'], 'is a directory, not a file'),
    ('footfall', ['--out', '{file}'], 'is not a directory'),
    ('footfall', ['--out', '/proc/footfall'], 'cannot create directory /proc/footfall'),
    ('describe', ['--urdf', '{missing}'], 'no such file'),
    ('describe', ['--urdf', '{dir}'], 'is a directory, not a file'),
    ('describe', ['--urdf', '{garbage}'], 'garbage'),
]


@pytest.mark.slow
@pytest.mark.parametrize(
    'command, args, says', PATHS, ids=[f'{c}-{" ".join(a)}' for c, a, _ in PATHS]
)
def test_bad_paths_end_with_one_line_that_names_them(command, args, says, tmp_path):
    places = {
        'dir': tmp_path / 'a_directory',
        'file': tmp_path / 'a_file',
        'missing': tmp_path / 'missing.npz',
        'garbage': tmp_path / 'garbage.npz',
    }
    places['dir'].mkdir()
    places['file'].write_text('a file, not a directory\n')
    places['garbage'].write_bytes(b'\x00garbage' * 10)
    proc = _run(command, *(a.format(**places) for a in args))
    line = _last_line(proc)
    assert proc.returncode != 0, (proc.stdout, proc.stderr)
    assert 'Traceback' not in proc.stderr, proc.stderr
    assert line.startswith(f'{command}: ') and says in line, proc.stderr


# -- signals, through the installed executables ------------------------------------------------
def _handles_sigterm(pid: int) -> bool:
    """Whether the process has installed its SIGTERM handler (it is past start-up)."""
    try:
        status = Path(f'/proc/{pid}/status').read_text()
    except OSError:
        return False
    caught = int(
        next(line for line in status.splitlines() if line.startswith('SigCgt:')).split()[1], 16
    )
    return bool(caught & (1 << (signal.SIGTERM - 1)))


RUNNING = {
    'generate_map': [
        '--out',
        '{tmp}/map.npz',
        '--niches',
        '20',
        '--evaluations',
        '100000000',
        '--checkpoint-every',
        '0.2',
        '--workers',
        '1',
        '--quiet',
    ],
    'adapt_client': ['--timeout', '600'],
    'run_experiment': ['--archive', DEMO_MAP, '--trial-engine', 'pybullet'],
    'run_navigation': ['--workers', '1', '--engine', 'pybullet'],
    'robot_emulator': ['--radio-link', '{tmp}/radio', '--sim'],
    'render_walk': ['--seconds', '60', '--out', '{tmp}/walk.gif'],
    'fidelity_table': ['--engine', 'pybullet'],
}


def _start(command: str, args: list[str]) -> subprocess.Popen:
    """Start ``command`` as from a terminal, its output captured."""
    return subprocess.Popen(
        [str(executable(PACKAGE[command], command)), *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        stdin=subprocess.DEVNULL,
        # faulthandler: a command still running past the time allowed shows where it is (SIGABRT)
        env=dict(os.environ, PYTHONUNBUFFERED='1', PYTHONFAULTHANDLER='1'),
        # as from a terminal: a suite started in the background (nohup ... &) ignores SIGINT, and
        # its children would inherit that
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )


def _stop(proc: subprocess.Popen, command: str, signum: int, within: float) -> tuple[str, str]:
    """Send ``signum``; return the output of a command that ended ``within`` s (else fail)."""
    proc.send_signal(signum)
    try:
        return proc.communicate(timeout=within)
    except subprocess.TimeoutExpired:
        proc.send_signal(signal.SIGABRT)
        _, err = proc.communicate(timeout=30)
        pytest.fail(f'{command} still ran {within:g} s after {signum!r}; where it was:\n{err}')


def _last_line_names(err: str, command: str, signum: int) -> list[str]:
    """Check stderr ends in the command's one line naming the signal; return its lines."""
    lines = [line for line in err.splitlines() if line.strip()]
    name = signal.Signals(signum).name
    assert 'Traceback' not in err, err
    assert lines and lines[-1].startswith(f'{command}: ') and name in lines[-1], err
    return lines


@pytest.mark.slow
@pytest.mark.parametrize('signum', [signal.SIGINT, signal.SIGTERM], ids=['SIGINT', 'SIGTERM'])
@pytest.mark.parametrize('command', sorted(RUNNING))
def test_a_signal_while_running_ends_with_one_line_and_its_status(
    command, signum, tmp_path, domain_id
):
    proc = _start(command, [a.format(tmp=tmp_path) for a in RUNNING[command]])
    try:
        wait_for(lambda: _handles_sigterm(proc.pid), 60, f'{command} to install its handlers')
        if command == 'generate_map':  # a checkpoint exists: it must survive the signal
            checkpoint = tmp_path / 'map.npz.ckpt.npz'
            wait_for(checkpoint.exists, 120, 'the first checkpoint')
        out, err = _stop(proc, command, signum, 60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 128 + signum, (out, err)
    lines = _last_line_names(err, command, signum)
    if command == 'generate_map':
        from hexapod_adapt.mapping.map_elites import load_checkpoint

        load_checkpoint(checkpoint)  # intact: --resume continues from it
        assert '--resume' in lines[-1]


POOLED = {  # the commands that walk gaits in a pool of worker processes, with two workers
    'run_navigation': ['--workers', '2', '--engine', 'pybullet', '--goals', '5'],
    'generate_map': RUNNING['generate_map'][:-2] + ['2', '--quiet'],
}


@pytest.mark.slow
@pytest.mark.parametrize('command', sorted(POOLED))
def test_a_stop_ends_a_pool_command_and_its_workers_at_once(command, tmp_path, domain_id):
    # a stop used to wait for the jobs the workers were running and could then hang for good
    # (run_navigation --workers 2 still ran 10 minutes after its SIGTERM)
    proc = _start(command, [a.format(tmp=tmp_path) for a in POOLED[command]])
    try:
        wait_for(lambda: len(child_pids(proc.pid)) >= 2, 60, f'{command} to start its workers')
        workers = child_pids(proc.pid)
        time.sleep(3)  # the workers busy with their first jobs
        _, err = _stop(proc, command, signal.SIGTERM, 15)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 128 + signal.SIGTERM, err
    _last_line_names(err, command, signal.SIGTERM)
    wait_for(lambda: not any(is_running(w) for w in workers), 5, 'the workers to end')


# -- the output rule: nothing a user has is destroyed (issue 32) --------------------------------
def _digest(path: Path) -> str:
    import hashlib

    if path.is_symlink():
        return 'link:' + os.readlink(path)
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _a_recording(path: Path) -> Path:
    """A small finished MCAP recording, written by the product's recorder."""
    from hexapod_util.recording import McapRecorder
    from nav_msgs.msg import Odometry

    with McapRecorder(path) as rec:
        for _ in range(5):
            rec.record('odom', Odometry())
    return path


#: (command, arguments, outputs that exist already, what the refusal says). Every command that
#: writes a file, with each kind of output it writes.
EXISTING = [
    (
        'generate_map',
        ['--out', '{out}/map.npz', '--niches', '20', '--evaluations', '50', '--workers', '1'],
        ['map.npz'],
        'already exists: --resume to continue it, or --force',
    ),
    (
        'generate_map',
        ['--out', '{out}/map.npz', '--niches', '20', '--evaluations', '50', '--workers', '1'],
        ['map.npz.ckpt.npz', 'map.npz.log.jsonl'],
        'already exist: --resume to continue it, or --force',
    ),
    (
        'run_experiment',
        ['--archive', DEMO_MAP, '--scenarios', 'S2', '--out', '{out}/runs.csv'],
        ['runs.csv'],
        'already exists: --force',
    ),
    (
        'run_experiment',
        ['--archive', DEMO_MAP, '--scenarios', 'S2', '--out-dir', '{out}'],
        ['trials.png'],
        'already exists: --force',
    ),
    (
        'run_navigation',
        ['--scenarios', 'S0', '--goals', '1', '--methods', 'tripod', '--out-dir', '{out}'],
        ['summary.json'],
        'already exists: --force',
    ),
    ('plot_map', ['--archive', DEMO_MAP, '--out-dir', '{out}'], ['demo_map_projections.png'], ''),
    ('recover_recording', ['{recording}'], ['rec.recovered.mcap'], 'already exists: --force'),
    (
        'recover_recording',
        ['{recording}', '--out', '{out}/copy.mcap'],
        ['copy.mcap'],
        'already exists: --force',
    ),
    ('recover_recording', ['{recording}', '--in-place'], ['rec.mcap.orig'], 'already exists'),
    ('render_walk', ['--seconds', '0.5', '--out', '{out}/walk.gif'], ['walk.gif'], '--force'),
    ('footfall', ['--out', '{out}'], ['footfall_wave.png'], 'already exists: --force'),
    (
        'robot_emulator',
        ['--radio-link', '{out}/radio'],
        ['radio'],
        'exists and is not a pseudo-terminal link',
    ),
]


@pytest.mark.parametrize(
    'command, args, existing, says',
    EXISTING,
    ids=[f'{c}-{"+".join(e)}' for c, _, e, _ in EXISTING],
)
def test_an_existing_output_is_refused_and_left_byte_identical(
    command, args, existing, says, tmp_path
):
    out = tmp_path / 'out'
    out.mkdir()
    recording = _a_recording(out / 'rec.mcap')
    for name in existing:
        (out / name).write_bytes(f"the user's {name}, made by hand\n".encode())
    before = {p.name: _digest(p) for p in out.iterdir()}
    proc = _run(command, *(a.format(out=out, recording=recording) for a in args))
    line = _last_line(proc)
    assert proc.returncode != 0, (proc.stdout, proc.stderr)
    assert 'Traceback' not in proc.stderr, proc.stderr
    assert line.startswith(f'{command}: ') and existing[0] in line and says in line, proc.stderr
    assert {p.name: _digest(p) for p in out.iterdir()} == before  # nothing changed or added


@pytest.mark.slow
@pytest.mark.parametrize(
    'command, args, output',
    [
        (
            'generate_map',
            ['--out', '{out}/map.npz', '--niches', '20', '--evaluations', '50', '--workers', '1'],
            'map.npz',
        ),
        ('footfall', ['--out', '{out}', '--preset', 'wave'], 'footfall_wave.png'),
        ('recover_recording', ['{recording}', '--out', '{out}/copy.mcap'], 'copy.mcap'),
    ],
    ids=['generate_map', 'footfall', 'recover_recording'],
)
def test_force_replaces_an_output_and_keeps_the_old_one_as_bak(command, args, output, tmp_path):
    out = tmp_path / 'out'
    out.mkdir()
    recording = _a_recording(out / 'rec.mcap')
    old = b'an older result the user may still want\n'
    (out / output).write_bytes(old)
    proc = _run(command, *(a.format(out=out, recording=recording) for a in args), '--force')
    assert proc.returncode == 0, proc.stderr
    assert (out / f'{output}.bak').read_bytes() == old
    assert (out / output).read_bytes() != old


#: (command, arguments, inputs): a normal run reads its inputs and never modifies them.
INPUTS = [
    ('plot_map', ['--archive', '{map}', '--log', '{log}', '--out-dir', '{out}'], ['map', 'log']),
    (
        'run_experiment',
        ['--archive', '{map}', '--scenarios', 'S2', '--max-trials', '2', '--out-dir', '{out}'],
        ['map'],
    ),
    (
        'run_navigation',
        [
            '--repertoire',
            '{repertoire}',
            '--scenarios',
            'S0',
            '--goals',
            '1',
            '--out-dir',
            '{out}',
        ],
        ['repertoire'],
    ),
    ('recover_recording', ['{recording}'], ['recording']),
    ('describe', ['--urdf', '{urdf}'], ['urdf']),
]


@pytest.mark.slow
@pytest.mark.parametrize('command, args, inputs', INPUTS, ids=[c for c, _, _ in INPUTS])
def test_a_command_never_modifies_its_inputs(command, args, inputs, tmp_path):
    import shutil

    from hexapod_description import urdf_path
    from hexapod_navigation.core.repertoire import shipped_repertoire

    src = tmp_path / 'inputs'
    src.mkdir()
    demo = Path(DEMO_MAP)
    files = {
        'map': shutil.copy(demo, src / 'demo_map.npz'),
        'log': shutil.copy(demo.with_name('demo_map.log.jsonl'), src / 'demo_map.log.jsonl'),
        'repertoire': shutil.copy(shipped_repertoire(), src / 'navigation_map.npz'),
        'recording': _a_recording(src / 'rec.mcap'),
        'urdf': shutil.copy(urdf_path(), src / 'hexapod.urdf'),
    }
    files = {k: Path(v) for k, v in files.items()}
    before = {name: _digest(files[name]) for name in inputs}
    places = {**files, 'out': tmp_path / 'out'}
    proc = _run(command, *(a.format(**places) for a in args))
    assert proc.returncode == 0, proc.stderr
    assert {name: _digest(files[name]) for name in inputs} == before


def test_adapt_client_names_a_damage_of_any_kind_and_refuses_nonsense(capsys):
    from hexapod_adapt.ros.adapt_client_cli import build_parser

    args = build_parser().parse_args(['--damage', '3:unpowered:femur,5:weak:0.3'])
    assert args.damage.as_lists() == ([3, 5], ['unpowered', 'weak'], [1.0, 0.3], ['femur', ''])
    for argv, says in (
        (['--damage', '2:melted'], "unknown damage kind 'melted'"),
        (['--damage', '1:locked,2:locked,3:locked'], 'at most 2 legs'),
        (['--damage', '2:unpowered:knee'], "got ['knee']"),
        (['--damage', ''], 'names no leg'),
        (['--damage', '2:locked', '--failed-legs', '2'], 'not allowed with argument'),
    ):
        with pytest.raises(SystemExit) as stop:
            build_parser().parse_args(argv)
        assert stop.value.code == 2
        assert says in capsys.readouterr().err, argv
