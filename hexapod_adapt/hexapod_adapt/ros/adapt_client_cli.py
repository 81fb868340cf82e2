# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
``ros2 run hexapod_adapt adapt_client``.

Send one goal to adapt_node's ``adapt`` action from a base-station PC and print each trial's
feedback as it completes (the same as ``ros2 action send_goal --feedback /adapt
hexapod_msgs/action/Adapt`` on a full ROS install). Ctrl-C cancels the run (after the trial being
walked), as ``ros2 action send_goal`` does.

    adapt_client --max-trials 20 [--alpha 0.9 --kappa 0.05 --length-scale 0.4 --noise 0.001]
    adapt_client --damage 3:unpowered:femur    # the damage known, when no report says it
    adapt_client --no-gain-stop    # a blind run ends on alpha or max_trials alone
"""

from __future__ import annotations

import argparse
import sys
import time

from action_msgs.msg import GoalStatus
from hexapod_adapt.online.mboa import (
    ALPHA_RANGE,
    KAPPA_RANGE,
    LENGTH_SCALE_RANGE,
    MAX_TRIALS_LIMIT,
    NOISE_RANGE,
    PROFILES,
    STOP_GAIN_RANGE,
)
from hexapod_adapt.online.run_config import TRIAL_DURATION_RANGE
from hexapod_adapt.ros.adapt_action import BUSY
from hexapod_msgs.action import Adapt
from hexapod_msgs.msg import AdaptationTrial
from hexapod_sim.damage import Damage, parse_damage
from hexapod_util import guarded_logging
from hexapod_util.cli import acknowledge_stop, interval, number, run_command
from hexapod_util.ros_glue import ACTION_QOS, spin_until_done, Waited
import rclpy
from rclpy.action import ActionClient
from rclpy.signals import SignalHandlerOptions


def _default_or(low: float, high: float, kind: type = float):
    """Return an argparse type: 0 means "the node's default", else a value in [low, high]."""
    check = number(kind, low, high)

    def parse(text: str):
        value = number(kind)(text)  # a number at all (the same message as any option)
        if value == 0:
            return value
        try:
            return check(text)
        except argparse.ArgumentTypeError:
            raise argparse.ArgumentTypeError(
                f"must be 0 (the node's default) or in {interval(low, high)}, got {text}"
            ) from None

    parse.__name__ = kind.__name__
    return parse


def _damage(text: str) -> Damage:
    try:
        damage = parse_damage(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    if not damage.legs:
        raise argparse.ArgumentTypeError('names no leg (--blind starts from the map as it is)')
    return damage


def build_parser() -> argparse.ArgumentParser:
    """Return the command-line options of ``adapt_client``."""
    ap = argparse.ArgumentParser(
        prog='adapt_client', description='Run one adaptation and print its trials.'
    )
    _mboa_options(ap)
    _damage_options(ap)
    ap.add_argument('--action', default='adapt', help='name of the adapt action')
    ap.add_argument(
        '--timeout',
        type=number(float, 0, 10**6, low_open=True),
        default=3600.0,
        help='give up after this many seconds, waiting for the action server included',
    )
    return ap


def _mboa_options(ap: argparse.ArgumentParser) -> None:
    """Add the run's M-BOA settings (0: the node's parameter)."""
    ap.add_argument(
        '--max-trials',
        type=_default_or(1, MAX_TRIALS_LIMIT, int),
        default=0,
        help=f"stop after this many trials, 1..{MAX_TRIALS_LIMIT} (0 = the node's default)",
    )
    ap.add_argument(
        '--trial-duration',
        type=_default_or(*TRIAL_DURATION_RANGE),
        default=0.0,
        help="seconds per trial (0 = the node's default)",
    )
    ap.add_argument(
        '--alpha',
        type=_default_or(*ALPHA_RANGE),
        default=0.0,
        help="stop ratio in [0.05, 1] (0 = the node's default)",
    )
    ap.add_argument(
        '--kappa',
        type=_default_or(*KAPPA_RANGE),
        default=0.0,
        help='UCB weight on the posterior std (0 = default)',
    )
    ap.add_argument(
        '--length-scale',
        type=_default_or(*LENGTH_SCALE_RANGE),
        default=0.0,
        help='Matern length scale rho (0 = default)',
    )
    ap.add_argument(
        '--noise',
        type=_default_or(*NOISE_RANGE),
        default=0.0,
        help='GP noise variance [(m/s)^2] (0 = default)',
    )
    gain = ap.add_mutually_exclusive_group()
    gain.add_argument(
        '--stop-gain',
        type=_default_or(*STOP_GAIN_RANGE),
        default=0.0,
        help="blind runs: success also needs the next trial's expected gain below this [m/s] (0 ="
        " the node's default: 0.002 in the default profile)",
    )
    gain.add_argument(
        '--no-gain-stop',
        action='store_true',
        help='no expected-gain stop: a blind run ends on alpha or max_trials alone',
    )
    ap.add_argument(
        '--profile',
        choices=sorted(PROFILES),
        default='',
        help="M-BOA settings (default: the node's profile parameter)",
    )


def _damage_options(ap: argparse.ArgumentParser) -> None:
    """Add what the run knows of the damage."""
    named = ap.add_mutually_exclusive_group()
    named.add_argument(
        '--failed-legs',
        type=number(int, 1, 6),
        nargs='+',
        default=[],
        help='legs known to have failed, lifted: the map is re-scored under them first (default:'
        ' what the node knows from the simulator or the servo reports)',
    )
    named.add_argument(
        '--damage',
        type=_damage,
        default=None,
        metavar='LEG:KIND[:AMOUNT],...',
        help='the damage known, of any kind, e.g. 3:unpowered:femur, 2:locked,5:weak:0.3 or'
        ' 4:shortened:0.5: the map is re-scored under it first',
    )
    ap.add_argument(
        '--blind', action='store_true', help='ignore known damage: start from the map as it is'
    )


def main(argv: list[str] | None = None) -> int:
    """Parse the options, send one adapt goal, print each trial; exit status 0 on success."""
    args, ros_args = build_parser().parse_known_args(argv)
    return run_command('adapt_client', lambda: _call(args, ros_args))


def trial_line(m: AdaptationTrial, trials_left: int) -> str:
    """Return the line printed for one trial's feedback."""
    return (
        f'trial {m.trial:>3d}: gait {m.archive_index:>6d}  '
        + ('TIPPED: stopped by the tip guard, scored' if m.tipped else 'measured')
        + f' {m.measured_speed:+.3f} m/s  (map {m.map_speed:.3f}, GP'
        f' {m.predicted_speed:.3f} +/- {m.predicted_speed_std:.3f})'
        f'  best {m.best_speed:+.3f} m/s  ({trials_left} left at most)'
    )


