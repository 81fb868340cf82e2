# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The console commands' shared behaviour: bounded numbers, paths, signals, one-line errors."""

import argparse
import os
import signal
import sys
import time

from hexapod_util.cli import (
    acknowledge_stop,
    input_file,
    interval,
    number,
    output_dir,
    output_file,
    run_command,
    STATUS_INTERRUPTED,
    STATUS_TERMINATED,
)
import pytest


def test_number_takes_its_bounds_and_refuses_just_outside():
    fps = number(int, 1, 60)
    assert fps('1') == 1 and fps('60') == 60
    for text in ('0', '61', '1.5', 'x'):
        with pytest.raises(argparse.ArgumentTypeError):
            fps(text)
    seconds = number(float, 0, 60, low_open=True)
    assert seconds('1e-9') == 1e-9 and seconds('60') == 60.0
    with pytest.raises(argparse.ArgumentTypeError, match=r'must be in \(0, 60\], got 0'):
        seconds('0')
    for text in ('nan', 'inf', '-inf'):
        with pytest.raises(argparse.ArgumentTypeError, match='finite'):
            seconds(text)
    assert interval(None, None) == '(-inf, inf)' and interval(2, 10_000_000) == '[2, 10000000]'


def test_paths_are_checked_before_any_work(tmp_path):
    a_file = tmp_path / 'file'
    a_file.write_text('x')
    assert input_file(str(a_file)) == a_file
    with pytest.raises(argparse.ArgumentTypeError, match='no such file'):
        input_file(str(tmp_path / 'missing'))
    with pytest.raises(argparse.ArgumentTypeError, match='is a directory, not a file'):
        input_file(str(tmp_path))
    assert output_file(str(tmp_path / 'new' / 'out.npz')) == tmp_path / 'new' / 'out.npz'
    assert (tmp_path / 'new').is_dir()  # created, as the command would
    with pytest.raises(argparse.ArgumentTypeError, match='is a directory, not a file'):
        output_file(str(tmp_path))
    with pytest.raises(argparse.ArgumentTypeError, match='is not a directory'):
        output_file(str(a_file / 'out.npz'))
    with pytest.raises(argparse.ArgumentTypeError, match='is not a directory'):
        output_dir(str(a_file))
    with pytest.raises(argparse.ArgumentTypeError, match='cannot write in /proc'):
        output_dir('/proc')


def test_run_command_turns_bad_input_and_signals_into_one_line(capsys):
    def missing():
        open('/nonexistent/hexapod/x')

    assert run_command('cmd', missing) == 1
    assert capsys.readouterr().err == 'cmd: No such file or directory: /nonexistent/hexapod/x\n'
    assert run_command('cmd', lambda: int('seven')) == 1
    assert 'invalid literal' in capsys.readouterr().err

    def interrupted():
        raise KeyboardInterrupt

    assert run_command('cmd', interrupted, 'resume with --resume') == STATUS_INTERRUPTED
    assert capsys.readouterr().err == 'cmd: interrupted (SIGINT); resume with --resume\n'

    def terminated():
        os.kill(os.getpid(), signal.SIGTERM)
        raise AssertionError('SIGTERM did not stop the body')

    before = signal.getsignal(signal.SIGTERM)
    assert run_command('cmd', terminated) == STATUS_TERMINATED
    assert capsys.readouterr().err == 'cmd: terminated (SIGTERM)\n'
    assert signal.getsignal(signal.SIGTERM) is before  # restored

    def bug():
        raise KeyError('a programming error keeps its traceback')

    with pytest.raises(KeyError):
        run_command('cmd', bug)


@pytest.mark.parametrize('signum', [signal.SIGINT, signal.SIGTERM], ids=['SIGINT', 'SIGTERM'])
def test_a_stop_dropped_by_a_destructor_still_ends_the_command(signum, capsys):
    # Python drops an exception raised in a destructor or a weakref callback (CI saw a Ctrl-C
    # land in the import system's module-lock callback, and the command ran on)
    dropped = []

    class Victim:
        """An object whose destructor receives the signal."""

        def __del__(self):
            try:
                os.kill(os.getpid(), signum)
                time.sleep(0.2)  # the handler raises here, inside the destructor
            finally:
                dropped.append(True)

    def body():
        Victim()  # collected at once
        assert dropped
        time.sleep(10)  # the stop, sent again, ends this
        return 0

    previous_int = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        start = time.monotonic()
        status = run_command('cmd', body)
    finally:
        signal.signal(signal.SIGINT, previous_int)
    assert status == 128 + signum
    assert time.monotonic() - start < 5
    err = capsys.readouterr().err
    assert 'Traceback' not in err and err.endswith(f'({signal.Signals(signum).name})\n'), err


@pytest.mark.parametrize('signum', [signal.SIGINT, signal.SIGTERM], ids=['SIGINT', 'SIGTERM'])
def test_a_stop_a_library_swallows_is_sent_again(signum, capsys):
    # CI: run_navigation ran on for 60 s after a SIGINT; a library that catches the
    # KeyboardInterrupt and goes on must not keep the command running
    swallowed = []

    def body():
        try:
            os.kill(os.getpid(), signum)
            time.sleep(5)  # the handler raises here
        except KeyboardInterrupt:  # as a library that retries might
            swallowed.append(True)
        time.sleep(10)  # the stop, sent again, ends this
        return 0

    previous_int = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        start = time.monotonic()
        status = run_command('cmd', body, resend_after=0.5)
    finally:
        signal.signal(signal.SIGINT, previous_int)
    assert swallowed and status == 128 + signum
    assert time.monotonic() - start < 5
    name = signal.Signals(signum).name
    assert capsys.readouterr().err == f'cmd: {_STOP_WORD[signum]} ({name})\n'
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored


def test_a_stop_in_hand_is_not_sent_again(capsys):
    cleaned = []

    def body():
        try:
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(5)
        except KeyboardInterrupt:
            acknowledge_stop()  # a clean-up longer than resend_after: it must not be cut
            time.sleep(1.0)
            cleaned.append(True)
            raise
        return 0

    assert run_command('cmd', body, resend_after=0.2) == STATUS_TERMINATED
    assert cleaned
    assert capsys.readouterr().err == 'cmd: terminated (SIGTERM)\n'


_STOP_WORD = {signal.SIGINT: 'interrupted', signal.SIGTERM: 'terminated'}


def test_a_stop_inside_a_constructor_leaves_no_destructor_traceback(capsys):
    # CI: SIGTERM landed inside ZipFile's constructor (np.load of a cache file); the half-built
    # ZipFile's destructor then failed ("Exception ignored ... no attribute '_writing'")

    class HalfBuilt:
        """Stopped before its constructor set what its destructor needs."""

        def __init__(self):
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.2)  # the handler raises here
            self.ready = True

        def __del__(self):
            if self.ready:  # AttributeError: the constructor never got here
                pass

    def body():
        keep = []
        keep.append(HalfBuilt())  # never appended: the stop ends the constructor
        return 0

    reported = []  # what would be printed as "Exception ignored in ..."
    before = sys.unraisablehook
    sys.unraisablehook = reported.append
    try:
        assert run_command('cmd', body) == STATUS_TERMINATED
        assert sys.unraisablehook == reported.append  # quiet only while the command ends
    finally:
        sys.unraisablehook = before
    assert capsys.readouterr().err == 'cmd: terminated (SIGTERM)\n'
    assert reported == []
