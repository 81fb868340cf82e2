# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
"""
``ros2 run hexapod_adapt adapt_client``.

Call the ``adapt`` service from a base-station PC and print each trial as it completes (the same as
``ros2 service call /adapt hexapod_msgs/srv/Adapt`` plus ``ros2 topic echo /adapt/trials`` on a
full ROS install).

    adapt_client --max-trials 20 [--alpha 0.9 --kappa 0.05 --length-scale 0.4 --noise 0.001]
"""

from __future__ import annotations

import argparse
import math
import sys
import time

from hexapod_adapt.mboa import MAX_TRIALS_LIMIT
from hexapod_msgs.msg import AdaptationTrial
from hexapod_msgs.srv import Adapt
import rclpy


def main(argv: list[str] | None = None) -> int:
    """Parse the options, call the adapt service, print each trial; exit status 0 on success."""
    ap = argparse.ArgumentParser(
        prog='adapt_client', description='Run one adaptation and print its trials.'
    )
    ap.add_argument(
        '--max-trials',
        type=int,
        default=0,
        help=f"stop after this many trials, 1..{MAX_TRIALS_LIMIT} (0 = the node's default)",
    )
    ap.add_argument(
        '--trial-duration',
        type=float,
        default=0.0,
        help="seconds per trial (0 = the node's default)",
    )
    ap.add_argument(
        '--alpha', type=float, default=0.0, help="stop ratio in [0.05, 1] (0 = the node's default)"
    )
    ap.add_argument(
        '--kappa', type=float, default=0.0, help='UCB weight on the posterior std (0 = default)'
    )
    ap.add_argument(
        '--length-scale', type=float, default=0.0, help='Matern length scale rho (0 = default)'
    )
    ap.add_argument(
        '--noise', type=float, default=0.0, help='GP noise variance [(m/s)^2] (0 = default)'
    )
    ap.add_argument('--service', default='adapt', help='name of the adapt service')
    ap.add_argument(
        '--timeout',
        type=float,
        default=3600.0,
        help='give up after this many seconds, waiting for the service included',
    )
    args, ros_args = ap.parse_known_args(argv)
    if not 0 <= args.max_trials <= MAX_TRIALS_LIMIT:
        print(
            f"adapt_client: --max-trials must be in [0, {MAX_TRIALS_LIMIT}] (0 = the node's"
            f' default), got {args.max_trials}',
            file=sys.stderr,
        )
        return 2
    if not (math.isfinite(args.timeout) and args.timeout > 0):
        print(f'adapt_client: --timeout must be > 0 s, got {args.timeout}', file=sys.stderr)
        return 2
    deadline = time.monotonic() + args.timeout
    rclpy.init(args=ros_args)
    node = rclpy.create_node('adapt_client')
    try:
        node.create_subscription(
            AdaptationTrial,
            'adapt/trials',
            lambda m: print(
                f'trial {m.trial:>3d}: gait {m.archive_index:>6d}  measured'
                f' {m.measured_speed:+.3f} m/s  (map {m.map_speed:.3f}, GP {m.predicted_speed:.3f}'
                f' +/- {m.predicted_speed_std:.3f})  best {m.best_speed:+.3f} m/s',
                flush=True,
            ),
            10,
        )
        client = node.create_client(Adapt, args.service)
        if not client.wait_for_service(timeout_sec=max(0.0, deadline - time.monotonic())):
            print(
                f'adapt_client: service {args.service} not available within {args.timeout:g} s '
                '(is adapt_node running?)',
                file=sys.stderr,
            )
            return 1
        request = Adapt.Request(
            max_trials=args.max_trials,
            trial_duration=args.trial_duration,
            alpha=args.alpha,
            kappa=args.kappa,
            length_scale=args.length_scale,
            noise=args.noise,
        )
        future = client.call_async(request)
        while not future.done() and time.monotonic() < deadline:
            rclpy.spin_once(node, timeout_sec=0.1)
        if not future.done():
            print(f'adapt_client: no answer within {args.timeout:g} s', file=sys.stderr)
            return 1
        for _ in range(5):  # let the last trial message arrive
            rclpy.spin_once(node, timeout_sec=0.05)
        r = future.result()
        print(f'{"success" if r.success else "stopped"}: {r.message}')
        if r.best_archive_index >= 0:
            print(
                f'best gait {r.best_archive_index}: {r.best_speed:.3f} m/s after {r.trials} trials'
                f' ({r.elapsed:.1f} s)'
            )
        if r.mcap_path:
            print(f'recording: {r.mcap_path}')
        return 0 if r.success else 3
    except KeyboardInterrupt:
        return 130
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    sys.exit(main())