def feedback_line(f: Adapt.Feedback) -> str:
    """Return the line printed for one feedback: a trial's, or what the run tells its operator."""
    if f.note:
        return f'note: {f.note}'
    return trial_line(f.trial, f.trials_left)


def _goal(args: argparse.Namespace) -> Adapt.Goal:
    legs, kinds, strengths, joints = (
        args.damage.as_lists() if args.damage else (args.failed_legs, [], [], [])
    )
    return Adapt.Goal(
        max_trials=args.max_trials,
        trial_duration=args.trial_duration,
        alpha=args.alpha,
        kappa=args.kappa,
        length_scale=args.length_scale,
        noise=args.noise,
        stop_gain=args.stop_gain,
        no_gain_stop=args.no_gain_stop,
        profile=args.profile,
        failed_legs=legs,
        kinds=kinds,
        strengths=strengths,
        joints=joints,
        blind=args.blind,
    )


def _say(text: str) -> None:
    print(f'adapt_client: {text}', file=sys.stderr, flush=True)


def _call(args: argparse.Namespace, ros_args: list[str]) -> int:
    deadline = time.monotonic() + args.timeout
    # Python's own handlers: Ctrl-C and SIGTERM stop the client the same way (run_command)
    rclpy.init(args=ros_args, signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node('adapt_client')
    try:
        client = ActionClient(
            node, Adapt, args.action,
            **ACTION_QOS,
        )  # fmt: skip
        if not client.wait_for_server(timeout_sec=max(0.0, deadline - time.monotonic())):
            _say(
                f'action {args.action} not available within {args.timeout:g} s'
                ' (is adapt_node running?)'
            )
            return 1
        sent = client.send_goal_async(
            _goal(args), feedback_callback=lambda f: print(feedback_line(f.feedback), flush=True)
        )
        outcome = _wait(node, client, sent, deadline, args)
        if outcome is not None:
            return outcome
        handle = sent.result()
        if not handle.accepted:
            _say(BUSY)
            return 1
        answer = handle.get_result_async()
        try:
            outcome = _wait(node, client, answer, deadline, args)
        except KeyboardInterrupt:  # Ctrl-C or SIGTERM: the run stops too
            acknowledge_stop()
            _cancel(node, handle, deadline)
            raise
        if outcome is not None:
            return outcome
        return _report(answer.result().status, answer.result().result)
    finally:
        node.destroy_node()
        guarded_logging.shutdown()


def _wait(node, client: ActionClient, future, deadline: float, args) -> int | None:
    """Spin until ``future`` is done (None) or return the exit status of why it is not."""
    waited = spin_until_done(node, future, deadline, client.server_is_ready)
    if waited is Waited.SERVER_GONE:
        _say(
            f'the server of {args.action} shut down before it answered (adapt_node stopped'
            ' mid-run; its recording holds the trials it completed)'
        )
        return 1
    if waited is Waited.TIMEOUT:
        _say(f'no answer within {args.timeout:g} s')
        return 1
    return None


def _cancel(node, handle, deadline: float) -> None:
    """Ask adapt_node to cancel the goal, waiting at most 2 s for its answer."""
    future = handle.cancel_goal_async()
    end = min(deadline, time.monotonic() + 2.0)
    while not future.done() and time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=0.1)
    accepted = future.done() and len(future.result().goals_canceling) > 0
    _say(
        'cancel sent: adapt_node stops the run (a trial being walked is not scored)'
        if accepted
        else 'the cancel was not confirmed: the run may go on in adapt_node'
    )


def _report(status: int, r: Adapt.Result) -> int:
    """Print the result; return the exit status (0: M-BOA's rule met)."""
    # the message says what happened (a gait found, the budget used, why it stopped)
    word = {GoalStatus.STATUS_SUCCEEDED: 'done', GoalStatus.STATUS_CANCELED: 'cancelled'}
    print(f'{word.get(status, "stopped")}: {r.message}')
    if r.best_archive_index >= 0:
        print(
            f'best gait {r.best_archive_index}: {r.best_speed:.3f} m/s after {r.trials}'
            f' trial{"" if r.trials == 1 else "s"}'
            f' ({r.elapsed:.1f} s)'
        )
    if r.prior:
        print(f'prior: {r.prior}')
    if r.mcap_path:
        print(f'recording: {r.mcap_path}')
    return 0 if r.success else 3


if __name__ == '__main__':
    sys.exit(main())
